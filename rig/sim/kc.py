"""Kinematics & compliance tests on the rig (``rig kc``, contract: docs/contracts.md): body held, wheels moved
quasi-statically.

The car's MJCF model (rig/vehicle/mjcf.py) with its body held at design (stiff springs on its joints) and its wheels
on the post pans through their tyres. The pans float in x and y as a K&C rig's pads do (they follow the hub, so the
tyres carry vertical load only), and the wheels are clamped to them (a tyre may pull where the spring alone would
let the wheel droop). Each sweep point is a static equilibrium, solved, not simulated: Newton's method on the
accelerations of the car's joints (all zero: zero force on each) and on the pans' heights, which set each wheel's
travel to its target. Forces and moments at the contact patches are applied loads. In the kinematic tests (travel,
roll, steer) the steering rack is held where the test puts it (infinitely stiff steering); in the compliance tests
(lateral, longitudinal, aligning) the steering wheel is held at centre and the rack is compliant by its
``rack_rate``.

Tests and their sweep (first column of ``kc.csv``): ``travel`` parallel wheel travel (m, bump +); ``roll`` the
body's roll angle (deg; positive right-handed about x, forward: the left wheels rebound by track/2 x tan(roll) and
the right ones bump by as much); ``steer`` the rack (m, positive to the left); ``lateral`` a force along +y (to the
left) at every contact patch (N); ``longitudinal`` along +x (forward) (N); ``aligning`` a moment about +z at every
contact patch (N m). Wheels not swept stay at design travel.

Per point and corner: the alignment (rig/vehicle/suspensions/geometry.py), the motion ratio (spring compression per
wheel travel) and the wheel rate (vertical contact-patch force per travel) from +-``PERTURBATION`` of parallel travel
about the point, the wheel load, and per axle the roll centre's height above the contact patches: the intersection,
in the front view, of the lines through each contact patch perpendicular to that patch's motion with travel
(through the wheel's instant centre). Compliance tests add compliance steer and camber (toe and camber per kN,
or per kN m). Vertical corners have design = static ride height; linkage corners their hardpoints' design.
"""

from __future__ import annotations

import mujoco
import numpy as np

from rig.elements.tendons import FORCE_CAP
from rig.io.kc_record import SWEEPS, TESTS, KcResult
from rig.vehicle.mjcf import build_model, build_spec
from rig.vehicle.statics import settle
from rig.vehicle.suspensions import kinematics_of, suspension_of
from rig.vehicle.suspensions.geometry import alignment
from rig.vehicle.suspensions.hardpoints import KinematicsError
from rig.vehicle.suspensions.linkage import Linkage, corner_axle, corner_side
from rig.vehicle.vehicle_file import Vehicle

COMPLIANCE_TESTS = ("lateral", "longitudinal", "aligning")
PERTURBATION = 5e-4  # m of parallel travel about each point for the motion ratio, wheel rate and roll centre
HELD_RACK_RATE = 1e11  # N/m: a held rack's stiffness (it stays within ~1e-9 m of where the test puts it)
HELD_BODY_RATE = 1e13  # N/m, N m/rad: the body's joints' stiffness (it stays within ~1e-9 m of design)
_STEP_TOLERANCE = 1e-9  # m (rad): a Newton step this small ends the solve
_TRAVEL_TOLERANCE = 1e-11  # m
_FD_STEP = 1e-7  # m (rad)
_BODY_JOINTS = ("car.heave", "car.pitch", "car.roll")


class KcError(KinematicsError):
    """A K&C test that cannot be run (no steering to sweep, a sweep beyond the linkage's reach, no equilibrium)."""


class KcRig:
    """The car held on the K&C rig: a compiled model with the body welded at design, ready for static solves."""

    def __init__(self, vehicle: Vehicle):
        if not vehicle.layout_type.pitches_and_rolls:
            raise KcError(f"{vehicle.name}: the K&C rig takes a full car (layout 'full')")
        self.vehicle = vehicle
        self.corners = vehicle.corners
        static = settle(build_model(vehicle, rate=1000.0))
        spec = build_spec(vehicle, "servo")
        for name in _BODY_JOINTS:  # the body held at design: stiff springs on its joints (which causes may use)
            spec.joint(name).stiffness = [HELD_BODY_RATE, 0.0, 0.0]
        for corner in self.corners:  # floating pads: they follow the hub in x and y (no lateral load on the tyres)
            for axis, label in ((1.0, 0.0, 0.0), "x"), ((0.0, 1.0, 0.0), "y"):
                spec.body(f"{corner}/post").add_joint(name=f"{corner}/pad_{label}", type=mujoco.mjtJoint.mjJNT_SLIDE,
                                                      axis=list(axis))
        for corner in self.corners:  # the wheels are clamped to the pads: the tyres may pull
            spec.actuator(f"{corner}/tyre").forcerange = [-FORCE_CAP, FORCE_CAP]
        self.model = spec.compile()
        self.data = mujoco.MjData(self.model)
        model = self.model
        posts = [model.joint(f"{c}/post") for c in self.corners]
        self.post_qpos = np.array([int(j.qposadr[0]) for j in posts])
        post_dofs = np.array([int(j.dofadr[0]) for j in posts])
        pads = [model.joint(f"{c}/pad_{label}") for c in self.corners for label in "xy"]
        self.pad_qpos = np.array([int(j.qposadr[0]) for j in pads]).reshape(-1, 2)
        self.pad_base = np.array([model.body(f"{c}/post").pos[:2] for c in self.corners])
        self.hub_sites = np.array([model.site(f"car.{c}/hub").id for c in self.corners])
        self.free = np.setdiff1d(np.arange(model.nv), [*post_dofs, *(int(j.dofadr[0]) for j in pads)])
        self.free_qpos = model.jnt_qposadr[model.dof_jntid[self.free]]
        self.state = model.qpos0.copy()
        self._jacobian: np.ndarray | None = None  # the last solve's, for the next (``solve``)
        self.racks = {axle: model.joint(f"car.{axle}/rack").id for axle in ("front", "rear")
                      if mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, f"car.{axle}/rack") >= 0}
        self.rack_rates = {axle: float(model.jnt_stiffness[j]) for axle, j in self.racks.items()}
        self.hold_racks(0.0)
        self.length_adr = np.array([self._sensor(f"car.{c}/suspension_length") for c in self.corners])
        self.load_adr = np.array([self._sensor(f"{c}/tyre_force") for c in self.corners])
        self.wheel_ids = np.array([model.body(f"car.{c}/wheel").id for c in self.corners])
        self.laser_adr = {model.sensor(k).name.removeprefix("car."): int(model.sensor_adr[k])
                          for k in range(model.nsensor) if model.sensor(k).type == mujoco.mjtSensor.mjSENS_RANGEFINDER}
        mujoco.mj_forward(model, self.data)
        design = self.data.sensordata[self.length_adr].copy()
        linkages = [isinstance(suspension_of(vehicle, c), Linkage) for c in self.corners]
        self.reference_length = np.where(linkages, design, static.suspension_length)
        self.load = np.zeros((len(self.corners), 6))  # force, moment at each contact patch (world)
        self.solve(self.reference_length - static.suspension_length)  # the static ride height
        self._set_static_references()
        self.solve(np.zeros(len(self.corners)))
        self.design_state = self.state.copy()
        self.design_wheels = self._wheel_poses()[0]
        self.design_centres = np.array([
            kinematics_of(vehicle, c).point("wheel_centre", corner_side(c)) if linkage else centre
            for c, linkage, centre in zip(self.corners, linkages, self.design_wheels)])

    def _sensor(self, name: str) -> int:
        return int(self.model.sensor_adr[self.model.sensor(name).id])

    def _set_static_references(self) -> None:
        """Causes' references defined at static ride height (bump stop contact, ...), set in this model."""
        from rig.causes import CAUSES

        for cause in CAUSES.values():
            if cause.present(self.vehicle):
                cause.at_static_ride_height(self.model, self.data, self.vehicle)

    # ---- statics -----------------------------------------------------------------------------------------
    def hold_racks(self, rack: float | None) -> None:
        """Hold every steering rack at ``rack`` m (to the left), or leave them on their own stiffness with the
        steering wheel at centre (None)."""
        for axle, joint in self.racks.items():
            self.model.jnt_stiffness[joint] = self.rack_rates[axle] if rack is None else HELD_RACK_RATE
            self.model.qpos_spring[self.model.jnt_qposadr[joint]] = 0.0 if rack is None else rack
            if rack is not None:
                self.state[self.model.jnt_qposadr[joint]] = rack

    def travel(self) -> np.ndarray:
        """Each wheel's travel from design (m, bump +): the hub's rise relative to the body site."""
        return self.reference_length - self.data.sensordata[self.length_adr]

    def _residual(self, x: np.ndarray, target: np.ndarray) -> np.ndarray:
        data = self.data
        data.qpos[:] = self.state
        data.qpos[self.free_qpos] = x[:self.free.size]
        data.qpos[self.post_qpos] = x[self.free.size:]
        data.qvel[:] = 0.0
        mujoco.mj_kinematics(self.model, data)
        data.qpos[self.pad_qpos] = data.site_xpos[self.hub_sites, :2] - self.pad_base
        if np.any(self.load):
            self._apply_loads()
        else:  # no load (the last solve's may still be there)
            data.xfrc_applied[:] = 0.0
        mujoco.mj_forward(self.model, data)
        return np.concatenate([data.qacc[self.free], self.travel() - target])

    def solve(self, target: np.ndarray, iterations: int = 30) -> None:
        """Static equilibrium with each wheel at ``target`` travel (m), from the last solution: Newton's method with a
        finite-difference Jacobian, until a step moves no joint by more than STEP_TOLERANCE (the accelerations then
        sit at the floor of the differences, ~1e-9 m/s^2 on the links). The last solve's Jacobian is tried first
        (a chord iteration: a sweep's neighbouring points have nearly the same one) and made anew when a step does
        not halve the one before."""
        x = np.concatenate([self.state[self.free_qpos], self.state[self.post_qpos]])
        value = self._residual(x, target)
        jacobian, fresh, last = self._jacobian, False, np.inf
        for _ in range(iterations):
            if jacobian is None:
                jacobian, fresh = self._finite_differences(x, value, target), True
            try:
                step = np.linalg.solve(jacobian, -value)
            except np.linalg.LinAlgError:
                break
            x = x + step
            value = self._residual(x, target)
            size = np.max(np.abs(step))
            if size < _STEP_TOLERANCE and np.max(np.abs(value[self.free.size:])) < _TRAVEL_TOLERANCE:
                self.state, self._jacobian = self.data.qpos.copy(), jacobian
                return
            if not fresh and size > 0.5 * last:
                jacobian = None
            last = size
        self._jacobian = None
        raise KcError(f"{self.vehicle.name}: no static equilibrium on the K&C rig at travel "
                      f"{np.round(target * 1e3, 2).tolist()} mm (largest residual {np.max(np.abs(value)):.3g})")

    def _finite_differences(self, x: np.ndarray, value: np.ndarray, target: np.ndarray) -> np.ndarray:
        jacobian = np.empty((x.size, x.size))
        for j in range(x.size):
            shifted = x.copy()
            shifted[j] += _FD_STEP
            jacobian[:, j] = (self._residual(shifted, target) - value) / _FD_STEP
        return jacobian

    # ---- measured quantities -----------------------------------------------------------------------------
    def _wheel_poses(self) -> tuple[np.ndarray, np.ndarray]:
        """Wheel centres (axle frame, m) and rotation matrices of the wheel bodies (corners, 3, 3)."""
        centres = self.data.xpos[self.wheel_ids] - self._axle_origins()
        return centres, self.data.xmat[self.wheel_ids].reshape(-1, 3, 3)

    def _axle_origins(self) -> np.ndarray:
        return np.array([[self.vehicle.corner_position(c)[0], 0.0, 0.0] for c in self.corners])

    def patches(self) -> np.ndarray:
        """Contact patches (axle frame, m): below each wheel centre in the wheel plane at the loaded radius."""
        centres, turns = self._wheel_poses()
        outboard = turns[:, :, 1] * np.array([corner_side(c) for c in self.corners])[:, None]
        down = np.array([0.0, 0.0, -1.0]) + outboard[:, 2:3] * outboard
        radius = self.design_centres[:, 2:3]  # the loaded radius: the design wheel centre's height
        return centres + radius * down / np.linalg.norm(down, axis=1, keepdims=True)

    def patches_on_wheels(self) -> np.ndarray:
        """The contact patches now, in each wheel body's frame (m): the wheels' material points that are there."""
        centres, turns = self._wheel_poses()
        return np.einsum("nji,nj->ni", turns, self.patches() - centres)

    def material_points(self, local: np.ndarray) -> np.ndarray:
        """Points fixed to the wheels (``local``: in each wheel body's frame, m) where they are now (axle frame)."""
        centres, turns = self._wheel_poses()
        return centres + np.einsum("nij,nj->ni", turns, local)

    def _apply_loads(self) -> None:
        patches = self.patches() + self._axle_origins()
        xfrc = self.data.xfrc_applied
        xfrc[:] = 0.0
        for i, body in enumerate(self.wheel_ids):
            force, moment = self.load[i, :3], self.load[i, 3:]
            xfrc[body, :3] = force
            xfrc[body, 3:] = moment + np.cross(patches[i] - self.data.xipos[body], force)

    def measure(self) -> dict[str, np.ndarray]:
        """The corners' alignment and load at the current equilibrium (per corner arrays, SI)."""
        centres, turns = self._wheel_poses()
        out = {"travel": self.travel(), "wheel_load": self.data.sensordata[self.load_adr].copy()}
        bottoms, tops = [], []
        for i, corner in enumerate(self.corners):
            suspension = suspension_of(self.vehicle, corner)
            if isinstance(suspension, Linkage):
                ends = [self.data.site(f"car.{corner}/{name}").xpos - self._axle_origins()[i]
                        for name in suspension.kingpin]
            else:
                ends = [centres[i], centres[i] + [0.0, 0.0, 0.1]]
            bottoms.append(ends[0])
            tops.append(ends[1])
        for i, corner in enumerate(self.corners):
            aligned = alignment(turns[i, :, 1], centres[i], bottoms[i], tops[i], corner_side(corner),
                                self.design_centres[i])
            for name, value in aligned.__dict__.items():
                if name != "travel":
                    out.setdefault(name, np.empty(len(self.corners)))[i] = value
        out["spring_length"] = np.array([self.data.ten_length[self._spring_tendon(c)] for c in self.corners])
        return out

    def _spring_tendon(self, corner: str) -> int:
        for name in (f"car.{corner}/spring_line", f"car.{corner}/suspension"):
            index = mujoco.mj_name2id(self.model, mujoco.mjtObj.mjOBJ_TENDON, name)
            if index >= 0:
                return index
        raise KcError(f"{corner} has no spring")



def run_kc(vehicle: Vehicle, test: str, half_range: float | None = None, steps: int = 41,
           rig: KcRig | None = None) -> KcResult:
    """Run one K&C ``test`` over -``half_range``..+``half_range`` (SI; default per test) in ``steps`` points."""
    if test not in TESTS:
        raise KcError(f"unknown K&C test {test!r} (tests: {', '.join(TESTS)})")
    if steps < 3:
        raise KcError(f"a K&C sweep needs at least 3 steps, got {steps}")
    half_range = SWEEPS[test][2] if half_range is None else float(half_range)
    if not half_range > 0:
        raise KcError(f"the K&C range must be positive, got {half_range}")
    return sweep_kc(rig or KcRig(vehicle), test, np.linspace(-half_range, half_range, steps))


def sweep_kc(rig: KcRig, test: str, sweep: np.ndarray, derivatives: bool = True) -> KcResult:
    """The K&C ``test`` at the sweep points ``sweep`` (SI, increasing), solved outward from the one nearest zero;
    without ``derivatives`` the motion ratio, wheel rate and roll centre are left out (a fit's quicker sweep)."""
    vehicle = rig.vehicle
    if test == "steer" and not rig.racks:
        raise KcError(f"{vehicle.name} has no steering rack to sweep (no steered linkage axle)")
    sweep = np.asarray(sweep, float)
    _check_reach(vehicle, test, sweep)
    points: list[dict] = [{}] * sweep.size
    states = np.empty((sweep.size, rig.model.nq))
    middle = int(np.argmin(np.abs(sweep)))
    for order in (range(middle, sweep.size), range(middle - 1, -1, -1)):
        rig.state = rig.design_state.copy()
        for k in order:
            points[k] = _point(rig, test, sweep[k], derivatives)
            states[k] = rig.state
    curves = {}
    for i, corner in enumerate(rig.corners):
        for quantity in points[0]:
            if quantity not in ("roll_centre_height", "lasers"):
                curves[f"{corner}/{quantity}"] = np.array([p[quantity][i] for p in points])
    for name in points[0]["lasers"]:
        curves[name] = np.array([p["lasers"][name] for p in points])
    if derivatives:
        for j, axle in enumerate(("front", "rear")):
            curves[f"{axle}/roll_centre_height"] = np.array([p["roll_centre_height"][j] for p in points])
    if test in COMPLIANCE_TESTS and sweep.size > 1:
        for corner in rig.corners:
            for quantity, angle in (("compliance_steer", "toe"), ("compliance_camber", "camber")):
                curves[f"{corner}/{quantity}"] = np.gradient(curves[f"{corner}/{angle}"], sweep)  # rad/N (N m)
    return KcResult(vehicle.name, test, SWEEPS[test][0], sweep, rig.corners, curves, states)


def _targets(rig: KcRig, test: str, value: float) -> np.ndarray:
    """Each wheel's travel (m) at a sweep point: the sweep in parallel travel, +-track/2 tan(roll) in roll."""
    if test == "travel":
        return np.full(len(rig.corners), value)
    if test != "roll":
        return np.zeros(len(rig.corners))
    tracks = np.array([rig.vehicle.track_front if c[0] == "F" else rig.vehicle.track_rear for c in rig.corners])
    sides = np.array([corner_side(c) for c in rig.corners])
    return -sides * tracks / 2 * np.tan(value)


def _point(rig: KcRig, test: str, value: float, derivatives: bool = True) -> dict:
    """Solve one sweep point and measure it, with the +-PERTURBATION parallel-travel derivatives."""
    rig.hold_racks(value if test == "steer" else None if test in COMPLIANCE_TESTS else 0.0)
    rig.load[:] = 0.0
    column = {"lateral": 1, "longitudinal": 0, "aligning": 5}.get(test)
    if column is not None:
        rig.load[:, column] = value
    target = _targets(rig, test, value)
    rig.solve(target)
    base_state = rig.state.copy()
    out = rig.measure()
    out["lasers"] = {name: float(rig.data.sensordata[adr]) for name, adr in rig.laser_adr.items()}
    if not derivatives:
        del out["spring_length"]
        return out
    patches = rig.patches_on_wheels()  # the roll centre's lines go through the contact patches of this point
    ends = []
    for sign in (1.0, -1.0):
        rig.solve(target + sign * PERTURBATION)
        ends.append((rig.measure(), rig.material_points(patches)))
    rig.state = base_state
    (plus, plus_patch), (minus, minus_patch) = ends
    span = plus["travel"] - minus["travel"]
    out["motion_ratio"] = -(plus["spring_length"] - minus["spring_length"]) / span
    out["wheel_rate"] = (plus["wheel_load"] - minus["wheel_load"]) / span
    out["roll_centre_height"] = _roll_centres(rig, (plus_patch + minus_patch) / 2,
                                              (plus_patch - minus_patch) / span[:, None])
    del out["spring_length"]
    return out


def _roll_centres(rig: KcRig, patches: np.ndarray, velocities: np.ndarray) -> np.ndarray:
    """Front and rear roll-centre heights (m) above their contact patches from the patches (axle frame) and their
    velocity per travel: the lines through each patch perpendicular to its motion, in the front view, meet there."""
    heights = []
    for left, right in (("FL", "FR"), ("RL", "RR")):
        i, j = rig.corners.index(left), rig.corners.index(right)
        # line k: (y, z) = patch_k + s_k (-v_z, v_y)
        direction = np.array([[-velocities[k, 2], velocities[k, 1]] for k in (i, j)])
        matrix = np.column_stack([direction[0], -direction[1]])
        ground = (patches[i, 2] + patches[j, 2]) / 2
        if abs(np.linalg.det(matrix)) < 1e-12:  # parallel lines (vertical sliders): at the patches' height
            heights.append(0.0)
            continue
        s = np.linalg.solve(matrix, patches[j, 1:] - patches[i, 1:])
        heights.append(patches[i, 2] + s[0] * direction[0, 1] - ground)
    return np.array(heights)


def _check_reach(vehicle: Vehicle, test: str, sweep: np.ndarray) -> None:
    """Refuse a travel, roll or rack sweep beyond the linkage's reach, naming the hardpoint that cannot follow."""
    for corner in vehicle.corners:
        suspension = suspension_of(vehicle, corner)
        if not isinstance(suspension, Linkage):
            continue
        kinematics, side = kinematics_of(vehicle, corner), corner_side(corner)
        track = vehicle.track_front if corner[0] == "F" else vehicle.track_rear
        travel = {"travel": sweep, "roll": -side * track / 2 * np.tan(sweep)}.get(test, 0.0 * sweep)
        rack = sweep if test == "steer" and kinematics.steered else 0.0 * sweep
        try:
            suspension.solve(kinematics, travel, rack, side)
        except KinematicsError as err:
            raise KcError(f"{vehicle.name} {corner} ({corner_axle(corner)} axle), {test} sweep to "
                          f"+-{np.max(np.abs(sweep)):g}: {err}") from None
