"""``hardpoint_error``: hardpoints of a linkage corner are not where its kinematics table puts them (a kinematic
cause: seen on K&C tests, rig/sim/kc.py).

    [hardpoint_error.front]               # m: each point moved from the table, left corner (the right mirrored)
    upper_outer = [0.002, 0.0, -0.003]
    [hardpoint_error.FL]                  # m: one corner's points moved, in vehicle axes (y left), on top
    tie_rod_outer = [0.0, 0.0, 0.003]

An axle's section moves both corners' points alike (mirror images); a corner's section moves that corner's alone,
by [dx, dy, dz] in vehicle axes (so a right corner's y is mirrored into its axle's left-corner table). Realised by
the suspension types, which build the corner from the moved points (``adjust_kinematics``). The diagnosis fits it
to K&C records (rig/diagnosis/kc/kinematic_diagnosis.py), not to ride records.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from rig.causes._base import Cause, ParameterSpec, with_extension
from rig.io.channels import axle_corners, corner_axle

LIMIT = 0.05  # m: a larger offset is a different design, not an error


class _HardpointError(Cause):
    name = "hardpoint_error"
    subsystem = "car"
    seen_on = "kc"
    meaning = "hardpoints of a linkage corner differ from its kinematics table"
    signature = "K&C curves (camber, toe, track change, caster, kingpin) off the table's, beyond the rig's scatter"

    def parse(self, section: Any, where: str, axles: tuple[str, ...]) -> dict[str, dict[str, tuple[float, ...]]]:
        corners = tuple(c for a in axles for c in axle_corners(a))
        names = [f"[{self.name}.{k}]" for k in (*axles, *corners)]
        if not isinstance(section, dict) or set(section) - set(axles) - set(corners):
            raise ValueError(f"{where}: [{self.name}] must hold sub-tables of axles or corners ({', '.join(names)})")
        out = {}
        for key, points in section.items():
            if not isinstance(points, dict):
                raise ValueError(f"{where}: [{self.name}.{key}] must be a table of hardpoint = [dx, dy, dz]")
            out[key] = {name: _offset(value, f"{where}: [{self.name}.{key}] {name}") for name, value in points.items()}
        return out

    def to_table(self, value: dict) -> dict:
        return {key: {name: list(offset) for name, offset in points.items()} for key, points in value.items()}

    def parameters(self) -> list[ParameterSpec]:
        return [ParameterSpec("<hardpoint>", "m", -LIMIT, LIMIT,
                              "[dx, dy, dz] of a hardpoint from its kinematics table (an axle's or a corner's)")]

    def adjust_kinematics(self, vehicle, corner, kinematics):
        axle = corner_axle(corner)
        section = vehicle.extensions.get(self.name, {})
        moves = {}
        for key, mirror in ((axle, 1.0), (corner, 1.0 if corner.endswith("L") else -1.0)):
            for name, offset in section.get(key, {}).items():
                if name not in kinematics.points:
                    raise ValueError(f"[{self.name}.{key}] {name}: not a hardpoint of the {axle} {kinematics.type} "
                                     f"(hardpoints: {', '.join(kinematics.points)})")
                moves[name] = moves.get(name, np.zeros(3)) + np.asarray(offset) * [1.0, mirror, 1.0]
        return kinematics.moved(moves) if moves else kinematics

    def hidden(self, truth, rng):
        """Two outer hardpoints of the front linkage moved by 3-5 mm in random directions."""
        if truth.front.kinematics is None:
            raise ValueError(f"[{self.name}] needs a linkage corner; {truth.name} has none at the front")
        points = [p for p in ("upper_outer", "strut_top", "tie_rod_outer", "lower_outer")
                  if p in truth.front.kinematics.points]
        chosen = rng.choice(points, size=2, replace=False)
        offsets = {}
        for name in chosen:
            direction = rng.normal(size=3)
            size = rng.uniform(3e-3, 5e-3)
            offsets[str(name)] = tuple(float(v) for v in direction / np.linalg.norm(direction) * size)
        return with_extension(truth, self.name, {"front": offsets})


def _offset(value: object, where: str) -> tuple[float, float, float]:
    if not isinstance(value, (list, tuple)) or len(value) != 3 or any(
            isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) or abs(v) > LIMIT
            for v in value):
        raise ValueError(f"{where} must be [dx, dy, dz] in m, each within +-{LIMIT} m, got {value!r}")
    return tuple(float(v) for v in value)  # type: ignore[return-value]


CAUSE = _HardpointError()
