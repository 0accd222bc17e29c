"""Contract quantities from one step's sensor data of every copy: one gather and one multiply-add.

``sensor_responses`` (rig/sim/simulate.py) makes each quantity at each corner from one sensor value, with a
sign and an offset (gravity, the static suspension length). ``SensorMap.of`` reads those columns, signs and
offsets off it once, from the zero and the unit sensor vectors, and checks on random sensor data that the
map gives bit for bit what ``sensor_responses`` gives; it refuses a conversion that is not such a map. The
environments convert a step's sensors with it, in place of one array operation per quantity.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from rig.sim.simulate import Simulator, sensor_responses


@dataclass(frozen=True)
class SensorMap:
    """Sensor data (copies, nsensordata) -> quantities (copies, quantities x corners), quantity-major."""

    names: tuple[str, ...]       # quantities in the order of the converted columns
    contract: tuple[str, ...]    # the same quantities in the order ``sensor_responses`` gives them
    corners: int
    columns: np.ndarray          # sensor data column of each converted column
    scale: np.ndarray            # its sign (+1 or -1)
    offset: np.ndarray           # and offset (SI); -0.0 for none, which adds nothing, not even to a zero's sign

    @classmethod
    def of(cls, sim: Simulator, first: Sequence[str] = ()) -> SensorMap:
        """The map of ``sim``'s sensors, its columns in the order of ``first``, then the other quantities."""
        rig, length = sim.rig, sim.static.suspension_length
        n = rig.model.nsensordata
        probe = sensor_responses(rig, length, np.vstack([np.zeros(n), np.eye(n)]))
        names = (*first, *(q for q in probe if q not in first))
        columns, scale, offset = [], [], []
        for name in names:
            for at_zero, *at_unit in probe[name].T:
                hit = np.flatnonzero(np.array(at_unit) != at_zero)
                if hit.size != 1:
                    raise ValueError(f"quantity {name} is not one sensor value with a sign and an offset")
                columns.append(hit[0])
                scale.append(np.sign(at_unit[hit[0]] - at_zero))
                offset.append(at_zero if at_zero != 0 else -0.0)
        corners = len(rig.corners)
        sensor_map = cls(names, tuple(probe), corners, np.array(columns), np.array(scale), np.array(offset))
        sensor_map._check(sim)
        return sensor_map

    def _check(self, sim: Simulator) -> None:
        sensors = np.random.default_rng(0).normal(0.0, 100.0, (16, sim.rig.model.nsensordata))
        sensors[0] = 0.0
        sensors[1] = -0.0
        converted = self.quantities(self.convert(sensors))
        for name, values in sensor_responses(sim.rig, sim.static.suspension_length, sensors).items():
            if values.tobytes() != np.ascontiguousarray(converted[name]).tobytes():
                raise ValueError(f"quantity {name} is not one sensor value with a sign and an offset")

    def convert(self, sensordata: np.ndarray) -> np.ndarray:
        """Quantities (copies, len(names) x corners), a new array, from ``sensordata`` (copies, nsensordata)."""
        values = sensordata[:, self.columns]
        values *= self.scale
        values += self.offset
        return values

    def slice(self, name: str) -> slice:
        """The columns of quantity ``name`` (its corners) in converted arrays."""
        start = self.names.index(name) * self.corners
        return slice(start, start + self.corners)

    def quantities(self, values: np.ndarray) -> dict[str, np.ndarray]:
        """Converted ``values`` as contract quantities (copies, corners) in ``sensor_responses``' order (views)."""
        return {name: values[:, self.slice(name)] for name in self.contract}
