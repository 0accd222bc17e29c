"""``top_mount_compliance``: the damper acts through a top-mount bushing in series.

    [top_mount_compliance.front]   # N/m, bushing in series with the damper
    rate = 400000.0

Realised as a top-mount body on a vertical slide joint (stiffness: the bushing's rate) carrying the
damper's upper end; its mass comes off the sprung mass (it moves with the body at low frequency). A real mount is
light, and the mount's inertia in the band changes what the body feels (a damper through a massless bushing lags
its rate by c / k, a Maxwell element); the mass is the least that keeps the damper's pole on the mount, c / m,
RK4-stable at the largest physics step with room for a rebound coefficient 1.6 times the axle's
(``MOUNT_STEPS``, rig/elements/top_mount.py): 2.4 kg behind 3959 N s/m, 0.8 kg behind 1313 N s/m (it was 5 kg, whose
inertia alone misses a massless bushing by a held-out TDDI of 0.007 on proton_x, against 0.002).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from rig.causes._base import AxleCause, FitParameter, Shape, axles_of
from rig.elements.parameters import param
from rig.elements.tendons import damper_of, damper_tendon
from rig.elements.top_mount import PHYSICS_STEP, mount_mass

MOUNT_MODE_STEP = 2.0  # the fit's stiffest mount: its mode's omega times the physics step (RK4 is stable to 2.8)


@dataclass(frozen=True)
class TopMountCompliance:
    rate: float = field(metadata=param("N/m", 1e4, 2e6, "bushing rate in series with the damper"))


class _TopMountCompliance(AxleCause):
    name = "top_mount_compliance"
    damper_line = "mount"
    damper_part = "series"
    subsystem = "car"
    linear = True
    layouts = ("full", "quarter")  # a strut's top mount: a truck's beam axles have none
    values = TopMountCompliance
    order = 10  # re-routes the damper before other causes change its law
    meaning = "damper in series with a top-mount bushing stiffness"
    signature = ("damping falls off at high frequency: the residual grows above wheel hop with a phase lag that "
                 "follows the bushing's stiffness, atan(2 pi f c / k)")
    evidence = (Shape.FORCE_LAGS,)
    fine_step = True  # the mount's mass is sized to the physics step

    def adjust_sprung(self, vehicle, mass, com, inertia):
        mounts = sum(mount_mass(vehicle.axle(c).damping) for c in vehicle.corners if self.at(vehicle, c) is not None)
        return mass - mounts, com, inertia

    def build(self, car, vehicle):
        for corner in vehicle.corners:
            mount = self.at(vehicle, corner)
            if mount is not None:
                _mount(car, corner, mount, mount_mass(vehicle.axle(corner).damping))

    def fit_parameters(self, vehicle, hints=None):
        """One bushing rate for every axle, started from the force lag the measured corner laws show (a damper c
        through a bushing k lags its rate by c / k), where the data resolve one; no stiffer than keeps the lightest
        mount's mode RK4-stable (a lab bench's 0.2 kg mount on 2e6 N/m is not; a car's are, unchanged)."""
        lags = (hints or {}).get("axle_lag_s") or {}
        start = np.mean([vehicle.axle_named(a).damping / lag for a, lag in lags.items() if lag > 0]) if lags else 1.5e6
        lightest = min(mount_mass(vehicle.axle_named(a).damping) for a in axles_of(vehicle))
        high = min(2e6, lightest * (MOUNT_MODE_STEP / PHYSICS_STEP) ** 2)
        return [FitParameter("rate", float(np.clip(start, 3e4, high)), 3e4, high,
                             lambda v, k: self.on_every_axle(v, lambda a: TopMountCompliance(k)), unit="N/m")]

    def hidden(self, truth, rng):
        return self.on_every_axle(truth, lambda a: TopMountCompliance(rng.uniform(1.5e5, 3.5e5)))


def _mount(car, corner: str, mount: TopMountCompliance, mass: float) -> None:
    """The mount body on its bushing, and the damper's upper end moved from the body to it."""
    import mujoco

    top = car.body("body").add_body(name=f"{corner}/top_mount", pos=list(car.site(f"{corner}/body").pos))
    top.add_joint(name=f"{corner}/top_mount", type=mujoco.mjtJoint.mjJNT_SLIDE, axis=[0, 0, 1], stiffness=mount.rate)
    top.mass, top.ipos, top.inertia, top.explicitinertial = mass, [0, 0, 0], [1e-4] * 3, True
    top.add_site(name=f"{corner}/top_mount")
    old = damper_of(car, corner)  # the damper's upper end moves from the body to the mount
    damping = np.array(old.damping).tolist()
    if old.name == f"{corner}/damper":
        car.delete(old)
    else:  # the spring's line: the spring stays
        old.damping = [0.0, 0.0, 0.0]
    damper_tendon(car, corner, f"{corner}/top_mount", damping)


CAUSE = _TopMountCompliance()
