"""The plant a drive tuner works on: a vehicle on the servo-post rig, post drives in, chosen channels out."""

from __future__ import annotations

import numpy as np

from rig.channels import split_channel
from rig.drive_limits import LimitHit, achieved_hits
from rig.model import build_model
from rig.simulate import Simulator, run_batch
from rig.vehicle import Vehicle


class VirtualRig:
    """Plays drives (samples x corners, m) at ``rate`` Hz and returns the ``channels`` (SI)."""

    def __init__(self, vehicle: Vehicle, rate: float, channels: list[str], nthread: int | None = None):
        self.vehicle = vehicle
        self.rate = rate
        self.channels = list(channels)
        self.nthread = nthread
        self.simulator = Simulator.create(build_model(vehicle, rate, "servo"))
        corners = vehicle.corners
        self._columns = []
        for name in self.channels:
            corner, quantity = split_channel(name)
            if corner not in corners:
                raise ValueError(f"channel '{name}' names no corner of {vehicle.name} ({', '.join(corners)})")
            self._columns.append((quantity, corners.index(corner)))

    def play(self, drives: np.ndarray) -> tuple[np.ndarray, dict[str, np.ndarray], list[list[LimitHit]]]:
        """Responses (batch, samples, channels), all quantities, and the post-force/stroke hits of each run."""
        drives = np.asarray(drives, float)
        if drives.ndim == 2:
            drives = drives[None]
        out = run_batch([self.simulator], drives, self.nthread)
        try:
            responses = np.stack([out[q][:, :, c] for q, c in self._columns], axis=-1)
        except KeyError as err:
            raise ValueError(f"the rig has no response quantity {err}") from None
        time = np.arange(drives.shape[1]) / self.rate
        hits = [achieved_hits(self.vehicle.rig, self.vehicle.corners, out["actuator_force"][b], out["actuator_disp"][b], time)
                for b in range(drives.shape[0])]
        return responses, out, hits
