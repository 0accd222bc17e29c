"""The plant a drive tuner works on: a vehicle on the servo-post rig, post drives in, chosen channels out.

A thin view of ``Replayer`` (rig/sim/replay.py): the same simulation path and measurement chain as a
replay, with the drive limits projected by the tuner and every hit reported.
"""

from __future__ import annotations

import numpy as np

from rig.io.channels import split_channel
from rig.sim.replay import Replayer, ReplayResult
from rig.vehicle.vehicle_file import Vehicle


class VirtualRig:
    """Plays drives (samples x corners, m) at ``rate`` Hz and returns the ``channels`` (SI)."""

    def __init__(self, vehicle: Vehicle, rate: float, channels: list[str], nthread: int | None = None):
        self.vehicle = vehicle
        self.rate = rate
        self.channels = list(channels)
        for name in self.channels:
            corner, _ = split_channel(name)
            if corner not in vehicle.corners:
                raise ValueError(f"channel '{name}' names no corner of {vehicle.name} ({', '.join(vehicle.corners)})")
        self.player = Replayer(vehicle, rate, "servo", nthread)

    def play(self, drives: np.ndarray, start_time: float = 0.0, forces: np.ndarray | None = None
             ) -> tuple[np.ndarray, list[ReplayResult]]:
        """Responses (batch, samples, channels) of drives (batch, samples, corners) or (samples, corners), and
        each run's replay result (all channels, post-force/stroke hits, joint positions). ``forces`` (samples x
        corners, N, from 0): the actuator forces between body and wheel that every run applies beside its drive (a
        lab bench's or an active car's ``active_force``, a measured input)."""
        drives = np.asarray(drives, float)
        if drives.ndim == 2:
            drives = drives[None]
        if forces is not None:
            forces = np.broadcast_to(np.asarray(forces, float), drives.shape)
        results = self.player.play(drives, clip=True, start_time=start_time, projected=True, forces=forces)
        missing = [n for n in self.channels if n not in results[0].record]
        if missing:
            raise ValueError(f"the rig has no response channel {', '.join(missing)}")
        return np.stack([np.column_stack([r.record[n] for n in self.channels]) for r in results]), results
