"""The suspension-type registry: one module per type, each holding one ``SUSPENSION``
(rig/vehicle/suspensions/_base.py).

A type builds one corner of the car's MjSpec at the station its layout gives (``Vehicle.corner_position``) and
knows its geometry. ``vertical`` is the baseline ride model's slider; ``double_wishbone`` and ``macpherson``
are linkages built from the hardpoints of a ``[front.kinematics]`` / ``[rear.kinematics]`` table; ``beam_leaf`` and
``beam_air`` are a truck's beam axles on leaf or air springs (``[[axles]]``, rig/vehicle/truck_file.py). Modules are
found on first use, so a new type is a new module and nothing else: its own parameters go in the axle's sub-table of
its ``law``, its defaults and derived rate in ``complete_axle`` and ``law_rate`` (rig/vehicle/suspensions/_base.py).
"""

from __future__ import annotations

import functools
from typing import TYPE_CHECKING

from rig.registries import held_by_modules

if TYPE_CHECKING:
    from rig.vehicle.suspensions._base import Suspension
    from rig.vehicle.suspensions.hardpoints import Kinematics
    from rig.vehicle.parts import Vehicle

VERTICAL = "vertical"


_REGISTERED: dict[str, Suspension] = {}


@functools.cache
def _found() -> dict[str, Suspension]:
    """Type name -> suspension type, found among this package's modules (those holding a ``SUSPENSION``)."""
    return held_by_modules(__name__, __path__, "SUSPENSION")


def suspensions() -> dict[str, Suspension]:
    """Type name -> suspension type, alphabetical: this package's modules and those registered."""
    return dict(sorted({**_found(), **_REGISTERED}.items()))


def register_suspension(suspension: Suspension) -> None:
    """Add a suspension type from outside this package (a test's throwaway type)."""
    _REGISTERED[suspension.name] = suspension


def unregister_suspension(name: str) -> None:
    _REGISTERED.pop(name, None)


def kinematics_of(vehicle: Vehicle, corner: str) -> Kinematics | None:
    """The corner's linkage hardpoints as built: its axle's table, as the vehicle's causes change it for this corner
    (a hardpoint error, bushing rates); None for a vertical corner."""
    from rig.vehicle.extensions import extensions

    kinematics = vehicle.axle(corner).kinematics
    if kinematics is None:
        return None
    for cause in extensions().values():
        if cause.present(vehicle):
            kinematics = cause.adjust_kinematics(vehicle, corner, kinematics)
    return kinematics


def suspension_of(vehicle: Vehicle, corner: str) -> Suspension:
    """The suspension type of ``corner``: a truck axle's ``suspension``, else its axle's kinematics type, or the
    vertical slider without one."""
    axle = vehicle.axle(corner)
    if axle.suspension:
        return suspensions()[axle.suspension]
    return suspensions()[axle.kinematics.type if axle.kinematics is not None else VERTICAL]
