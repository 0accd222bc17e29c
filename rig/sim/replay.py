"""Replay drives on the virtual rig: records in, response records out (channels and SI units: docs/contracts.md).

A record with ``<corner>/drive`` channels is played through the post servo model; one with only
``<corner>/actuator_disp`` channels moves the posts exactly as measured (ideal posts, for model
validation). A record's ``<corner>/active_force`` channels (any corners) are applied beside the posts by the force
actuators between body and wheel (rig/vehicle/mjcf.py), as their change from the first sample: the car starts at
rest at static ride height, which the first sample's force is part of (a load cell's zero offset with it). The car
starts at static ride height. Limits are checked before and after the run.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import mujoco
import numpy as np

from rig.io.channels import RESPONSE_QUANTITIES, channel
from rig.io.record import Record, RecordError
from rig.sim.drive_limits import DriveLimitError, LimitHit, achieved_hits, check_drive, check_start
from rig.sim.measurement import apply_sensor_model, true_inputs
from rig.sim.simulate import VEHICLE_CHANNELS, Simulator, run_batch
from rig.vehicle.mjcf import MAX_TIMESTEP, build_model
from rig.vehicle.vehicle_file import Vehicle

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


def active_forces(record: Record, corners: tuple[str, ...]) -> np.ndarray | None:
    """The record's ``active_force`` channels (samples x corners, N) from their first sample, 0 at corners without
    one; None when it has none."""
    if not any(channel(c, "active_force") in record for c in corners):
        return None
    names = [channel(c, "active_force") for c in corners]
    return np.column_stack([record[n] - record[n][0] if n in record else np.zeros(record.n_samples) for n in names])


def replay(vehicle: Vehicle, drive: Record, clip: bool = False, nthread: int | None = None,
           limits: bool = True, interpolation: str = "cubic") -> ReplayResult:
    """Replay one drive record on ``vehicle``; see ``replay_batch``."""
    return replay_batch(vehicle, [drive], clip, nthread, limits, interpolation)[0]


def replay_batch(vehicles: Vehicle | Sequence[Vehicle], drives: Sequence[Record], clip: bool = False,
                 nthread: int | None = None, limits: bool = True, interpolation: str = "cubic",
                 wheel_angles: np.ndarray | None = None, longest: float = MAX_TIMESTEP,
                 qpos: bool = True) -> list[ReplayResult]:
    """Replay several drives (same rate, length and input quantity) in one threaded rollout.

    ``vehicles`` is one vehicle for all drives, or one per drive (variants of one layout). Drives beyond
    the post stroke or velocity are refused (DriveLimitError), or clipped and reported with ``clip``;
    so is a run that saturates the post force. ``limits=False`` skips the post limits (a road under
    ideal posts, for track runs); a drive must still start at zero. ``interpolation`` ('cubic' or
    'linear') is how the input runs between samples (rig/sim/simulate.py). ``wheel_angles`` (drives x samples x
    corners, rad) turn the wheels that can turn (a track run: rig/sim/track.py). ``longest``: the longest physics
    step asked (s; rig/vehicle/mjcf.py ``longest_step``). A drive's input channels are first brought back to the
    motion they record by each vehicle's causes keyed by channel (rig/sim/measurement.py ``true_inputs``).
    ``qpos=False``: the results hold no joint positions (nothing to animate; the rollout then keeps no states).
    """
    each = [vehicles] if isinstance(vehicles, Vehicle) else list(vehicles)
    drives = [true_inputs(d, v.extensions) for d, v in zip(drives, each * len(drives) if len(each) == 1 else each)]
    first = drives[0]
    corners = each[0].corners
    quantity = input_quantity(first, corners)
    forces = [active_forces(d, corners) for d in drives]
    for d, f in zip(drives[1:], forces[1:]):
        if d.rate != first.rate or d.n_samples != first.n_samples or input_quantity(d, corners) != quantity:
            raise ValueError("drives in one batch must share sample rate, length and input quantity")
        if (f is None) != (forces[0] is None):
            raise ValueError("drives in one batch must all carry active_force channels or none")
    player = Replayer(vehicles, first.rate, INPUT_MODES[quantity], nthread, interpolation, longest=longest)
    return player.play(np.stack([d.quantity(quantity, corners) for d in drives]), clip, limits,
                       [d.start_time for d in drives], wheel_angles=wheel_angles,
                       forces=None if forces[0] is None else np.stack(forces), qpos=qpos)


class Replayer:
    """Settled models of one or several vehicles (variants of one layout) that play post inputs at ``rate``
    Hz: drives through the servo model (``posts='servo'``) or post (road) heights (``'ideal'``).

    Each play returns contract records through the measurement chain (rig/sim/measurement.py): the one
    simulation path of replays, track runs, drive iteration and validation. ``extend(spec)`` adds elements to each
    assembled model before it is compiled and ``longest`` is the longest physics step asked (rig/vehicle/mjcf.py
    ``build_model``).
    """

    def __init__(self, vehicles: Vehicle | Sequence[Vehicle], rate: float, posts: str = "servo",
                 nthread: int | None = None, interpolation: str = "cubic",
                 extend: Callable[[mujoco.MjSpec], None] | None = None, longest: float = MAX_TIMESTEP):
        self.vehicles = [vehicles] if isinstance(vehicles, Vehicle) else list(vehicles)
        if len({v.layout for v in self.vehicles}) > 1:
            raise ValueError("vehicles in one batch must share a layout (all full cars or all quarter cars)")
        self.rate, self.posts, self.nthread, self.interpolation = rate, posts, nthread, interpolation
        self.corners = self.vehicles[0].corners
        self.simulators = [Simulator.create(build_model(v, rate, posts, extend, longest)) for v in self.vehicles]
        if len({s.rig.steps_per_sample for s in self.simulators}) > 1:
            raise ValueError("vehicles in one batch must share a physics step (the same causes sized to it)")

    def play(self, inputs: np.ndarray, clip: bool = False, limits: bool = True,
             start_time: float | Sequence[float] = 0.0, projected: bool = False,
             wheel_angles: np.ndarray | None = None, forces: np.ndarray | None = None,
             qpos: bool = True) -> list[ReplayResult]:
        """Play inputs (batch, samples, corners) in m: one per vehicle, or all on the one vehicle.

        Limits as ``replay_batch``; ``projected``: the caller has already projected the inputs onto the
        post stroke and velocity (a drive tuner), so only what the run reaches is checked. ``start_time``
        (s, one or one per run) is the records' first sample time. ``wheel_angles`` (runs x samples x corners,
        rad) turn the wheels that can turn (rig/sim/simulate.py). ``forces`` (runs x samples x corners, N, from 0)
        are the actuator forces between body and wheel, written to the records as ``<corner>/active_force``.
        ``qpos=False``: no joint positions in the results (``replay_batch``).
        """
        inputs = np.asarray(inputs, float)
        if len(self.vehicles) not in (1, inputs.shape[0]):
            raise ValueError(f"need one vehicle or one per drive, got {len(self.vehicles)} for "
                             f"{inputs.shape[0]} drives")
        per_run = list(zip(self.vehicles, self.simulators))
        if len(per_run) == 1:
            per_run *= inputs.shape[0]
        starts = np.broadcast_to(np.asarray(start_time, float), inputs.shape[:1])
        times = starts[:, None] + np.arange(inputs.shape[1]) / self.rate
        checked, hits = [], []
        for values, (vehicle, _), time in zip(inputs, per_run, times):
            found = []
            if limits and not projected:
                values, found = check_drive(values, self.rate, vehicle.rig, self.corners, time, clip)
            elif not projected:
                check_start(values, self.corners)
            checked.append(values)
            hits.append(found)
        responses = run_batch([s for _, s in per_run] if len(self.simulators) > 1 else self.simulators,
                              np.stack(checked), self.nthread, self.interpolation, wheel_angles, forces, qpos)
        results = []
        for i, ((vehicle, sim), time) in enumerate(zip(per_run, times)):
            found = hits[i]
            if limits:
                displacement = responses["actuator_disp"][i] if self.posts == "servo" else None
                found = found + achieved_hits(vehicle.rig, self.corners, responses["actuator_force"][i],
                                              displacement, time)
            if found and not clip:
                raise DriveLimitError("the run reached the post limits (use clip to accept and report): "
                                      + "; ".join(h.describe() for h in found))
            channels = {}
            for c_index, corner in enumerate(self.corners):
                if self.posts == "servo":
                    channels[channel(corner, "drive")] = checked[i][:, c_index]
                if forces is not None:
                    channels[channel(corner, "active_force")] = np.asarray(forces, float)[i, :, c_index]
                for q in RESPONSE_QUANTITIES:
                    channels[channel(corner, q)] = responses[q][i, :, c_index]
            channels.update({name: responses[q][i, :, 0] for q, name in VEHICLE_CHANNELS.items() if q in responses})
            channels = apply_sensor_model(channels, vehicle.extensions, self.rate)
            metadata = {"vehicle": vehicle.name, "test": "rig", "posts": self.posts}
            results.append(ReplayResult(Record(self.rate, channels, metadata=metadata, start_time=float(time[0])),
                                        found, None if responses["qpos"] is None else responses["qpos"][i],
                                        sim.rig.model))
        return results
