"""A vehicle as the model builds it: its axles (``Axle``, both corners of one alike) and the whole (``Vehicle``), what a
vehicle file becomes once read and checked (rig/vehicle/vehicle_file.py, rig/vehicle/truck_file.py)."""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

from rig.elements.frame import Frame
from rig.elements.mounted_body import MountedBody
from rig.elements.parameters import ElementValues
from rig.io.channels import axle_corners, axle_names, corner_axle
from rig.vehicle.layouts import Layout, layout_named
from rig.vehicle.rig_config import RigConfig
from rig.vehicle.suspensions.hardpoints import Kinematics


@dataclass(frozen=True)
class Axle:
    """Per-corner parameters of one axle (both corners alike), at the wheel."""

    unsprung_mass: float
    spring_rate: float
    parasitic_rate: float
    damping: float
    tyre_rate: float
    tyre_damping: float
    kinematics: Kinematics | None = None  # a linkage's hardpoints; None: the vertical slider
    # layout 'truck' (rig/vehicle/truck_file.py): where the axle is and what it is
    position: float = 0.0       # m behind the front axle
    track: float = 0.0          # m between the wheel stations' centres
    tyres: str = "single"       # 'single' or 'dual' (two tyres at each station, dual_spacing apart)
    dual_spacing: float = 0.0   # m between the centres of a station's dual tyres
    suspension: str = ""        # suspension type (rig/vehicle/suspensions/); '' on a car: its kinematics, or vertical
    spring_track: float = 0.0   # m between a beam axle's springs
    damper_track: float = 0.0   # m between a beam axle's dampers
    roll_inertia: float = 0.0   # kg m^2, a beam axle's about its centre
    law: ElementValues | None = None  # the springs' own law (its suspension type's): LeafFriction, AirSpring

    @property
    def suspension_rate(self) -> float:
        """Spring plus parasitic (bushing) rate in N/m: k_s + k_p of Nurhadiyanto's eq. 3.1."""
        return self.spring_rate + self.parasitic_rate


@dataclass(frozen=True)
class Vehicle:
    """A vehicle file, parsed and checked. Lengths in m, masses in kg, rates in N/m, damping in N s/m."""

    name: str
    layout: str
    sprung_mass: float
    front: Axle
    rear: Axle | None
    middle: tuple[Axle, ...] = ()  # a truck's axles between its front and rear axle, front to rear
    wheelbase: float = 0.0
    cg_to_front_axle: float = 0.0
    track_front: float = 0.0
    track_rear: float = 0.0
    cg_height: float = 0.55
    wheel_radius: float = 0.30
    pitch_inertia: float = 0.0
    roll_inertia: float = 0.0
    yaw_inertia: float = 0.0
    rig: RigConfig = field(default_factory=RigConfig)
    extensions: dict = field(default_factory=dict)  # cause -> parameters (rig/causes/)
    source: str = ""
    frame: Frame | None = None            # a truck's flexible frame (rig/elements/frame.py); None: rigid
    cab: MountedBody | None = None        # a truck's cab on its mounts (rig/elements/mounted_body.py)
    driveline: MountedBody | None = None  # a truck's engine and gearbox on their mounts

    @property
    def axles(self) -> tuple[Axle, ...]:
        """The axles front to rear."""
        return (self.front,) if self.rear is None else (self.front, *self.middle, self.rear)

    @property
    def axle_names(self) -> tuple[str, ...]:
        """Their names: ``front``, [``middle`` | ``middle1``, ...], ``rear`` (docs/contracts.md)."""
        return axle_names(len(self.axles))

    @property
    def layout_type(self) -> Layout:
        """What its ``layout`` is (rig/vehicle/layouts/): code asks it, never the name."""
        return layout_named(self.layout)

    @property
    def corners(self) -> tuple[str, ...]:
        per_axle = self.layout_type.corners_per_axle
        return tuple(c for axle in self.axle_names for c in axle_corners(axle)[:per_axle])

    def axle(self, corner: str) -> Axle:
        return self.axle_named(corner_axle(corner))

    def axle_named(self, name: str) -> Axle:
        """The axle called ``name`` (``front``, ``middle``, ``rear``...); ValueError names the vehicle's axles."""
        names = self.axle_names
        if name not in names:
            raise ValueError(f"{self.name} has no {name!r} axle (its axles: {', '.join(names)})")
        return self.axles[names.index(name)]

    def with_axle(self, name: str, axle: Axle) -> Vehicle:
        """This vehicle with axle ``name`` replaced."""
        self.axle_named(name)  # refuses a name the vehicle does not have
        index = self.axle_names.index(name)
        if index == 0:
            return dataclasses.replace(self, front=axle)
        if index == len(self.axle_names) - 1:
            return dataclasses.replace(self, rear=axle)
        middle = list(self.middle)
        middle[index - 1] = axle
        return dataclasses.replace(self, middle=tuple(middle))

    def corner_position(self, corner: str) -> tuple[float, float]:
        """(x, y) of the corner relative to the sprung CG in m: x forward, y left."""
        if not self.layout_type.footprint:
            return 0.0, 0.0
        side = 1 if corner.endswith("L") else -1
        if self.layout_type.axle_list:
            axle = self.axle(corner)
            return self.cg_to_front_axle - axle.position, side * axle.track / 2
        front = corner[0] == "F"
        x = self.cg_to_front_axle if front else self.cg_to_front_axle - self.wheelbase
        track = self.track_front if front else self.track_rear
        return x, side * track / 2
