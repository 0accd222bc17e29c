"""How results look, shared by the PNG plots and the Rerun review: one colour per corner, the neutral grey of
references (targets, measurements, the road), one colour per model where models of one corner are compared, the
units a quantity is read in (mm for post motion and suspension travel, kN for forces), and a fitted value written
to the precision its interval supports."""

from __future__ import annotations

import math

from rig.io.channels import split_channel

Color = tuple[int, int, int]  # RGB, 0-255

#: One colour per corner (Okabe-Ito: told apart with colour-blind vision, readable on light and dark
#: backgrounds); trucks' middle axles take the next ones.
CORNER_COLORS: dict[str, Color] = {"FL": (213, 94, 0), "FR": (0, 114, 178), "RL": (0, 150, 110), "RR": (170, 80, 160),
                                   "ML": (180, 140, 0), "MR": (90, 90, 200)}
#: References (a target, a measurement, the road): a neutral grey with a WCAG contrast above 3 against white
#: and against near-black.
REFERENCE_COLOR: Color = (115, 115, 115)

#: Models of one corner compared with its measurement (a diagnosis): one colour each, so that they are told apart
#: from each other and from the measurement's grey (the corner palette's purple, vermilion and blue: a tab holds
#: one corner, and its name says which).
MODEL_COLORS: dict[str, Color] = {"baseline": (170, 80, 160), "recalibrated": (213, 94, 0),
                                  "extended": (0, 114, 178)}

#: quantity -> (unit it is read in, factor from SI)
DISPLAY_UNITS: dict[str, tuple[str, float]] = {
    "drive": ("mm", 1e3), "actuator_disp": ("mm", 1e3), "road": ("mm", 1e3), "susp_travel": ("mm", 1e3),
    "sprung_disp": ("mm", 1e3), "unsprung_disp": ("mm", 1e3),
    "sprung_acc": ("m/s²", 1.0), "unsprung_acc": ("m/s²", 1.0), "susp_velocity": ("m/s", 1.0),
    "tyre_force": ("kN", 1e-3), "actuator_force": ("kN", 1e-3), "control_force": ("kN", 1e-3),
    "active_force": ("kN", 1e-3), "wheel_angle": ("rad", 1.0), "seat_acc": ("m/s²", 1.0),
}


def corner_color(corner: str) -> Color:
    """The colour of ``corner`` (a truck's ``M1L``, ``M2L``, ... take ``ML``'s; the reference grey for a name that is
    not a corner)."""
    if corner not in CORNER_COLORS and len(corner) > 2 and corner[0] == "M" and corner[1:-1].isdigit():
        return CORNER_COLORS["M" + corner[-1]]
    return CORNER_COLORS.get(corner, REFERENCE_COLOR)


def channel_color(name: str) -> Color:
    """The colour of channel ``<corner>/<quantity>``: its corner's; the road is a reference (grey)."""
    corner, quantity = split_channel(name)
    return REFERENCE_COLOR if quantity == "road" else corner_color(corner)


def tint(color: Color, share: float = 0.55) -> Color:
    """``color`` mixed with white (``share`` of white): a command beside what was achieved, same corner."""
    return tuple(round(v + share * (255 - v)) for v in color)


def mpl(color: Color) -> tuple[float, float, float]:
    """``color`` as matplotlib takes it (0-1)."""
    return tuple(v / 255 for v in color)


def display_unit(quantity: str) -> tuple[str, float]:
    """The unit ``quantity`` is read in and its factor from SI (SI itself for quantities not listed)."""
    return DISPLAY_UNITS.get(quantity, ("SI", 1.0))


def index_text(index: float | None) -> str:
    """A signed discrepancy index (Forsén's ride, payload or fatigue index), or '-' where the record has no channel
    for it."""
    return "-" if index is None else f"{index:+.3f}"


def value_text(value: float, unit: str = "-", interval: tuple[float, float] | None = None) -> str:
    """``value`` with its unit (none for ``-``), written to the precision its 95 % ``interval`` supports (two
    significant digits of the interval's half-width: an optimiser's 2.8e-13 on an interval of +-680 is 0 +- 680);
    four significant digits without an interval; "not determined" for an unbounded one."""
    suffix = "" if unit in ("-", "") else f" {unit}"
    if interval is None:
        return f"{value:.4g}{suffix}"
    low, high = interval
    if not (math.isfinite(low) and math.isfinite(high)):
        return f"{value:.4g}{suffix} (not determined)"
    half = (high - low) / 2
    if not half > 0:
        return f"{value:.4g}{suffix}"
    step = 10.0 ** (math.floor(math.log10(half)) - 1)
    rounded, half = round(value / step) * step or 0.0, round(half / step) * step  # "or": no -0
    decimals = max(0, -math.floor(math.log10(step) + 1e-9))
    if decimals <= 5 and max(abs(rounded), half) < 1e7:  # plain: 0.01517 +- 0.00037, 236000 +- 32000
        return f"{rounded:.{decimals}f} ± {half:.{decimals}f}{suffix}"
    digits = math.floor(math.log10(abs(rounded))) - math.floor(math.log10(step) + 1e-9) if rounded else 0
    return f"{rounded:.{max(digits, 0)}e} ± {half:.1e}{suffix}" if rounded else f"0 ± {half:.1e}{suffix}"
