"""Channel names of the test-record contract (docs/contracts.md): ``<corner>/<quantity>``, SI units.

Corners are wheel stations: ``FL``, ``FR`` and ``RL``, ``RR`` on a car; a truck (layout ``truck``) adds ``ML``,
``MR`` for one middle axle, or ``M1L``, ``M1R``, ``M2L``, ``M2R``, ... front to rear for more. A corner's axle has a
name: ``front``, ``middle`` (``middle1``, ``middle2``, ...), ``rear``; per-axle vehicle-file tables use it.
"""

from __future__ import annotations

import re
from collections.abc import Iterable

CORNERS = ("FL", "FR", "RL", "RR")  # a car's corners, in contract order

_CORNER = re.compile(r"^(F|R|M|M[1-9][0-9]*)([LR])$")
_AXLE = re.compile(r"^(front|rear|middle|middle[1-9][0-9]*)$")

#: Quantities of the contract and their SI unit.
QUANTITY_UNITS = {
    "drive": "m",
    "actuator_disp": "m",
    "actuator_force": "N",
    "sprung_acc": "m/s^2",
    "unsprung_acc": "m/s^2",
    "susp_travel": "m",
    "susp_velocity": "m/s",
    "tyre_force": "N",
    "road": "m",
    "control_force": "N",  # force of a suspension controller's actuator (active force or semi-active damper)
    "force": "N",  # damper/force on a dynamometer: positive resisting extension (docs/contracts.md)
    "temperature": "degC",  # damper/temperature: the damper's (oil or body) temperature
    "wheel_angle": "rad",  # unwrapped, 0 at the wheel's mark (an impulse transducer), growing in the rolling direction
    "seat_acc": "m/s^2",  # cab/seat_acc: vertical acceleration at a truck's seat point
    "active_force": "N",  # an input: an actuator's force between body and wheel, on the body, up positive
    "sprung_disp": "m",  # body vertical displacement above the wheel from static, up positive
    "unsprung_disp": "m",  # wheel-centre vertical displacement from static, up positive
}

#: Response quantities a replay returns, in this order per corner.
RESPONSE_QUANTITIES = (
    "sprung_acc",
    "unsprung_acc",
    "susp_travel",
    "susp_velocity",
    "tyre_force",
    "actuator_disp",
    "actuator_force",
    "sprung_disp",
    "unsprung_disp",
)


def channel(corner: str, quantity: str) -> str:
    """The contract name of ``quantity`` at ``corner``, e.g. ``FL/sprung_acc``."""
    return f"{corner}/{quantity}"


def split_channel(name: str) -> tuple[str, str]:
    """``'FL/sprung_acc'`` -> ``('FL', 'sprung_acc')``; ``('', name)`` for a name without a corner."""
    corner, sep, quantity = name.partition("/")
    if not sep:
        return "", name
    return corner, quantity


def is_corner(name: str) -> bool:
    """Whether ``name`` is a corner of some layout (``FL``, ``MR``, ``M2L``...)."""
    return _CORNER.match(name) is not None


def axle_names(count: int) -> tuple[str, ...]:
    """Axle names of a layout with ``count`` axles, front to rear: front, [middle | middle1, middle2, ...], rear."""
    if count < 1:
        raise ValueError(f"a layout needs at least one axle, got {count}")
    if count == 1:
        return ("front",)
    middle = ("middle",) if count == 3 else tuple(f"middle{i}" for i in range(1, count - 1))
    return ("front", *middle, "rear")


def axle_corners(axle: str) -> tuple[str, str]:
    """The left and right corner of axle ``axle`` (``'middle2'`` -> ``('M2L', 'M2R')``)."""
    if _AXLE.match(axle) is None:
        raise ValueError(f"{axle!r} is not an axle name (front, middle, middle1, ..., rear)")
    prefix = {"front": "F", "rear": "R"}.get(axle, "M" + axle[len("middle"):])
    return f"{prefix}L", f"{prefix}R"


def corner_axle(corner: str) -> str:
    """The axle a corner belongs to: ``FL`` -> ``front``, ``ML`` -> ``middle``, ``M2R`` -> ``middle2``."""
    match = _CORNER.match(corner)
    if match is None:
        raise ValueError(f"{corner!r} is not a corner (FL, FR, ML, MR, M1L, ..., RL, RR)")
    prefix = match.group(1)
    return {"F": "front", "R": "rear"}.get(prefix, "middle" + prefix[1:])


def corner_side(corner: str) -> int:
    """+1 for a left corner, -1 for a right one."""
    return 1 if corner.endswith("L") else -1


def _order(corner: str) -> tuple[int, int, int]:
    prefix, side = _CORNER.match(corner).groups()
    rank = {"F": (0, 0), "R": (2, 0)}.get(prefix, (1, int(prefix[1:] or 0)))
    return (*rank, 0 if side == "L" else 1)


def sort_corners(names: Iterable[str]) -> list[str]:
    """The corners among ``names``, once each, in contract order (front to rear, left before right)."""
    return sorted({n for n in names if is_corner(n)}, key=_order)
