"""Force elements on tendons between the sprung body and a wheel, in the car's MjSpec: the damper's tendon, a hidden
spring beside the suspension (a stop, a progressive spring's extra), a rate damper clamped to a force range. The
vehicle's suspension types and the causes build from them; all act inside ``mj_step``."""

from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import mujoco

FORCE_CAP = 1e7  # N: the open end of a one-sided (clamped) actuator's force range
PHYSICS_STEP = 1e-3  # s: the models' largest physics step (rig/vehicle/mjcf.py): elements are sized to it


def spring_beside_suspension(car: mujoco.MjSpec, name: str, corner: str, stiffness: list[float]) -> None:
    """A hidden spring tendon from body to hub, MuJoCo's polynomial law f = -(a y + b y^2 + c y^3) on the
    stretch y beyond its reference, with a [0, 1 km] dead band: inactive until ``at_static_ride_height``
    sets the reference from the settled length (``spring_reference``)."""
    tendon = car.add_tendon(name=name)
    tendon.wrap_site(f"{corner}/body")
    tendon.wrap_site(f"{corner}/hub")
    tendon.stiffness = stiffness
    tendon.springlength = [0.0, 1e3]
    tendon.rgba = [0.2, 0.2, 0.2, 0.0]


def spring_reference(model: mujoco.MjModel, data: mujoco.MjData, name: str, below: float = 0.0,
                     dead_band: bool = False, above: float | None = None) -> None:
    """Set a ``spring_beside_suspension`` tendon's reference ``below`` m shorter than its static length:
    a single length (polynomial spring about it) or, with ``dead_band``, the lower end of a dead band; with
    ``above``, a dead band from zero length to ``above`` m longer than static (a spring acting in rebound)."""
    tendon = model.tendon(f"car.{name}").id
    if above is not None:
        model.tendon_lengthspring[tendon] = [0.0, data.ten_length[tendon] + above]
        return
    length = data.ten_length[tendon] - below
    model.tendon_lengthspring[tendon] = [length, 1e3] if dead_band else length


def rate_damper(car: mujoco.MjSpec, name: str, target: str, coefficient: float, force_range: list[float],
                on_joint: bool = False) -> None:
    """An affine actuator F = -coefficient x the rate of ``target`` (a tendon, or a joint with ``on_joint``),
    clamped to ``force_range`` (N)."""
    import mujoco

    actuator = car.add_actuator(name=name, target=target)
    actuator.trntype = mujoco.mjtTrn.mjTRN_JOINT if on_joint else mujoco.mjtTrn.mjTRN_TENDON
    actuator.gainprm[0] = 0.0
    actuator.biastype = mujoco.mjtBias.mjBIAS_AFFINE
    actuator.biasprm[:3] = [0.0, 0.0, -coefficient]
    actuator.forcelimited = mujoco.mjtLimited.mjLIMITED_TRUE
    actuator.forcerange = force_range


def clamped_damper(car: mujoco.MjSpec, corner: str, label: str, coefficient: float, sign: int) -> None:
    """A rate damper on the damper's tendon clamped to one force sign (``sign`` +1: pushes only, -1: pulls only): one
    branch of a piecewise-linear damper."""
    rate_damper(car, f"{corner}/damper_{label}", damper_of(car, corner).name, coefficient,
                [0.0, FORCE_CAP] if sign > 0 else [-FORCE_CAP, 0.0])


def damper_of(car: mujoco.MjSpec, corner: str) -> mujoco.MjsTendon:
    """The tendon that carries the corner's damper: ``<corner>/damper`` where the damper has a line of its own (a top
    mount, a linkage's, a beam axle's), else the suspension's spring line from the body site to the hub, on which a
    vertical corner's damper acts (one tendon fewer to compute at each evaluation: a tenth of a car's physics step).
    Elements that act where the damper does (its asymmetry, ramps, preload) act on this tendon."""
    return car.tendon(f"{corner}/damper") or car.tendon(f"{corner}/suspension")


def damper_tendon(car: mujoco.MjSpec, corner: str, upper_site: str, damping: list[float]) -> None:
    """The damper on a line of its own: a spatial tendon ``<corner>/damper`` from ``upper_site`` to the hub, with
    MuJoCo's polynomial damping f = -(a v + b v|v| + c v^3) (v: extension rate, N s/m, N s^2/m^2, N s^3/m^3)."""
    tendon = car.add_tendon(name=f"{corner}/damper")
    tendon.wrap_site(upper_site)
    tendon.wrap_site(f"{corner}/hub")
    tendon.rgba = [0.3, 0.3, 0.3, 0.0]
    tendon.damping = list(damping)
