"""Unit conversion to and from SI for record import and export (docs/contracts.md: SI everywhere inside).

Temperatures stay in degC (a damper's oil temperature); degF and K are read with their offsets, and a bare ``C`` or
``F``, as dyno loggers write them (``Temperature (C)``), is read as degrees where the channel is a temperature
(``si_conversion``); elsewhere a bare letter is refused, never guessed.
"""

import re
from typing import NamedTuple

from rig.errors import RigError

STANDARD_GRAVITY = 9.80665  # m/s^2, exact by definition (ISO 80000-3)

#: Factor that converts a value in the unit to SI, and the SI unit it converts to.
_TO_SI = {
    "s": (1.0, "s"),
    "ms": (1e-3, "s"),
    "us": (1e-6, "s"),
    "m": (1.0, "m"),
    "mm": (1e-3, "m"),
    "cm": (1e-2, "m"),
    "in": (0.0254, "m"),  # exact (international inch, 1959), as US dynamometers write lengths
    "m/s": (1.0, "m/s"),
    "mm/s": (1e-3, "m/s"),
    "in/s": (0.0254, "m/s"),
    "m/s^2": (1.0, "m/s^2"),
    "m/s2": (1.0, "m/s^2"),
    "m/s²": (1.0, "m/s^2"),
    "g": (STANDARD_GRAVITY, "m/s^2"),
    "N": (1.0, "N"),
    "kN": (1e3, "N"),
    "lbf": (4.4482216152605, "N"),  # exact: 0.45359237 kg x standard gravity
    "rad": (1.0, "rad"),
    "deg": (3.141592653589793 / 180.0, "rad"),
    "V": (1.0, "V"),  # raw transducer voltages, read only where a channel map asks for them
    "mV": (1e-3, "V"),
    "": (1.0, ""),
}


#: temperatures: factor and offset to degC (``degC = value * factor + offset``)
_TEMPERATURES = {
    "degC": (1.0, 0.0), "°C": (1.0, 0.0), "degF": (5 / 9, -32 * 5 / 9), "°F": (5 / 9, -32 * 5 / 9),
    "K": (1.0, -273.15),
}
#: the bare letters a logger writes for degrees, read so only on a temperature channel
_BARE_DEGREES = {"C": "degC", "F": "degF"}


class SIConversion(NamedTuple):
    """``value_si = value * factor + offset``, in ``unit`` (SI, or degC)."""

    factor: float
    offset: float
    unit: str


#: a header's unit at its end in parentheses or brackets, the closing one possibly cut off by the DAQ
_UNIT_IN_NAME = re.compile(r"^(?P<base>.*?)\s*[(\[](?P<unit>[^()\[\]]*)(?P<close>[)\]]?)\s*$")


class UnitError(RigError):
    """A unit that the importer does not know."""


def known_units() -> list[str]:
    """Units accepted on import, as written in a CSV header."""
    return sorted(u for u in [*_TO_SI, *_TEMPERATURES] if u)


def si_conversion(unit: str, temperature: bool = False) -> SIConversion:
    """How a value in ``unit`` becomes SI (temperatures: degC, with an offset); ``temperature``: the channel is a
    temperature, so a bare ``C`` or ``F`` is degrees. UnitError for a unit not in the tables."""
    key = unit.strip()
    key = _BARE_DEGREES.get(key, key) if temperature else key
    if key in _TEMPERATURES:
        return SIConversion(*_TEMPERATURES[key], "degC")
    if key in _BARE_DEGREES:
        raise UnitError(f"unit '{unit}' is read as degrees only on a temperature channel (map it to "
                        f"'<...>/temperature', or write deg{key})")
    return SIConversion(to_si(unit)[0], 0.0, to_si(unit)[1])


def to_si(unit: str) -> tuple[float, str]:
    """Return ``(factor, si_unit)`` such that ``value_si = value * factor``.

    Unit names are case-sensitive (``g`` is not ``G``). Raises UnitError for a unit that is not in the
    table: it never guesses.
    """
    key = unit.strip()
    if key in _TEMPERATURES:
        if _TEMPERATURES[key][1]:
            raise UnitError(f"'{unit}' converts to degC with an offset, not a factor")
        return _TEMPERATURES[key][0], "degC"
    if key not in _TO_SI:
        raise UnitError(f"unknown unit '{unit}' (known: {', '.join(known_units())})")
    return _TO_SI[key]


def si_to(unit: str, si_unit: str) -> float:
    """Factor that converts a value in ``si_unit`` to ``unit`` (for export); checks the dimensions agree."""
    factor, target = to_si(unit)
    if target != si_unit:
        raise UnitError(f"cannot express a value in {si_unit} as {unit}")
    return 1.0 / factor


def split_unit(header: str) -> tuple[str, str]:
    """A column header's name and the unit it writes at its end in parentheses or brackets (``"Force (N)"`` ->
    ``("Force", "N")``; ``("Force", "")`` without one). A DAQ that cuts its headers short may drop the closing
    parenthesis (LabVIEW: ``"Amplitude - Fc (N"``): an unclosed unit is read where it is one this module knows."""
    match = _UNIT_IN_NAME.match(header)
    if match is None:
        return header.strip(), ""
    unit = match["unit"].strip()
    if not match["close"] and unit not in known_units() and unit not in _BARE_DEGREES:
        return header.strip(), ""
    return match["base"].strip(), unit
