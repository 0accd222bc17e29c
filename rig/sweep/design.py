"""The points of a sweep: vehicle-file keys (``front.damping``, ``sprung.mass``, a truck's ``axles.1.damping`` counted
from 0) and ``speed``, and their values.

- a full grid: ``KEY=START:STOP:COUNT`` per key, every combination, the last key varying fastest;
- ``samples`` points: each ``KEY=START:STOP`` uniform over its range, each scattered key ``KEY=PCT`` normal about
  its nominal value with a standard deviation of PCT % of it (Forsén 1999: the experimental scatter is the accuracy
  target, so simulate that scatter). Drawn as a Latin hypercube (``scipy.stats.qmc``; the normal keys through the
  inverse normal CDF, so every stratum of each key is drawn once) or plain Monte-Carlo. Zero scatter gives the
  nominal value exactly.

A point becomes a vehicle by setting its keys in the vehicle file's tables and reading them back with the
vehicle-file checks (rig/vehicle/vehicle_file.py), so an implausible value is refused as a file would be.
"""

from __future__ import annotations

import copy
import json
import tomllib
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from rig.errors import RigError
from rig.vehicle.vehicle_file import Vehicle, vehicle_from_dict, vehicle_to_toml

SPEED = "speed"
SAMPLINGS = ("lhs", "random")


class SweepError(RigError):
    """A sweep that cannot be run as asked; the message names the option or key."""


@dataclass(frozen=True)
class Factor:
    """A varied key: START..STOP, with COUNT grid values (None: sampled uniformly)."""

    key: str
    start: float
    stop: float
    count: int | None = None


@dataclass(frozen=True)
class Design:
    """The design points: ``values[i, j]`` is key ``keys[j]`` at point ``i`` (SI, as in the vehicle file)."""

    keys: tuple[str, ...]
    values: np.ndarray
    kind: str  # "grid", "lhs", "random" or "nominal"

    @property
    def n_points(self) -> int:
        return self.values.shape[0]

    def point(self, i: int) -> dict[str, float]:
        return {k: float(v) for k, v in zip(self.keys, self.values[i])}

    def to_json(self) -> str:
        return json.dumps({"keys": list(self.keys), "kind": self.kind, "values": self.values.tolist()})

    @classmethod
    def from_json(cls, text: str) -> Design:
        data = json.loads(text)
        return cls(tuple(data["keys"]), np.array(data["values"], float).reshape(-1, len(data["keys"])), data["kind"])


def parse_vary(text: str) -> Factor:
    """``KEY=START:STOP:COUNT`` (grid) or ``KEY=START:STOP`` (sampled)."""
    key, _, spec = text.partition("=")
    parts = spec.split(":")
    if not key or len(parts) not in (2, 3):
        raise SweepError(f"vary {text!r}: expected KEY=START:STOP:COUNT (a grid) or KEY=START:STOP (sampled)")
    try:
        start, stop = float(parts[0]), float(parts[1])
        count = int(parts[2]) if len(parts) == 3 else None
    except ValueError:
        raise SweepError(f"vary {text!r}: START and STOP must be numbers and COUNT an integer") from None
    if not (np.isfinite(start) and np.isfinite(stop)) or (count is not None and count < 1):
        raise SweepError(f"vary {text!r}: START and STOP must be finite and COUNT at least 1")
    return Factor(key, start, stop, count)


def parse_scatter(text: str) -> tuple[str, float]:
    """``KEY=PCT``: the key's standard deviation in percent of its nominal value."""
    key, _, pct = text.partition("=")
    try:
        value = float(pct)
    except ValueError:
        value = float("nan")
    if not key or not np.isfinite(value) or value < 0:
        raise SweepError(f"scatter {text!r}: expected KEY=PCT with PCT a non-negative number (percent)")
    return key, value


def vehicle_tables(vehicle: Vehicle) -> dict:
    """The vehicle file's tables, every key present (defaults written out), to set keys in."""
    return tomllib.loads(vehicle_to_toml(vehicle))


def nominal_value(tables: dict, key: str, speed: float | None = None) -> float:
    """The nominal value of ``key`` (a dotted vehicle-file path, or ``speed``); SweepError if there is none."""
    if key == SPEED:
        if speed is None:
            raise SweepError("'speed' can only be varied on a road (a road and a speed), not on a drive replay")
        return speed
    node = tables
    for i, part in enumerate(key.split(".")):
        if isinstance(node, list):  # a truck's [[axles]]: axles.<index>.<key>, counted from 0
            if not part.isdigit() or int(part) >= len(node):
                raise SweepError(f"unknown key {key!r}: {'.'.join(key.split('.')[:i])} is a list of {len(node)} "
                                 f"tables, indexed 0..{len(node) - 1}")
            node = node[int(part)]
            continue
        if not isinstance(node, dict) or part not in node:
            where = ".".join(key.split(".")[:i]) or "the vehicle file"
            known = ", ".join(sorted(node)) if isinstance(node, dict) else "none"
            raise SweepError(f"unknown key {key!r}: {where} has no {part!r} (it has: {known})")
        node = node[part]
    if isinstance(node, bool) or not isinstance(node, (int, float)):
        raise SweepError(f"key {key!r} is not a number in the vehicle file (got {node!r})")
    return float(node)


def vehicle_at(tables: dict, point: dict[str, float], where: str = "sweep point") -> Vehicle:
    """The vehicle with the point's keys set (``speed`` is not a vehicle key and is left out)."""
    changed = copy.deepcopy(tables)
    for key, value in point.items():
        if key == SPEED:
            continue
        *path, last = key.split(".")
        node = changed
        for part in path:
            node = node[int(part)] if isinstance(node, list) else node[part]
        node[last] = value
    return vehicle_from_dict(changed, where)


def make_design(vary: Sequence[Factor], scatter: Sequence[tuple[str, float]], nominal: dict[str, float],
                samples: int | None = None, sampling: str = "lhs", seed: int = 0) -> Design:
    """The design points (see the module docstring); ``nominal`` gives every scattered key's nominal value."""
    from scipy.stats import norm, qmc  # here, not at the top: the command line imports SweepError from this module

    keys = [f.key for f in vary] + [k for k, _ in scatter]
    repeated = sorted({k for k in keys if keys.count(k) > 1})
    if repeated:
        raise SweepError(f"key(s) {', '.join(repeated)} given more than once in vary / scatter")
    if samples is None:
        if scatter:
            raise SweepError("scatter needs a number of samples (the Monte-Carlo draws)")
        if any(f.count is None for f in vary):
            raise SweepError("a grid needs KEY=START:STOP:COUNT for every vary (or a number of samples)")
        if not vary:
            return Design((), np.zeros((1, 0)), "nominal")
        axes = np.meshgrid(*[np.linspace(f.start, f.stop, f.count) for f in vary], indexing="ij")
        return Design(tuple(keys), np.stack([a.ravel() for a in axes], axis=1), "grid")
    if samples < 1:
        raise SweepError(f"samples must be at least 1, got {samples}")
    if sampling not in SAMPLINGS:
        raise SweepError(f"sampling must be one of {', '.join(SAMPLINGS)}, got {sampling!r}")
    if any(f.count is not None for f in vary):
        raise SweepError("with samples, give vary as KEY=START:STOP (sampled uniformly), not a grid COUNT")
    if not keys:
        raise SweepError("samples need something to sample: vary KEY=START:STOP or scatter KEY=PCT")
    rng = np.random.default_rng(seed)
    unit = qmc.LatinHypercube(d=len(keys), seed=rng).random(samples) if sampling == "lhs" else \
        rng.random((samples, len(keys)))
    columns = [f.start + unit[:, j] * (f.stop - f.start) for j, f in enumerate(vary)]
    for j, (key, pct) in enumerate(scatter, start=len(vary)):
        z = norm.ppf(np.clip(unit[:, j], 1e-12, 1.0 - 1e-12))  # plain Monte-Carlo may draw exactly 0
        columns.append(np.full(samples, nominal[key]) if pct == 0 else nominal[key] * (1.0 + pct / 100.0 * z))
    return Design(tuple(keys), np.stack(columns, axis=1), sampling)
