"""An independent simulator of a rigid-frame truck on a multi-post rig, written from the equations for the tests.

Neither MuJoCo nor the project's model builder: the frame a rigid body (heave z, pitch theta about +y, roll phi about
+x, about its CG), each beam axle a body in heave and roll, the cab and the driveline bodies in heave, pitch and roll
about their CGs, every force element a vertical line between two points (small angles: a point (x, y) of a body moves
by z - x theta + y phi); per wheel station a servo post (transport delay, first-order command lag, position loop on
the post mass with the static load fed forward), its tyres one-sided springs and dampers. Leaf springs are linear with
Fancher's inter-leaf friction as the Dahl equation dF_f/dt = sigma0 (v - |v| F_f / F_c) on the spring's rate of
extension v; air springs (an axle's, or a cab's mounts) follow the polytropic law itself,
F = ((p0 + p_atm) (V0 / V)^n - p_atm) A, a mount's compressed as its body falls towards the frame. Everything is
measured from the drawn (unloaded) configuration of the vehicle file's geometry; the rest state is found by a root
solve; a fixed-step RK4 in NumPy integrates.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.interpolate import CubicSpline
from scipy.optimize import root

from independent_rig import rk4_samples

G = 9.80665
ATMOSPHERE = 101325.0


@dataclass
class Line:
    """A vertical force element between point rows ``upper`` and ``lower`` (displacement = row @ q)."""

    upper: np.ndarray
    lower: np.ndarray
    kind: str            # 'leaf', 'air', 'damper', 'mount'
    rate: float = 0.0
    damping: float = 0.0
    law: object = None   # the air spring (area, area_slope, volume, pressure, polytropic_index) or leaf friction
    index: int = -1      # the leaf's friction state


def air_force(spring, compression: float) -> float:
    """The polytropic law's force (N, pushing) of an air spring at ``compression`` (m) from design height."""
    volume = spring.volume - spring.area * compression - spring.area_slope * compression**2 / 2
    pressure = (spring.pressure + ATMOSPHERE) * (spring.volume / volume) ** spring.polytropic_index - ATMOSPHERE
    return pressure * (spring.area + spring.area_slope * compression)


class Truck:
    """Equations of a rigid-frame truck (``vehicle`` has no [frame]) on its posts."""

    def __init__(self, vehicle):
        assert vehicle.frame is None and vehicle.layout == "truck"
        self.v = vehicle
        self.corners = list(vehicle.corners)
        names = ["z", "theta", "phi"]
        for axle in vehicle.axle_names:
            names += [f"{axle}/z", f"{axle}/phi"]
        self.bodies = [b for b in ("cab", "driveline") if getattr(vehicle, b) is not None]
        for body in self.bodies:
            names += [f"{body}/z", f"{body}/theta", f"{body}/phi"]
        self.names, self.n = names, len(names)
        mass = [vehicle.sprung_mass, vehicle.pitch_inertia, vehicle.roll_inertia]
        for axle in vehicle.axles:
            mass += [2 * axle.unsprung_mass, axle.roll_inertia]
        for body in self.bodies:
            spec = getattr(vehicle, body)
            mass += [spec.mass, spec.pitch_inertia, spec.roll_inertia]
        self.mass = np.array(mass)
        self.gravity = np.zeros(self.n)
        for i, name in enumerate(names):
            if name.endswith("z"):
                self.gravity[i] = -self.mass[i] * G
        self._elements()
        self.post_static = np.zeros(len(self.corners))

    # ---- geometry -----------------------------------------------------------------------------------------
    def frame_point(self, x: float, y: float) -> np.ndarray:
        row = np.zeros(self.n)
        row[:3] = [1.0, -x, y]
        return row

    def axle_point(self, axle: str, y: float) -> np.ndarray:
        row = np.zeros(self.n)
        row[self.names.index(f"{axle}/z")], row[self.names.index(f"{axle}/phi")] = 1.0, y
        return row

    def body_point(self, body: str, dx: float, dy: float) -> np.ndarray:
        row = np.zeros(self.n)
        i = self.names.index(f"{body}/z")
        row[i:i + 3] = [1.0, -dx, dy]
        return row

    def _elements(self) -> None:
        v = self.v
        self.lines, self.tyres, self.leaves = [], [], 0
        for corner in self.corners:
            axle_name = {"F": "front", "R": "rear"}.get(corner[:-1], "middle" + corner[1:-1])
            axle = v.axle(corner)
            x, y = v.corner_position(corner)
            side = 1.0 if corner.endswith("L") else -1.0
            spring_y, damper_y = side * axle.spring_track / 2, side * axle.damper_track / 2
            spring = Line(self.frame_point(x, spring_y), self.axle_point(axle_name, spring_y), "leaf")
            if axle.suspension == "beam_air":
                spring.kind, spring.law, spring.rate = "air", axle.law, axle.parasitic_rate
            else:
                spring.rate, spring.law = axle.spring_rate + axle.parasitic_rate, axle.law
                if axle.law is not None:
                    spring.index, self.leaves = self.leaves, self.leaves + 1
            self.lines.append(spring)
            self.lines.append(Line(self.frame_point(x, damper_y), self.axle_point(axle_name, damper_y), "damper",
                                   damping=axle.damping))
            offsets = [0.0] if axle.tyres == "single" else [side * axle.dual_spacing / 2, -side * axle.dual_spacing / 2]
            for dy in offsets:
                self.tyres.append((self.corners.index(corner), self.axle_point(axle_name, y + dy), axle))
        for body in self.bodies:
            spec = getattr(v, body)
            x = v.cg_to_front_axle - spec.position
            for dx, dy in spec.mount_points():
                self.lines.append(Line(self.frame_point(x + dx, dy), self.body_point(body, dx, dy), "mount",
                                       rate=0.0 if spec.air_spring else spec.stiffness, damping=spec.damping,
                                       law=spec.air_spring))
        self.hubs = np.array([self.axle_point({"F": "front", "R": "rear"}.get(c[:-1], "middle" + c[1:-1]),
                                              v.corner_position(c)[1]) for c in self.corners])
        self.body_sites = np.array([self.frame_point(*v.corner_position(c)) for c in self.corners])

    # ---- laws ---------------------------------------------------------------------------------------------
    def line_force(self, line: Line, q, qd, friction) -> float:
        """Force of a line pushing its ends apart (N); a mount pulls (its upper end above the body)."""
        compression = (line.lower - line.upper) @ q      # the lower end up relative to the upper one
        rate = (line.lower - line.upper) @ qd
        if line.kind == "damper":
            return line.damping * rate
        if line.kind == "mount":  # a hanging spring: its tension falls as the body rises, a push of k x + c v
            if line.law is not None:  # the body drawn at design height, compressed as it falls below it
                return -air_force(line.law, -compression) + line.damping * rate
            return line.rate * compression + line.damping * rate
        force = line.rate * compression
        if line.kind == "air":
            return force + air_force(line.law, compression)
        if line.index >= 0:
            force += friction[line.index]
        return force

    # ---- equations of motion --------------------------------------------------------------------------------
    def split(self, s):
        n, c, k = self.n, len(self.corners), self.leaves
        cuts = np.cumsum([0, n, n, c, c, c, k])
        return [s[cuts[i]:cuts[i + 1]] for i in range(6)]

    def derivative(self, s, drive):
        v = self.v
        q, qd, p, pd, cmd, friction = self.split(s)
        generalized = self.gravity.copy()
        friction_rate = np.zeros(self.leaves)
        for line in self.lines:
            force = self.line_force(line, q, qd, friction)
            generalized += force * (line.upper - line.lower)  # a push raises the upper end, lowers the lower one
            if line.index >= 0:  # Dahl on the spring's extension rate
                extension_rate = -(line.lower - line.upper) @ qd
                law = line.law
                sigma = law.friction / law.decay_length
                friction_rate[line.index] = -sigma * (extension_rate - abs(extension_rate) * (-friction[line.index])
                                                      / law.friction)
        tyre_force = np.zeros(len(self.corners))
        for corner, row, axle in self.tyres:
            force = max(axle.tyre_rate * (p[corner] - row @ q) + axle.tyre_damping * (pd[corner] - row @ qd), 0.0)
            tyre_force[corner] += force
            generalized += force * row
        qdd = generalized / self.mass
        rig = v.rig
        tau = 1.0 / (2 * np.pi * rig.servo_bandwidth)
        kp = rig.post_mass * (2 * np.pi * rig.loop_frequency) ** 2
        kv = 2 * rig.loop_damping * rig.post_mass * 2 * np.pi * rig.loop_frequency
        servo = kp * (cmd - p) - kv * pd + self.post_static
        pdd = (servo - tyre_force - rig.post_mass * G) / rig.post_mass
        cmdd = (drive - cmd) / tau
        return np.concatenate([qd, qdd, pd, pdd, cmdd, friction_rate]), {
            "qdd": qdd, "q": q, "qd": qd, "p": p, "tyre": tyre_force, "servo": servo}

    def rest(self) -> np.ndarray:
        """The rest state with the posts at zero: frame, axles and bodies in equilibrium, friction free."""
        s = np.zeros(2 * self.n + 3 * len(self.corners) + self.leaves)

        def residual(q):
            state = s.copy()
            state[:self.n] = q
            return self.derivative(state, np.zeros(len(self.corners)))[0][self.n:2 * self.n] * self.mass

        q = root(residual, -0.05 * np.ones(self.n) * np.array([n.endswith("z") for n in self.names]), tol=1e-12).x
        s[:self.n] = q
        _, info = self.derivative(s, np.zeros(len(self.corners)))
        self.post_static = info["tyre"] + self.v.rig.post_mass * G
        return s

    def run(self, drive: np.ndarray, rate: float, substeps: int = 4) -> dict[str, np.ndarray]:
        """Simulate drives (samples x corners, m) at ``rate`` Hz; contract channels at the sample times."""
        n = drive.shape[0]
        h = 1.0 / (rate * substeps)
        spline = CubicSpline(np.arange(n) / rate, drive, axis=0)
        times = np.arange(2 * (n - 1) * substeps + 1) * h / 2 - self.v.rig.servo_delay
        delayed = np.where(times[:, None] < 0, 0.0, spline(np.clip(times, 0, None)))
        s = self.rest()
        start = s[:self.n].copy()
        samples = rk4_samples(self.derivative, s, delayed, substeps, h)
        qdd = np.array([i["qdd"] for i in samples])
        q = np.array([i["q"] for i in samples])
        travel = (self.hubs - self.body_sites) @ (q - start).T
        out = {"sprung_acc": qdd @ self.body_sites.T, "unsprung_acc": qdd @ self.hubs.T, "susp_travel": travel.T,
               "actuator_disp": np.array([i["p"] for i in samples]),
               "tyre_force": np.array([i["tyre"] for i in samples]),
               "actuator_force": np.array([i["servo"] for i in samples])}
        if "cab" in self.bodies and self.v.cab.seat is not None:
            sx, sy, _ = self.v.cab.seat
            out["seat_acc"] = qdd @ self.body_point("cab", sx, sy)
        return out


def equivalent(truth):
    """``truth`` (a rigid-frame truck) with its causes written into its own parameters, as this simulator takes them:
    a leaf spring's or an air spring's law on its axle, a body's mounts or the cab's air springs in its table, a
    payload on the centre line (``y`` = 0) in the sprung mass, CG and pitch inertia."""
    import dataclasses

    extensions = dict(truth.extensions)
    vehicle = dataclasses.replace(truth, extensions={})
    for name in ("leaf_friction", "air_spring_law"):
        for axle, law in extensions.pop(name, {}).items():
            vehicle = vehicle.with_axle(axle, dataclasses.replace(vehicle.axle_named(axle), law=law))
    for body in ("cab", "driveline"):
        mounts = extensions.pop(f"{body}_mounts", None)
        if mounts is not None:
            vehicle = dataclasses.replace(vehicle, **{body: dataclasses.replace(
                getattr(vehicle, body), stiffness=mounts.stiffness, damping=mounts.damping, air_spring=None)})
    spring = extensions.pop("cab_air_spring", None)
    if spring is not None:
        vehicle = dataclasses.replace(vehicle, cab=dataclasses.replace(vehicle.cab, air_spring=spring,
                                                                       stiffness=spring.rate))
    payload = extensions.pop("mass_error", None)
    if payload is not None:
        assert payload.y == 0.0
        mass = vehicle.sprung_mass + payload.mass
        shift = payload.mass * payload.x / mass  # the CG moves forward by this
        pitch = (vehicle.pitch_inertia + vehicle.sprung_mass * shift**2 + payload.mass * (payload.x - shift) ** 2
                 + payload.pitch_inertia)
        vehicle = dataclasses.replace(vehicle, sprung_mass=mass, cg_to_front_axle=vehicle.cg_to_front_axle - shift,
                                      pitch_inertia=pitch, roll_inertia=vehicle.roll_inertia + payload.roll_inertia)
    assert not extensions, f"the independent simulator does not take {', '.join(extensions)}"
    return vehicle


def rig_test_records(truth, rng: np.random.Generator, duration: float, holdout: float, rate: float,
                     noise: float = 0.02):
    """A measured and a held-out rig record of ``truth`` (its causes as ``equivalent`` writes them) simulated here,
    under the diagnosis's event drives (rig/diagnosis/rig_test/synthetic.py), with white noise of ``noise`` times each
    measured channel's RMS (the drives exact)."""
    from rig import Record
    from rig.diagnosis.rig_test.synthetic import event_drive

    vehicle = equivalent(truth)
    truck = Truck(vehicle)
    records = []
    for length in (duration, holdout):
        drive = event_drive(vehicle.corners, length, rate, rng)
        out = truck.run(drive, rate)
        channels = {f"{c}/drive": drive[:, i] for i, c in enumerate(vehicle.corners)}
        for quantity in ("actuator_disp", "sprung_acc", "unsprung_acc", "susp_travel", "tyre_force"):
            channels |= {f"{c}/{quantity}": out[quantity][:, i] for i, c in enumerate(vehicle.corners)}
        if "seat_acc" in out:
            channels["cab/seat_acc"] = out["seat_acc"]
        for name, values in channels.items():
            if not name.endswith("/drive"):
                channels[name] = values + noise * np.std(values) * rng.standard_normal(values.size)
        records.append(Record(rate, channels, metadata={"vehicle": truth.name, "test": "rig",
                                                        "source": "independent truck simulator (tests/)"}))
    return records[0], records[1]
