"""Unit conversion to and from SI for record import and export (docs/contracts.md: SI everywhere inside)."""

STANDARD_GRAVITY = 9.80665  # m/s^2, exact by definition (ISO 80000-3)

#: Factor that converts a value in the unit to SI, and the SI unit it converts to.
_TO_SI = {
    "s": (1.0, "s"),
    "ms": (1e-3, "s"),
    "m": (1.0, "m"),
    "mm": (1e-3, "m"),
    "cm": (1e-2, "m"),
    "m/s": (1.0, "m/s"),
    "mm/s": (1e-3, "m/s"),
    "m/s^2": (1.0, "m/s^2"),
    "m/s2": (1.0, "m/s^2"),
    "m/s²": (1.0, "m/s^2"),
    "g": (STANDARD_GRAVITY, "m/s^2"),
    "N": (1.0, "N"),
    "kN": (1e3, "N"),
    "rad": (1.0, "rad"),
    "deg": (3.141592653589793 / 180.0, "rad"),
    "degC": (1.0, "degC"),  # temperatures stay in degC (a damper's oil temperature on a dynamometer)
    "°C": (1.0, "degC"),
    "V": (1.0, "V"),  # raw transducer voltages, read only where a channel map asks for them
    "mV": (1e-3, "V"),
    "": (1.0, ""),
}


class UnitError(ValueError):
    """A unit that the importer does not know."""


def known_units() -> list[str]:
    """Units accepted on import, as written in a CSV header."""
    return sorted(u for u in _TO_SI if u)


def to_si(unit: str) -> tuple[float, str]:
    """Return ``(factor, si_unit)`` such that ``value_si = value * factor``.

    Unit names are case-sensitive (``g`` is not ``G``). Raises UnitError for a unit that is not in the
    table: it never guesses.
    """
    key = unit.strip()
    if key not in _TO_SI:
        raise UnitError(f"unknown unit '{unit}' (known: {', '.join(known_units())})")
    return _TO_SI[key]


def si_to(unit: str, si_unit: str) -> float:
    """Factor that converts a value in ``si_unit`` to ``unit`` (for export); checks the dimensions agree."""
    factor, target = to_si(unit)
    if target != si_unit:
        raise UnitError(f"cannot express a value in {si_unit} as {unit}")
    return 1.0 / factor
