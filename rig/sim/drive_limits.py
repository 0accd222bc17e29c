"""Post limits (stroke, velocity, force): check a drive before it is played, clip it only when asked.

A drive beyond the rig's limits is refused with a message that names the corner, the limit, the time
and the peak; with ``clip=True`` it is clipped and every clipped corner is reported. Nothing is ever
clipped silently.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rig.errors import RigError
from rig.vehicle.rig_config import RigConfig

START_TOLERANCE = 5e-4  # m: a drive must start within this of zero (the car is settled with posts at 0)


class DriveLimitError(RigError):
    """A drive (or achieved post motion) outside the rig's limits."""


@dataclass(frozen=True)
class LimitHit:
    """One corner's excursion beyond one limit."""

    corner: str
    limit: str          # 'stroke' | 'velocity' | 'force'
    peak: float         # largest magnitude reached (m, m/s, N)
    allowed: float      # the limit (same unit)
    first_time: float   # s, first sample beyond the limit
    samples: int        # number of samples beyond the limit

    def describe(self) -> str:
        unit = {"stroke": "m", "velocity": "m/s", "force": "N"}[self.limit]
        verb = "exceeded" if self.peak > self.allowed * (1 + 1e-6) else "reached"
        return (f"{self.corner}: {self.limit} limit ±{self.allowed:.4g} {unit} {verb}, peak {self.peak:.4g} {unit} "
                f"from t = {self.first_time:.4g} s ({self.samples} samples)")


def find_hits(values: np.ndarray, allowed: float, limit: str, corners: tuple[str, ...],
              time: np.ndarray) -> list[LimitHit]:
    """Hits of |values| > allowed per corner; ``values`` is samples x corners."""
    hits = []
    for i, corner in enumerate(corners):
        over = np.flatnonzero(np.abs(values[:, i]) > allowed)
        if over.size:
            hits.append(LimitHit(corner, limit, float(np.max(np.abs(values[:, i]))), allowed,
                                 float(time[over[0]]), int(over.size)))
    return hits


def achieved_hits(rig: RigConfig, corners: tuple[str, ...], force: np.ndarray, displacement: np.ndarray | None,
                  time: np.ndarray) -> list[LimitHit]:
    """Limits reached during a run (samples x corners): post force, and stroke when the posts are simulated.

    The servo's force is clamped at the rating inside MuJoCo, so reaching it means saturation; with
    ideal posts (``displacement`` None) the force is computed and may exceed it.
    """
    allowed = rig.force_limit * (1 - 1e-9) if displacement is not None else rig.force_limit
    hits = find_hits(force, allowed, "force", corners, time)
    if displacement is not None:
        hits += find_hits(displacement, rig.stroke, "stroke", corners, time)
    return hits


def post_velocity(displacement: np.ndarray, rate: float) -> np.ndarray:
    """Post velocity in m/s between samples (samples x corners), first sample repeated."""
    velocity = np.diff(displacement, axis=0, prepend=displacement[:1]) * rate
    return velocity


def check_start(drive: np.ndarray, corners: tuple[str, ...]) -> None:
    """A drive (samples x corners, m) must start at zero: the car is settled there before the run."""
    starts = [f"{c} starts at {drive[0, i] * 1e3:.2f} mm" for i, c in enumerate(corners)
              if abs(drive[0, i]) > START_TOLERANCE]
    if starts:
        raise DriveLimitError(
            "drive must start at 0 m, where the car is settled to static ride height: " + "; ".join(starts)
            + " (remove the offset or add a ramp-in)"
        )


def check_drive(drive: np.ndarray, rate: float, rig: RigConfig, corners: tuple[str, ...], time: np.ndarray,
                clip: bool = False) -> tuple[np.ndarray, list[LimitHit]]:
    """Check the start, stroke and velocity of a drive (samples x corners, m).

    Returns the drive (clipped when ``clip``) and the hits found. Without ``clip``, any hit raises
    DriveLimitError listing them all.
    """
    check_start(drive, corners)
    hits = find_hits(drive, rig.stroke, "stroke", corners, time)
    hits += find_hits(post_velocity(drive, rate), rig.velocity_limit, "velocity", corners, time)
    if hits and not clip:
        raise DriveLimitError("drive exceeds the post limits (use clip to clip and report): "
                              + "; ".join(h.describe() for h in hits))
    if hits:
        drive = rate_limit(np.clip(drive, -rig.stroke, rig.stroke), rig.velocity_limit / rate)
    return drive, hits


def on_limits(drive: np.ndarray, rate: float, rig: RigConfig) -> np.ndarray:
    """Samples (samples x corners) where a clipped drive sits on the post stroke or velocity limit: where
    ``check_drive(clip=True)`` changed it. A velocity-limited stretch counts from the sample its step was cut."""
    stroke = np.abs(drive) >= rig.stroke * (1 - 1e-9)
    velocity = np.abs(post_velocity(drive, rate)) >= rig.velocity_limit * (1 - 1e-9)
    return stroke | velocity


def rate_limit(signal: np.ndarray, max_step: float) -> np.ndarray:
    """Limit the change between samples to ``max_step`` (samples x corners), tracking the signal otherwise."""
    out = signal.copy()
    for k in range(1, out.shape[0]):
        out[k] = out[k - 1] + np.clip(signal[k] - out[k - 1], -max_step, max_step)
    return out
