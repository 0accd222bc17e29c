"""K&C records of fs_car with moved hardpoints from the independent loop-closure solver (tests/kinematics_reference.py),
as a K&C machine measures them: camber, toe and track change only, with 0.02 deg and 0.05 mm of scatter; a travel
test (+-60 mm at every wheel) and a steer test (+-20 mm of rack). Each corner may have its own points."""

from __future__ import annotations

import tomllib

import numpy as np

from kinematics_reference import sweep
from rig.io.kc_record import KcResult
from rig.vehicle.vehicle_file import resolve_vehicle_path

ANGLE_NOISE, LENGTH_NOISE = 0.02, 5e-5  # deg, m
CORNERS = {"FL": ("front", 1), "FR": ("front", -1), "RL": ("rear", 1), "RR": ("rear", -1)}


def fs_tables() -> dict[str, dict]:
    """fs_car's kinematics tables per axle, as in its file."""
    table = tomllib.loads(resolve_vehicle_path("fs_car").read_text())
    return {axle: table[axle]["kinematics"] for axle in ("front", "rear")}


def moved(moves: dict[str, dict[str, list[float]]]) -> dict[str, dict]:
    """fs_car's tables per corner, with ``moves``: corner -> point -> [dx, dy, dz] (m, vehicle axes of that corner)."""
    tables = fs_tables()
    out = {}
    for corner, (axle, side) in CORNERS.items():
        table = dict(tables[axle])
        for point, offset in moves.get(corner, {}).items():
            table[point] = list(np.add(table[point], [offset[0], side * offset[1], offset[2]]))
        out[corner] = table
    return out


def records(tables: dict[str, dict], seed: int, samples: int = 13) -> list[KcResult]:
    """Travel and steer records of every corner (tables per corner) with the machine's scatter."""
    rng = np.random.default_rng(seed)
    out = []
    for test, values in (("travel", np.linspace(-0.06, 0.06, samples)), ("steer", np.linspace(-0.02, 0.02, samples))):
        curves = {}
        for corner, (axle, side) in CORNERS.items():
            steered = axle == "front"
            reference = sweep(tables[corner], side, steered=steered,
                              **({"travels": values} if test == "travel" else {"racks": values}))
            curves[f"{corner}/travel"] = values if test == "travel" else 0.0 * values
            for quantity in ("camber", "toe"):
                curves[f"{corner}/{quantity}"] = np.radians(reference[quantity] + rng.normal(0, ANGLE_NOISE, samples))
            curves[f"{corner}/track_change"] = reference["track_change"] + rng.normal(0, LENGTH_NOISE, samples)
        out.append(KcResult("fs_car", test, "travel" if test == "travel" else "rack", values, tuple(CORNERS), curves))
    return out
