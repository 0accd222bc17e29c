"""K&C records (``DIR/kc.csv``, contract: docs/contracts.md): the sweep in the first column, then the curves per corner
and per axle, with units in brackets; ``# key: value`` metadata lines first (vehicle, test).

In memory everything is SI (angles in rad, compliance in rad/N); the file holds the contract's units (angles in
deg, compliance in deg/kN). Reading accepts those, SI, or mm / kN where a length / force is expected.
"""

from __future__ import annotations

import io
import math
import os
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from rig.io.atomic import atomic_path
from rig.io.record import RecordError
from rig.io.text import read_text

TESTS = ("travel", "roll", "steer", "lateral", "longitudinal", "aligning")
#: test -> (sweep name, SI unit, default half range in SI)
SWEEPS = {"travel": ("travel", "m", 0.06), "roll": ("roll", "rad", np.radians(3.0)), "steer": ("rack", "m", 0.02),
          "lateral": ("force", "N", 1000.0), "longitudinal": ("force", "N", 1000.0),
          "aligning": ("moment", "N m", 100.0)}


@dataclass(frozen=True)
class KcResult:
    """A K&C test's curves: ``sweep`` (SI: m, rad, N, N m) and ``curves`` '<corner>/<quantity>' or
    '<axle>/roll_centre_height' -> array over the sweep, SI (angles in rad)."""

    vehicle: str
    test: str
    sweep_name: str
    sweep: np.ndarray
    corners: tuple[str, ...]
    curves: dict[str, np.ndarray] = field(default_factory=dict)
    states: np.ndarray | None = None  # the K&C rig model's joint positions per point (a simulated test; not written)


#: quantity -> unit written (and the SI unit kept in memory)
QUANTITY_UNITS = {
    "travel": "m", "camber": "deg", "toe": "deg", "caster": "deg", "kingpin": "deg", "scrub_radius": "m",
    "trail": "m", "track_change": "m", "wheelbase_change": "m", "motion_ratio": "-", "wheel_rate": "N/m",
    "wheel_load": "N", "compliance_steer": "deg/kN", "compliance_camber": "deg/kN", "roll_centre_height": "m",
    "laser": "m", "rack": "m", "wishbone_angle": "deg", "upper_wishbone_angle": "deg", "steering_angle": "deg",
}
SWEEP_UNITS = {"travel": "m", "roll": "deg", "rack": "m", "force": "N", "moment": "N m"}
_DEG = math.pi / 180.0
#: unit -> factor to SI
FACTORS = {"m": 1.0, "mm": 1e-3, "deg": _DEG, "rad": 1.0, "N": 1.0, "kN": 1e3, "N m": 1.0, "kN m": 1e3,
           "N/m": 1.0, "N/mm": 1e3, "-": 1.0, "": 1.0, "deg/kN": _DEG / 1e3, "rad/N": 1.0,
           "deg/(kN m)": _DEG / 1e3, "rad/(N m)": 1.0}


class KcRecordError(RecordError):
    """A K&C record that cannot be read: names the column or row."""


def unit_of(name: str, test: str) -> str:
    """The unit a curve ``<corner or axle>/<quantity>`` is written in."""
    quantity = name.split("/", 1)[1].rstrip("0123456789_")
    unit = QUANTITY_UNITS[quantity]
    return "deg/(kN m)" if unit == "deg/kN" and test == "aligning" else unit


def write_kc_csv(path: str | os.PathLike, result: KcResult) -> None:
    """Write ``result`` as a K&C record (atomically)."""
    names = list(result.curves)
    units = [unit_of(n, result.test) for n in names]
    sweep_unit = SWEEP_UNITS[result.sweep_name]
    columns = [result.sweep / FACTORS[sweep_unit]] + [result.curves[n] / FACTORS[u] for n, u in zip(names, units)]
    buffer = io.StringIO()
    buffer.write(f"# vehicle: {result.vehicle}\n# test: kc\n# kc_test: {result.test}\n")
    buffer.write(",".join([f"{result.sweep_name} [{sweep_unit}]"] + [f"{n} [{u}]" for n, u in zip(names, units)]))
    buffer.write("\n")
    np.savetxt(buffer, np.column_stack(columns), delimiter=",", fmt="%.10g")
    with atomic_path(path) as temporary:
        Path(temporary).write_text(buffer.getvalue(), encoding="utf-8")


def is_kc_record(path: str | os.PathLike) -> bool:
    """Whether ``path`` is a K&C record (a CSV whose metadata say ``# test: kc``)."""
    path = Path(path)
    if path.suffix.lower() != ".csv" or not path.is_file():
        return False
    try:
        text = read_text(path, "CSV record")
    except ValueError:  # not text: not a K&C record (the record reader says what it is)
        return False
    for line in text.splitlines():
        if not line.startswith("#"):
            return False
        key, _, value = line[1:].partition(":")
        if key.strip() == "test":
            return value.strip() == "kc"
    return False


def read_kc_csv(path: str | os.PathLike) -> KcResult:
    """Read a K&C record (as ``write_kc_csv`` writes it, or a measurement in the same layout)."""
    path = Path(path)
    lines = read_text(path, "K&C record", RecordError).splitlines()
    metadata, start = {}, 0
    while start < len(lines) and lines[start].startswith("#"):
        key, _, value = lines[start][1:].partition(":")
        metadata[key.strip()] = value.strip()
        start += 1
    if start >= len(lines):
        raise KcRecordError(f"{path}: no header line")
    header = [_split(cell, path) for cell in lines[start].split(",")]
    sweep_name, sweep_unit = header[0]
    test = metadata.get("kc_test") or next((t for t, (n, _, _) in SWEEPS.items() if n == sweep_name), None)
    if sweep_name not in SWEEP_UNITS or test is None or SWEEPS[test][0] != sweep_name:
        raise KcRecordError(f"{path}: the first column must be the sweep ({', '.join(SWEEP_UNITS)}), got "
                            f"{sweep_name!r}")
    try:
        data = np.atleast_2d(np.loadtxt(lines[start + 1:], delimiter=",", ndmin=2))
    except ValueError as err:
        raise KcRecordError(f"{path}: {err}") from None
    if data.shape[1] != len(header):
        raise KcRecordError(f"{path}: {data.shape[1]} values per row for {len(header)} columns")
    if not np.all(np.isfinite(data)):
        row, column = np.argwhere(~np.isfinite(data))[0]
        raise KcRecordError(f"{path}: column {header[column][0]!r} row {row + 1} is not a finite number")
    curves = {}
    for (name, unit), values in zip(header[1:], data[:, 1:].T):
        if "/" not in name:
            raise KcRecordError(f"{path}: column {name!r} is not '<corner>/<quantity>'")
        curves[name] = values * _factor(unit, name, path)
    corners = tuple(dict.fromkeys(n.split("/")[0] for n in curves if n.split("/")[0] not in ("front", "rear")))
    return KcResult(metadata.get("vehicle", ""), test, sweep_name, data[:, 0] * _factor(sweep_unit, sweep_name, path),
                    corners, curves)


def _split(cell: str, path: Path) -> tuple[str, str]:
    name, _, rest = cell.strip().partition("[")
    if not rest.endswith("]"):
        raise KcRecordError(f"{path}: column {cell.strip()!r} has no unit in brackets")
    return name.strip(), rest[:-1].strip()


def _factor(unit: str, name: str, path: Path) -> float:
    if unit not in FACTORS:
        raise KcRecordError(f"{path}: column {name!r} has the unknown unit {unit!r} (known: {', '.join(FACTORS)})")
    return FACTORS[unit]
