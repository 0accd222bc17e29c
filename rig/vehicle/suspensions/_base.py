"""What a suspension type is: one object per type module, ``SUSPENSION``, that builds one corner of the car's
MjSpec at the station the vehicle's layout gives and knows the corner's geometry.

The corner's contract with the rest of the model (what causes, sensors and the simulator rely on): a site
``<corner>/body`` on the sprung body above the wheel centre, a site ``<corner>/hub`` at the wheel centre, a body
``<corner>/wheel`` carrying the wheel, tendons ``<corner>/suspension`` (spring, wheel rate at design) and
``<corner>/damper`` (damping at the wheel at design), and sensors ``<corner>/unsprung_acc``,
``<corner>/suspension_length`` and ``<corner>/suspension_rate`` whose decrease is the wheel's travel (m, m/s)
relative to the body.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, ClassVar

import numpy as np

if TYPE_CHECKING:
    import mujoco

    from rig.elements.parameters import ElementValues
    from rig.vehicle.parts import Vehicle


class Suspension:
    """Base of every suspension type; a type module holds one instance, ``SUSPENSION``."""

    name: ClassVar[str]
    truck_axle: ClassVar[bool] = False  # may be a truck's [[axles]] suspension
    #: the springs' own law: (sub-table of the axle, its parameters' dataclass, whether the type needs it)
    law: ClassVar[tuple[str, type, bool] | None] = None
    #: whether a corner's force law measured from the data (rig/diagnosis/rig_test/force_laws.py: the wheel's
    #: equilibrium, its suspension force against its own travel) describes this suspension's corner
    corner_law: ClassVar[bool] = True
    #: a truck axle's keys only this type reads (a beam axle's spring_track): written for it alone
    own_keys: ClassVar[tuple[str, ...]] = ()

    def law_rate(self, law: ElementValues | None) -> float | None:
        """The spring rate (N/m) the springs' own law gives at design, in place of the axle's ``spring_rate`` (an air
        spring's, linearised), or None: the axle's ``spring_rate`` is required."""
        return None

    def complete_axle(self, values: dict, label: str) -> dict:
        """A truck axle's values (``[[axles]]`` keys) with this type's defaults filled in; ValueError names a missing
        key (``label``: the axle, as messages name it)."""
        return values

    def build_corner(self, car: mujoco.MjSpec, vehicle: Vehicle, corner: str) -> None:
        """Build (or fill in the template's) corner at its station, with the axle's rates at the wheel."""
        raise NotImplementedError

    def linkage_joints(self, vehicle: Vehicle, corner: str) -> tuple[str, ...]:
        """Joints inside the corner's linkage (kept at design when the static solver presses the car down)."""
        return ()

    def adjust_sprung(self, vehicle: Vehicle, corner: str, mass: float, com: np.ndarray, inertia: np.ndarray
                      ) -> tuple[float, np.ndarray, np.ndarray]:
        """The sprung body's mass (kg), CG offset (m) and inertia (3 x 3 about the CG, kg m^2) with this corner."""
        return mass, com, inertia
