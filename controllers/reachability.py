"""What a target asks beyond the model: where the drive has no hold on a channel, what the rig and car cannot
give, and the error reached on the rest of the record.

- lift-off: the tyre only pushes, so a wheel can fall no faster than its suspension pushes it down,
  a_wheel >= -(F_susp + m_t g) / m_t, with equality exactly while the tyre is off its post. There the post cannot
  move the wheel: where the target's wheel falls faster than the airborne wheel does, no drive reproduces it.
- stroke and velocity: the drive the iteration asked for before it was projected onto the post's limits
  (rig/sim/drive_limits.py), against the limit;
- force: the servo's force at its rating (clamped inside the simulation).

Each demand is an ``Unreachable`` (what, where, how much against how much, for how long in total). The rest of the
record is every sample of a channel outside the samples its corner was airborne, on a limit or at the force rating,
widened by ``SETTLE`` on each side.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np
from scipy.ndimage import binary_dilation

from rig.io.channels import channel, split_channel
from rig.io.record import Record
from rig.sim.drive_limits import LimitHit
from rig.vehicle.rig_config import RigConfig

G = 9.80665
#: s on each side of a sample without hold that the rest of the record leaves out: the servo's delay and lag
#: (2 ms and 3 ms in the default rig) and a sample of the target's own filtering
SETTLE = 0.008
KINDS = ("lift-off", "stroke", "velocity", "force")


@dataclass(frozen=True)
class Unreachable:
    """A demand of the target the model cannot meet: ``demanded`` against ``available`` (``unit``), for
    ``duration`` s in total. Lift-off: the wheel's downward acceleration (m/s^2), both the largest over the samples
    where the target's wheel falls faster than the airborne one; ``demanded`` is None where the corner's wheel is not
    iterated (the body above it then has no hold)."""

    kind: str
    corner: str
    demanded: float | None
    available: float
    unit: str
    duration: float

    def describe(self) -> str:
        if self.kind == "lift-off":
            if self.demanded is None:
                return (f"{self.corner}: the tyre leaves the post for {self.duration:.2g} s in total, where the drive "
                        f"has no hold on the corner")
            return (f"{self.corner}: the target's wheel falls at up to {self.demanded:.3g} m/s^2 "
                    f"({self.demanded / G:.2g} g) where the airborne wheel then falls at {self.available:.3g} "
                    f"m/s^2 ({self.available / G:.2g} g) at most (the tyre off its post, the suspension's push "
                    f"alone), for {self.duration:.2g} s in total")
        if self.kind == "force":
            return (f"{self.corner}: the post force reaches its {self.available / 1e3:.3g} kN rating for "
                    f"{self.duration:.2g} s in total")
        if self.kind == "stroke":
            return (f"{self.corner} needs {self.demanded * 1e3:.3g} mm of stroke where the post gives "
                    f"±{self.available * 1e3:.3g} mm, for {self.duration:.2g} s in total")
        return (f"{self.corner} needs {self.demanded:.3g} m/s where the post gives {self.available:.3g} m/s, "
                f"for {self.duration:.2g} s in total")

    def to_json(self) -> dict:
        return asdict(self)


def airborne(record: Record, corners: tuple[str, ...]) -> np.ndarray:
    """Samples x corners: True where the tyre is off its post (zero tyre force)."""
    return np.column_stack([record[channel(c, "tyre_force")] <= 0.0 for c in corners])


def at_force_rating(record: Record, corners: tuple[str, ...], rig: RigConfig) -> np.ndarray:
    """Samples x corners: True where the post's servo force is at its rating."""
    return np.column_stack([np.abs(record[channel(c, "actuator_force")]) >= rig.force_limit * (1 - 1e-9)
                            for c in corners])


def per_channel(by_corner: np.ndarray, corners: tuple[str, ...], channels: list[str]) -> np.ndarray:
    """Samples x channels: each channel takes its corner's column."""
    return by_corner[:, [corners.index(split_channel(name)[0]) for name in channels]]


def widened(mask: np.ndarray, rate: float, seconds: float = SETTLE) -> np.ndarray:
    """``mask`` (samples x columns) widened by ``seconds`` on each side."""
    half = int(round(seconds * rate))
    if half == 0 or not mask.any():
        return mask
    return binary_dilation(mask, np.ones((2 * half + 1, 1), bool))


def lift_off_demands(target: np.ndarray, response: np.ndarray, airborne_by_corner: np.ndarray, channels: list[str],
                     corners: tuple[str, ...], rate: float, margin: np.ndarray) -> list[Unreachable]:
    """Per corner that left its post: where the target's wheel (band-passed, samples x channels, m/s^2) falls faster
    than the airborne wheel by more than the channel's ``margin`` (m/s^2, per channel); without an iterated wheel
    channel, the time airborne."""
    found = []
    for i, corner in enumerate(corners):
        off = airborne_by_corner[:, i]
        if not off.any():
            continue
        wheel = channel(corner, "unsprung_acc")
        if wheel not in channels:
            if any(split_channel(name)[0] == corner for name in channels):
                found.append(Unreachable("lift-off", corner, None, 0.0, "m/s^2", float(off.sum() / rate)))
            continue
        j = channels.index(wheel)
        faster = off & (target[:, j] < response[:, j] - margin[j])
        if faster.any():
            found.append(Unreachable("lift-off", corner, float(-target[faster, j].min()),
                                     float(-response[faster, j].min()), "m/s^2", float(faster.sum() / rate)))
    return found


def limit_demands(asked: list[LimitHit], reached: list[LimitHit], rate: float) -> list[Unreachable]:
    """Stroke and velocity ``asked`` of a drive before its projection, and the limits a run ``reached`` (force
    ratings; the stroke's end where the drive asked for no more stroke), as demands."""
    units = {"stroke": "m", "velocity": "m/s", "force": "N"}
    asked_for = {(h.corner, h.limit) for h in asked}
    hits = asked + [h for h in reached if (h.corner, h.limit) not in asked_for]
    return [Unreachable(h.limit, h.corner, None if h.limit == "force" else h.peak, h.allowed, units[h.limit],
                        h.samples / rate) for h in hits]


def rest_error(target: np.ndarray, response: np.ndarray, without_hold: np.ndarray) -> tuple[dict[int, float], float]:
    """RMS error (%) of each channel over the samples with hold, of the target's RMS there; and their share of
    the samples. Arrays are samples x channels over the target's span."""
    keep = ~without_hold
    errors = {}
    for j in range(target.shape[1]):
        reference = np.sum(target[keep[:, j], j] ** 2)
        errors[j] = float(100 * np.sqrt(np.sum((target - response)[keep[:, j], j] ** 2) / reference)) \
            if reference > 0 else 0.0
    return errors, float(keep.mean())
