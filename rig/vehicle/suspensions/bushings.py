"""Bushings at the joints of a linkage: ``[<axle>.bushings.<joint>]`` tables (docs/kinematics.md), each joint its own.

A table gives a joint's rates: ``radial`` and ``axial`` (N/m) in translation, ``conical`` and ``torsional``
(N m/rad) in rotation, and the matching damping (``radial_damping``, ``axial_damping`` in N s/m,
``conical_damping``, ``torsional_damping`` in N m s/rad). A translational rate left out is rigid, a rotational one
free: a joint without a table is a ball joint (a spherical bearing) rigid in translation, and two of them on an
arm's pivots make its hinge. As the source paper ("Validation of a Suspension Model and its Elastic Behaviour
Demonstrated at the Formula Student Race Car of the University Duisburg-Essen") recalls, the elasticity of the
parts may be lumped into the bearings.

Each joint's axis (the axial direction; the radial ones are across it, alike in every direction):
- an arm's pivot (``lower_front``, ``lower_rear``, ``upper_front``, ``upper_rear``): the arm's pivot axis;
- a ball joint on the upright (``lower_outer``, ``upper_outer``): the kingpin;
- a strut's top mount (``strut_top``): the strut's axis;
- a tie rod's ends (``tie_rod_inner``, ``tie_rod_outer``) and a pushrod's (``pushrod_inner``, ``pushrod_outer``):
  the rod;
- a rocker's pivot (``rocker_pivot``): the rocker's axis.
Conical and torsional rates belong to pivots (an arm's, a rocker's): the other joints are ball joints, which turn
freely, and a rate there is refused.

Realised in the MJCF (rig/vehicle/suspensions/linkage.py) as joints with these stiffnesses and damping, each
given armature so that its own mode is no faster than 1 / BUSHING_PERIOD (RK4 at 1 ms):
- an arm on two pivots is one rigid body: along its axis its pivots act in parallel (one slide, the sum of the
  axial rates, rigid if either is); its front pivot's radial rates are two slides at the front pivot, its rear
  pivot's two slides of a sleeve on the body joined to the arm's rear pivot by a ``connect``; conical rates are
  moments on the arm's tilt, the same at either pivot, so both act on two hinges about the front pivot (present
  whenever a radial rate lets the arm tilt); the torsional rates add to the arm's hinge, as the parasitic rate does;
- a ball joint's rates are three slides (axial, two radial) between the joint's two parts: before the upright's
  (or strut's) hinges where one part hangs from the other, else on a small body that carries the joint's site.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import mujoco
import numpy as np

from rig.elements.bushing_rates import RANGES, RATES, ROTATION, TRANSLATION, UNITS
from rig.vehicle.suspensions.hardpoints import Kinematics, KinematicsError

DAMPINGS = tuple(f"{rate}_damping" for rate in RATES)
MAX_DAMPING = 1e6
BUSHING_PERIOD = 1e-3  # s: armature so that a bushing's own mode is no faster than 1 / this
BUSHING_MASS = 1e-3    # kg: a small body carrying a bushed joint's site (MuJoCo's moving bodies need mass)
#: kg: a free slide's armature: a ``connect`` to a light body is soft (MuJoCo's constraint impedance scales with the
#: bodies' inverse mass: 4e10 N/m per kg here), and this keeps it ~1e3 stiffer than the bushings
FREE_SLIDE_ARMATURE = 1.0
PIVOTS = {"lower_front": "lower", "lower_rear": "lower", "upper_front": "upper", "upper_rear": "upper"}


@dataclass(frozen=True)
class Bushing:
    """One joint's rates (N/m, N m/rad; inf: rigid in translation) and damping (N s/m, N m s/rad)."""

    radial: float = math.inf
    axial: float = math.inf
    conical: float = 0.0
    torsional: float = 0.0
    radial_damping: float = 0.0
    axial_damping: float = 0.0
    conical_damping: float = 0.0
    torsional_damping: float = 0.0

    def to_table(self) -> dict:
        """The TOML table: the compliant rates and the damping given."""
        out = {k: getattr(self, k) for k in TRANSLATION if math.isfinite(getattr(self, k))}
        out.update({k: getattr(self, k) for k in ROTATION + DAMPINGS if getattr(self, k) > 0})
        return out

    def damping(self, rate: str) -> float:
        return getattr(self, f"{rate}_damping")


def joints_of(kinematics: Kinematics) -> dict[str, str]:
    """The joints a table may name on this linkage -> their kind: 'pivot' (conical and torsional rates allowed)
    or 'ball'."""
    points = kinematics.points
    out = {name: "pivot" for name in PIVOTS if name in points}
    out.update({name: "ball" for name in ("lower_outer", "upper_outer", "strut_top", "tie_rod_inner",
                                            "tie_rod_outer", "pushrod_inner", "pushrod_outer") if name in points})
    if "rocker_pivot" in points:
        out["rocker_pivot"] = "pivot"
    return out


def parse_bushings(table: object, where: str, axle: str, kinematics: Kinematics) -> dict[str, Bushing]:
    """``[<axle>.bushings]``: one sub-table per joint, checked against the linkage's joints and the ranges."""
    section = f"[{axle}.bushings]"
    if not isinstance(table, dict):
        raise KinematicsError(f"{where}: {section} must hold one table per joint, [{axle}.bushings.<joint>]")
    if kinematics.bushing_rate is not None:
        raise KinematicsError(f"{where}: {section} and [{axle}.kinematics] bushing_rate both give the arms' "
                              f"compliance: give each joint its table and leave bushing_rate out")
    joints = joints_of(kinematics)
    out = {}
    for joint, rates in table.items():
        name = f"[{axle}.bushings.{joint}]"
        if joint not in joints:
            raise KinematicsError(f"{where}: {name}: not a joint of the {axle} {kinematics.type} (joints: "
                                  f"{', '.join(joints)})")
        if not isinstance(rates, dict) or not rates:
            raise KinematicsError(f"{where}: {name} must be a table of rates ({', '.join(RATES)}) and damping")
        unknown = sorted(set(rates) - set(RATES + DAMPINGS))
        if unknown:
            raise KinematicsError(f"{where}: {name} unknown key(s) {', '.join(unknown)} (known: "
                                  f"{', '.join(RATES + DAMPINGS)})")
        turning = [k for k in ROTATION + DAMPINGS[2:] if k in rates]
        if joints[joint] == "ball" and turning:
            raise KinematicsError(f"{where}: {name} {', '.join(turning)}: {joint} is a ball joint, which turns "
                                  f"freely; conical and torsional rates belong to pivots ({', '.join(PIVOTS)})")
        values = {key: _number(rates[key], f"{where}: {name} {key}", *RANGES[key], UNITS[key])
                  for key in RATES if key in rates}
        values.update({key: _number(rates[key], f"{where}: {name} {key}", 0.0, MAX_DAMPING, "N s/m or N m s/rad")
                       for key in DAMPINGS if key in rates})
        out[joint] = Bushing(**values)
    return out


def _number(value: object, where: str, low: float, high: float, unit: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise KinematicsError(f"{where} must be a number in {unit}, got {value!r}")
    if not low <= value <= high:
        raise KinematicsError(f"{where} = {value} {unit} is outside the plausible range {low:g}..{high:g} {unit}")
    return float(value)


def with_rates(kinematics: Kinematics, rates: dict[tuple[str, str], float]) -> Kinematics:
    """These kinematics with joints' rates replaced: (joint, rate name) -> value (a joint without a table gets one)."""
    bushings = dict(kinematics.bushings)
    for (joint, rate), value in rates.items():
        bushings[joint] = dataclasses.replace(bushings.get(joint, Bushing()), **{rate: float(value)})
    return dataclasses.replace(kinematics, bushings=bushings)


def perpendiculars(axis: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Two unit vectors perpendicular to ``axis`` and to each other."""
    axis = np.asarray(axis, float) / np.linalg.norm(axis)
    first = np.cross(axis, [1.0, 0.0, 0.0] if abs(axis[0]) < 0.9 else [0.0, 1.0, 0.0])
    first /= np.linalg.norm(first)
    return first, np.cross(axis, first)


def joint_axis(kinematics: Kinematics, joint: str, side: int) -> np.ndarray:
    """A joint's axis at design (unit, axle frame; module docstring)."""
    point = kinematics.point
    pairs = {"lower_outer": ("lower_outer", "upper_outer" if "upper_outer" in kinematics.points else "strut_top"),
             "upper_outer": ("lower_outer", "upper_outer"), "strut_top": ("strut_lower", "strut_top"),
             "tie_rod_inner": ("tie_rod_inner", "tie_rod_outer"), "tie_rod_outer": ("tie_rod_inner", "tie_rod_outer"),
             "pushrod_inner": ("pushrod_outer", "pushrod_inner"), "pushrod_outer": ("pushrod_outer", "pushrod_inner"),
             "rocker_pivot": ("rocker_pivot", "rocker_axis")}
    if joint in PIVOTS:
        arm = PIVOTS[joint]
        pairs[joint] = (f"{arm}_front", f"{arm}_rear")
    start, end = pairs[joint]
    direction = point(end, side) - point(start, side)
    return direction / np.linalg.norm(direction)


@dataclass(frozen=True)
class Slide:
    """A bushing's slide joint: name suffix, axis (unit, the carrying body's frame at design), rate (N/m) and
    damping (N s/m)."""

    label: str
    axis: np.ndarray
    rate: float
    damping: float
    armature: float | None = None  # kg; None: rate x BUSHING_PERIOD^2

    @property
    def inertia(self) -> float:
        return self.rate * BUSHING_PERIOD**2 if self.armature is None else self.armature


def translation_slides(bushing: Bushing | None, axis: np.ndarray, radial: bool = True, axial: bool = True
                       ) -> list[Slide]:
    """The slides of a joint's compliant translations: along its axis and the two radial directions (those
    asked for and not rigid)."""
    if bushing is None:
        return []
    out = []
    if axial and math.isfinite(bushing.axial):
        out.append(Slide("axial", axis, bushing.axial, bushing.axial_damping))
    if radial and math.isfinite(bushing.radial):
        out += [Slide(f"radial_{k + 1}", direction, bushing.radial, bushing.radial_damping)
                for k, direction in enumerate(perpendiculars(axis))]
    return out


@dataclass(frozen=True)
class ArmCompliance:
    """An arm's two pivots' bushings as the MJCF realises them (module docstring): slides at the front pivot,
    slides of the rear sleeve, conical hinges about the front pivot (rate, damping), the hinge's torsional rate and
    damping."""

    front: list[Slide]
    rear: list[Slide]
    conical: tuple[float, float] | None
    torsional: tuple[float, float]

    @property
    def closed_by_connect(self) -> bool:
        """Whether the arm's rear pivot is a ``connect`` (the arm can tilt: a radial rate is compliant)."""
        return self.conical is not None


def arm_compliance(kinematics: Kinematics, front: str, rear: str, side: int) -> ArmCompliance:
    """The realisation of the bushings of an arm's pivots ``front`` and ``rear`` (joint names)."""
    axis = joint_axis(kinematics, front, side)
    first, second = kinematics.bushings.get(front), kinematics.bushings.get(rear)
    both = [b for b in (first, second) if b is not None]
    slides = []
    if first is not None and second is not None and math.isfinite(first.axial) and math.isfinite(second.axial):
        slides.append(Slide("axial", axis, first.axial + second.axial, first.axial_damping + second.axial_damping))
    slides += translation_slides(first, axis, axial=False)
    rear_slides = translation_slides(second, axis, axial=False)
    tilts = bool(slides and any(s.label.startswith("radial") for s in slides)) or bool(rear_slides)
    conical = (sum(b.conical for b in both), sum(b.conical_damping for b in both)) if tilts else None
    if tilts:  # the tilt about the front pivot moves the rear one along the axis to second order: a free slide
        rear_slides.append(Slide("axial", axis, 0.0, 0.0, FREE_SLIDE_ARMATURE))
    return ArmCompliance(slides, rear_slides, conical,
                         (sum(b.torsional for b in both), sum(b.torsional_damping for b in both)))


def ball_slides(kinematics: Kinematics, joint: str, side: int) -> list[Slide]:
    """The slides of a ball joint's bushing (none without a table)."""
    if joint not in kinematics.bushings:
        return []
    return translation_slides(kinematics.bushings[joint], joint_axis(kinematics, joint, side))


def add_slides(body: mujoco.MjsBody, prefix: str, slides: list[Slide]) -> None:
    """The slides as joints ``<prefix>_<label>`` of ``body``, with their rates, damping and armature."""
    for slide in slides:
        body.add_joint(name=f"{prefix}_{slide.label}", type=mujoco.mjtJoint.mjJNT_SLIDE, axis=list(slide.axis),
                       stiffness=[slide.rate, 0.0, 0.0], damping=[slide.damping, 0.0, 0.0],
                       armature=slide.inertia)


def add_conical(body: mujoco.MjsBody, prefix: str, axis: np.ndarray, conical: tuple[float, float]) -> None:
    """Two hinges ``<prefix>_conical_1``/``_2`` across ``axis`` at the body's origin: the arm's tilt."""
    rate, damping = conical
    for k, direction in enumerate(perpendiculars(axis)):
        body.add_joint(name=f"{prefix}_conical_{k + 1}", type=mujoco.mjtJoint.mjJNT_HINGE, axis=list(direction),
                       stiffness=[rate, 0.0, 0.0], damping=[damping, 0.0, 0.0],
                       armature=rate * BUSHING_PERIOD**2)


def bushed_site(parent: mujoco.MjsBody, name: str, pos: np.ndarray, slides: list[Slide], joint: str) -> None:
    """The site ``name`` at ``pos`` of ``parent``: on a small body on the slides (joints ``<joint>_<label>``) when
    the joint is bushed."""
    if not slides:
        parent.add_site(name=name, pos=list(pos))
        return
    body = parent.add_body(name=f"{joint}_bushing", pos=list(pos))
    body.mass, body.ipos, body.inertia, body.explicitinertial = BUSHING_MASS, [0.0] * 3, [1e-9] * 3, True
    add_slides(body, joint, slides)
    body.add_site(name=name, pos=[0.0, 0.0, 0.0])


def joint_names(kinematics: Kinematics, corner: str, side: int, arms: tuple[tuple[str, str, str], ...]) -> list[str]:
    """Every bushing joint of a corner in the MJCF (``arms``: (arm name, front pivot, rear pivot))."""
    names = []
    for arm, front, rear in arms:
        compliance = arm_compliance(kinematics, front, rear, side)
        names += [f"{corner}/{arm if s.label == 'axial' else front}_{s.label}" for s in compliance.front]
        names += [f"{corner}/{rear}_{s.label}" for s in compliance.rear]
        if compliance.conical is not None:
            names += [f"{corner}/{arm}_conical_{k}" for k in (1, 2)]
    for joint, kind in joints_of(kinematics).items():
        if kind == "ball" or joint == "rocker_pivot":
            names += [f"{corner}/{joint}_{s.label}" for s in ball_slides(kinematics, joint, side)]
    if "rocker_pivot" in kinematics.bushings and kinematics.bushings["rocker_pivot"].conical > 0:
        names += [f"{corner}/rocker_conical_{k}" for k in (1, 2)]
    return names
