"""The parameters of a force element (and of a cause, built from elements): frozen dataclasses whose fields carry
their SI unit, plausible range and meaning (``param``), read from a vehicle-file table with unknown, missing and
implausible keys refused (``parse_values``)."""

from __future__ import annotations

from dataclasses import MISSING, fields
from typing import Any, ClassVar, Protocol


class ElementValues(Protocol):
    """A force element's parameters: a dataclass whose fields carry ``param`` metadata (an air spring's, a leaf
    spring's friction)."""

    __dataclass_fields__: ClassVar[dict[str, Any]]


def param(unit: str, low: float, high: float, meaning: str) -> dict:
    """Field metadata of a cause parameter: SI unit, plausible range, meaning."""
    return {"unit": unit, "low": low, "high": high, "meaning": meaning}


def parse_values(kind: type, table: Any, where: str) -> object:
    """A cause's parameter dataclass from a vehicle-file table: unknown, missing or implausible keys refused."""
    if not isinstance(table, dict):
        raise ValueError(f"{where} must be a table")
    names = [f.name for f in fields(kind)]
    required = [f.name for f in fields(kind) if f.default is MISSING]
    unknown = sorted(set(table) - set(names))
    missing = [n for n in required if n not in table]
    if unknown or missing:
        raise ValueError(f"{where}: " + "; ".join(
            ([f"unknown key(s) {', '.join(unknown)}"] if unknown else [])
            + ([f"missing {', '.join(missing)}"] if missing else [])
        ) + f" (keys: {', '.join(names)})")
    for f in fields(kind):
        if f.name not in table:
            continue
        value, low, high = table[f.name], f.metadata["low"], f.metadata["high"]
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not low <= value <= high:
            raise ValueError(f"{where}: {f.name} = {value!r} is outside the plausible range {low:g}..{high:g} "
                             f"{f.metadata['unit']}")
    return kind(**{n: float(v) for n, v in table.items()})
