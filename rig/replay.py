"""Replay drives on the virtual rig: records in, response records out (DESIGN.md channels, SI).

A record with ``<corner>/drive`` channels is played through the post servo model; one with only
``<corner>/actuator_disp`` channels moves the posts exactly as measured (ideal posts, for model
validation). The car starts at static ride height. Limits are checked before and after the run.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import mujoco
import numpy as np

from rig.channels import RESPONSE_QUANTITIES, channel
from rig.drive_limits import DriveLimitError, LimitHit, achieved_hits, check_drive, check_start
from rig.model import build_model
from rig.record import Record, RecordError
from rig.sensors import apply_sensor_model
from rig.simulate import Simulator, run_batch
from rig.vehicle import Vehicle

#: Input quantity of a record and the post model that plays it.
INPUT_MODES = {"drive": "servo", "actuator_disp": "ideal"}


@dataclass
class ReplayResult:
    record: Record              # responses at the drive's sample times, SI
    limit_hits: list[LimitHit]  # limits reached (only non-empty when clipping was allowed)
    qpos: np.ndarray | None = None       # joint positions at the sample times (samples x nq)
    model: mujoco.MjModel | None = None  # the compiled model they belong to (for animation)

    def airborne_time(self) -> dict[str, float]:
        """Time in s each tyre spent off the ground (zero tyre force), per corner."""
        return {c: float(np.sum(self.record[channel(c, "tyre_force")] <= 0.0) / self.record.rate)
                for c in self.record.corners_with("tyre_force")}


def input_quantity(record: Record, corners: tuple[str, ...]) -> str:
    """'drive' if the record drives every corner, else 'actuator_disp' if it has measured post motion."""
    for quantity in INPUT_MODES:
        if all(channel(c, quantity) in record for c in corners):
            return quantity
    wanted = " or ".join(", ".join(channel(c, q) for c in corners) for q in INPUT_MODES)
    have = [q for q in INPUT_MODES if record.corners_with(q)]
    missing = [channel(c, q) for q in have for c in corners if channel(c, q) not in record] if have else []
    raise RecordError(f"record has no complete set of post inputs: needs {wanted}"
                      + (f"; missing {', '.join(missing)}" if missing else ""))


def replay(vehicle: Vehicle, drive: Record, clip: bool = False, nthread: int | None = None,
           limits: bool = True, interpolation: str = "cubic") -> ReplayResult:
    """Replay one drive record on ``vehicle``; see ``replay_batch``."""
    return replay_batch(vehicle, [drive], clip, nthread, limits, interpolation)[0]


def replay_batch(vehicles: Vehicle | Sequence[Vehicle], drives: Sequence[Record], clip: bool = False,
                 nthread: int | None = None, limits: bool = True, interpolation: str = "cubic") -> list[ReplayResult]:
    """Replay several drives (same rate, length and input quantity) in one threaded rollout.

    ``vehicles`` is one vehicle for all drives, or one per drive (variants of one layout). Drives beyond
    the post stroke or velocity are refused (DriveLimitError), or clipped and reported with ``clip``;
    so is a run that saturates the post force. ``limits=False`` skips the post limits (a road under
    ideal posts, for track runs); a drive must still start at zero. ``interpolation`` ('cubic' or
    'linear') is how the input runs between samples (rig/simulate.py).
    """
    if isinstance(vehicles, Vehicle):
        vehicles = [vehicles]
    if len(vehicles) not in (1, len(drives)):
        raise ValueError(f"need one vehicle or one per drive, got {len(vehicles)} for {len(drives)} drives")
    if len({v.layout for v in vehicles}) > 1:
        raise ValueError("vehicles in one batch must share a layout (all full cars or all quarter cars)")
    corners = vehicles[0].corners
    first = drives[0]
    quantity = input_quantity(first, corners)
    for d in drives[1:]:
        if d.rate != first.rate or d.n_samples != first.n_samples or input_quantity(d, corners) != quantity:
            raise ValueError("drives in one batch must share sample rate, length and input quantity")
    posts = INPUT_MODES[quantity]
    sims = [Simulator.create(build_model(v, first.rate, posts)) for v in vehicles]  # one per distinct vehicle
    per_drive = list(zip(vehicles, sims)) if len(vehicles) > 1 else [(vehicles[0], sims[0])] * len(drives)
    inputs, hits = [], []
    for d, (vehicle, _) in zip(drives, per_drive):
        values = d.quantity(quantity, corners)
        if limits:
            values, found = check_drive(values, d.rate, vehicle.rig, corners, d.time, clip)
        else:
            check_start(values, corners)
            found = []
        inputs.append(values)
        hits.append(found)
    responses = run_batch(sims, np.stack(inputs), nthread, interpolation)
    results = []
    for i, (d, (vehicle, sim)) in enumerate(zip(drives, per_drive)):
        if limits:
            displacement = responses["actuator_disp"][i] if posts == "servo" else None
            found = hits[i] + achieved_hits(vehicle.rig, corners, responses["actuator_force"][i], displacement, d.time)
        else:
            found = []
        if found and not clip:
            raise DriveLimitError("the run reached the post limits (use clip to accept and report): "
                                  + "; ".join(h.describe() for h in found))
        channels = {}
        for c_index, corner in enumerate(corners):
            if posts == "servo":
                channels[channel(corner, "drive")] = inputs[i][:, c_index]
            for q in RESPONSE_QUANTITIES:
                channels[channel(corner, q)] = responses[q][i, :, c_index]
        channels = apply_sensor_model(channels, vehicle.extensions, d.rate)
        metadata = {"vehicle": vehicle.name, "test": "rig", "posts": posts}
        results.append(ReplayResult(Record(d.rate, channels, metadata=metadata, start_time=d.start_time), found,
                                    responses["qpos"][i], sim.rig.model))
    return results
