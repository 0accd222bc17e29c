"""``top_mount_compliance``: the damper acts through a top-mount bushing in series.

    [top_mount_compliance.front]   # N/m, bushing in series with the damper
    rate = 400000.0

Realised as a 5 kg top-mount body on a vertical slide joint (stiffness: the bushing's rate) carrying the
damper's upper end; the 5 kg come off the sprung mass (they move with the body at low frequency), and
keep the mount's mode RK4-stable at 1 ms.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from rig.causes._base import AxleCause, FitParameter, Shape, damper_tendon, param

TOP_MOUNT_MASS = 5.0  # kg taken from the sprung mass per compliant top mount


@dataclass(frozen=True)
class TopMountCompliance:
    rate: float = field(metadata=param("N/m", 1e4, 2e6, "bushing rate in series with the damper"))


class _TopMountCompliance(AxleCause):
    name = "top_mount_compliance"
    subsystem = "car"
    values = TopMountCompliance
    order = 10  # re-routes the damper before other causes change its law
    meaning = "damper in series with a top-mount bushing stiffness"
    signature = ("damping falls off at high frequency: the residual grows above wheel hop with a phase lag that "
                 "follows the bushing's stiffness, atan(2 pi f c / k)")
    evidence = (Shape.FORCE_LAGS,)

    def adjust_sprung(self, vehicle, mass, com, inertia):
        mounts = sum(1 for c in vehicle.corners if self.at(vehicle, c) is not None)
        return mass - TOP_MOUNT_MASS * mounts, com, inertia

    def build_corner(self, car, corner, mount):
        import mujoco

        top = car.body("body").add_body(name=f"{corner}/top_mount", pos=list(car.site(f"{corner}/body").pos))
        top.add_joint(name=f"{corner}/top_mount", type=mujoco.mjtJoint.mjJNT_SLIDE, axis=[0, 0, 1],
                      stiffness=mount.rate)
        top.mass, top.ipos, top.inertia, top.explicitinertial = TOP_MOUNT_MASS, [0, 0, 0], [1e-3] * 3, True
        top.add_site(name=f"{corner}/top_mount")
        old = car.tendon(f"{corner}/damper")  # the damper's upper end moves from the body to the mount
        damping = np.array(old.damping).tolist()
        car.delete(old)
        damper_tendon(car, corner, f"{corner}/top_mount", damping)

    def fit_parameters(self, vehicle, hints=None):
        """One bushing rate for every axle, started from the force lag the measured corner laws show (a damper c
        through a bushing k lags its rate by c / k), where the data resolve one."""
        lags = (hints or {}).get("axle_lag_s") or {}
        start = np.mean([getattr(vehicle, a).damping / lag for a, lag in lags.items() if lag > 0]) if lags else 1.5e6
        return [FitParameter("rate", float(np.clip(start, 3e4, 2e6)), 3e4, 2e6,
                             lambda v, k: self.on_every_axle(v, lambda a: TopMountCompliance(k)), unit="N/m")]

    def hidden(self, truth, rng):
        return self.on_every_axle(truth, lambda a: TopMountCompliance(rng.uniform(1.5e5, 3.5e5)))


CAUSE = _TopMountCompliance()
