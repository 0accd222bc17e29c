"""An independent simulator of a car on a four-poster, written from the equations for the tests.

Neither MuJoCo nor the project's model builder: a 7-DOF ride model (heave, pitch, roll, four wheels) on
four servo posts, integrated by a fixed-step RK4 in NumPy, with laws the diagnosis does not fit (a
Duffing spring, a smooth quadratic bump-stop rise, tanh friction, a damper with hydraulic compliance, a
subsystem resonating on its mounts, a second-order valve...). Records carry what a rig measures, with 2 %
noise, and the truth car's linear parameters off by up to 3 %, like the project's own synthetic tests.

Coordinates: absolute vertical positions from the nominal car's static equilibrium; body corner i moves
by z - x_i theta + y_i phi (x forward, y left of the CG). Compression x_i = z_wheel - z_body_corner,
positive when the wheel rises towards the body.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from itertools import pairwise

import numpy as np
from scipy.interpolate import CubicSpline
from scipy.optimize import root

from rig.io.record import Record

G = 9.80665
CORNERS = ("FL", "FR", "RL", "RR")


@dataclass
class Hidden:
    """Hidden effects, each off when None. Laws (F: force on the body, up; x, v: compression and its rate)."""

    cubic_spring: float | None = None            # N/m^3: F += k3 x^3 (symmetric Duffing stiffening)
    smooth_bump: tuple[float, float] | None = None  # (gap m, kq N/m^2): F += kq (x - gap)^2 beyond the gap
    smooth_rebound: tuple[float, float] | None = None  # (gap m, kq N/m^2): F -= kq (-x - gap)^2 beyond the gap
    tanh_friction: tuple[float, float] | None = None  # (F0 N, v0 m/s): F += F0 tanh(v / v0)
    digressive_damper: tuple[float, float] | None = None  # (knee m/s, ratio): slope c below the knee, ratio c above
    damper_ratio: float | None = None            # rebound / compression damping, their mean the car's damping
    damper_factors: tuple[float, float] | None = None  # (compression, rebound) damping over the car's damping
    hydraulic_compliance: float | None = None    # N/m: damper force obeys dF/dt = kh (v - F / c) (Maxwell)
    payload: tuple[float, float, float] | None = None  # (kg, x m, y m): a point mass on the body
    secondary_mass: tuple[float, float, float, float, float] | None = None  # (kg, x, y, Hz, damping ratio)
    anti_roll_bar: tuple[float, float] | None = None  # N/m front, rear per m of left-right compression difference
    tyre_damping: float | None = None            # N s/m
    valve: tuple[float, float, float] | None = None  # (Hz, damping ratio, delay s): second-order post command
    sensor_gain: dict[str, float] = field(default_factory=dict)
    sensor_delay: dict[str, float] = field(default_factory=dict)


@dataclass
class Car:
    """Linear parameters per corner (FL, FR, RL, RR) and the body, SI."""

    mass: float
    pitch_inertia: float
    roll_inertia: float
    x: np.ndarray
    y: np.ndarray
    unsprung: np.ndarray
    spring: np.ndarray      # spring + parasitic rate
    damping: np.ndarray
    tyre: np.ndarray
    track: tuple[float, float]
    post_mass: float
    servo_bandwidth: float
    servo_delay: float
    loop_frequency: float
    loop_damping: float

    @classmethod
    def from_vehicle(cls, v) -> Car:
        axles = [v.front, v.front, v.rear, v.rear]
        a, b = v.cg_to_front_axle, v.wheelbase - v.cg_to_front_axle
        return cls(v.sprung_mass, v.pitch_inertia, v.roll_inertia, np.array([a, a, -b, -b]),
                   np.array([v.track_front / 2, -v.track_front / 2, v.track_rear / 2, -v.track_rear / 2]),
                   np.array([ax.unsprung_mass for ax in axles]), np.array([ax.suspension_rate for ax in axles]),
                   np.array([ax.damping for ax in axles]), np.array([ax.tyre_rate for ax in axles]),
                   (v.track_front, v.track_rear), v.rig.post_mass, v.rig.servo_bandwidth, v.rig.servo_delay,
                   v.rig.loop_frequency, v.rig.loop_damping)

    def nominal_loads(self) -> np.ndarray:
        """Static suspension loads of the nominal car (N per corner): the springs' preloads."""
        a, b = self.x[0], -self.x[2]
        front, rear = self.mass * G * b / (a + b) / 2, self.mass * G * a / (a + b) / 2
        return np.array([front, front, rear, rear])


def perturbed(car: Car, rng: np.random.Generator, error: float = 0.03) -> Car:
    """The car with its mass, rates, damping and unsprung masses off by up to ``error``."""
    def off(values):
        return values * rng.uniform(1 - error, 1 + error, np.shape(values))
    return dataclasses.replace(car, mass=float(off(car.mass)), spring=off(car.spring), damping=off(car.damping),
                               tyre=off(car.tyre), unsprung=off(car.unsprung))


class Simulator:
    """The truth car on the servo-post rig. State: body q (z, theta, phi) and its rate, wheels, posts, the
    post command filter (two states per corner), the damper forces (Maxwell) and the secondary mass."""

    def __init__(self, car: Car, hidden: Hidden, preload_car: Car | None = None):
        self.car, self.hidden = car, hidden
        self.preload = (preload_car or car).nominal_loads()
        self.jacobian = np.column_stack([np.ones(4), -car.x, car.y])  # corner displacement = J q
        self.mass_matrix = np.diag([car.mass, car.pitch_inertia, car.roll_inertia])
        self.gravity = np.array([-car.mass * G, 0.0, 0.0])
        if hidden.payload is not None:  # coupled mass matrix and static moment of a point mass on the body
            m, x, y = hidden.payload
            j = np.array([1.0, -x, y])
            self.mass_matrix = self.mass_matrix + m * np.outer(j, j)
            self.gravity = self.gravity - m * G * j
        if hidden.secondary_mass is not None:  # part of the sprung mass, now on its own mounts
            m, x, y, *_ = hidden.secondary_mass
            j = np.array([1.0, -x, y])
            self.mass_matrix = self.mass_matrix - m * np.outer(j, j)
            self.gravity = self.gravity + m * G * j
        self.n = 3 + 3 + 4 + 4 + 4 + 4 + 4 + 4 + 4 + 2
        self.post_static = np.zeros(4)  # the servos' static feed-forward, set at rest
        kp = car.post_mass * (2 * np.pi * car.loop_frequency) ** 2
        self.loop = (kp, 2 * car.loop_damping * car.post_mass * 2 * np.pi * car.loop_frequency)
        self.mass_inverse_t = np.linalg.inv(self.mass_matrix).T.copy()  # the body's equations, solved once
        self.jacobian_t = self.jacobian.T.copy()  # contiguous: batched states multiply from the left
        edges = np.cumsum([0, 3, 3, 4, 4, 4, 4, 4, 4, 4, 2])
        self.parts = [slice(a, b) for a, b in pairwise(edges)]

    # ---- laws --------------------------------------------------------------------------------------
    def suspension(self, x: np.ndarray, v: np.ndarray, damper_state: np.ndarray) -> np.ndarray:
        """Force on the body (up) per corner, beyond the preload, at compression x and rate v."""
        car, h = self.car, self.hidden
        force = car.spring * x
        if h.cubic_spring is not None:
            force = force + h.cubic_spring * x**3
        if h.smooth_bump is not None:
            gap, kq = h.smooth_bump
            force = force + kq * np.maximum(x - gap, 0.0) ** 2
        if h.smooth_rebound is not None:
            gap, kq = h.smooth_rebound
            force = force - kq * np.maximum(-x - gap, 0.0) ** 2
        if h.tanh_friction is not None:
            force = force + h.tanh_friction[0] * np.tanh(v / h.tanh_friction[1])
        if h.hydraulic_compliance is not None:
            force = force + damper_state
        elif h.damper_ratio is not None:
            compression = 2 * car.damping / (1 + h.damper_ratio)
            force = force + np.where(v > 0, compression, h.damper_ratio * compression) * v
        elif h.damper_factors is not None:
            force = force + car.damping * np.where(v > 0, h.damper_factors[0], h.damper_factors[1]) * v
        elif h.digressive_damper is not None:
            knee, ratio = h.digressive_damper
            force = force + car.damping * np.where(np.abs(v) < knee, v,
                                                   np.sign(v) * (knee + ratio * (np.abs(v) - knee)))
        else:
            force = force + car.damping * v
        if h.anti_roll_bar is not None:
            front, rear = h.anti_roll_bar
            force = force + np.array([front, -front, rear, -rear]) * (x[..., [0, 0, 2, 2]] - x[..., [1, 1, 3, 3]])
        return force

    def tyre(self, road: np.ndarray, road_rate: np.ndarray, wheel: np.ndarray, wheel_rate: np.ndarray) -> np.ndarray:
        car = self.car
        damping = self.hidden.tyre_damping or 0.0
        preload = self.preload + car.unsprung * G
        return np.maximum(preload + car.tyre * (road - wheel) + damping * (road_rate - wheel_rate), 0.0)

    # ---- equations of motion -----------------------------------------------------------------------
    def split(self, s: np.ndarray):
        return [s[..., part] for part in self.parts]

    def derivative(self, s: np.ndarray, drive: np.ndarray) -> tuple[np.ndarray, dict]:
        """The state's rate and what a rig measures, for states (..., n) and drives (..., 4) of any batch shape."""
        car, h = self.car, self.hidden
        q, qd, zw, zwd, p, pd, cmd, cmdd, damper, extra = self.split(s)
        body, body_rate = q @ self.jacobian_t, qd @ self.jacobian_t
        x, v = zw - body, zwd - body_rate
        f_susp = self.preload + self.suspension(x, v, damper)
        f_tyre = self.tyre(p, pd, zw, zwd)
        generalized = f_susp @ self.jacobian + self.gravity
        extra_rate = np.zeros(extra.shape)
        if h.secondary_mass is not None:
            m_e, x_e, y_e, f_e, zeta = h.secondary_mass
            j = np.array([1.0, -x_e, y_e])
            k_e, c_e = m_e * (2 * np.pi * f_e) ** 2, 2 * zeta * m_e * 2 * np.pi * f_e
            mount = m_e * G - k_e * (extra[..., 0] - q @ j) - c_e * (extra[..., 1] - qd @ j)  # on the mass, up
            generalized = generalized - mount[..., None] * j
            extra_rate = np.stack([extra[..., 1], mount / m_e - G], axis=-1)
        qdd = generalized @ self.mass_inverse_t
        zwdd = (f_tyre - f_susp - car.unsprung * G) / car.unsprung
        # posts: command filter (first-order lag, or a second-order valve), position loop on the post mass
        if h.valve is not None:
            f_v, zeta_v, _ = h.valve
            w = 2 * np.pi * f_v
            cmddd = w**2 * (drive - cmd) - 2 * zeta_v * w * cmdd
        else:
            tau = 1.0 / (2 * np.pi * car.servo_bandwidth)
            cmddd = np.zeros(cmd.shape)
            cmdd = (drive - cmd) / tau
        kp, kv = self.loop
        pdd = (kp * (cmd - p) - kv * pd + self.post_static - f_tyre - car.post_mass * G) / car.post_mass
        damper_rate = np.zeros(damper.shape)
        if h.hydraulic_compliance is not None:
            damper_rate = h.hydraulic_compliance * (v - damper / car.damping)
        out = np.concatenate([qd, qdd, zwd, zwdd, pd, pdd, cmdd, cmddd, damper_rate, extra_rate], axis=-1)
        return out, {"qdd": qdd, "zwdd": zwdd, "x": x, "v": v, "p": p, "f_tyre": f_tyre}

    def rest(self) -> np.ndarray:
        """The static equilibrium with the posts at zero (the truth car sinks or tilts under a payload)."""
        s = np.zeros(self.n)
        q_i, zw_i = slice(0, 3), slice(6, 10)

        def residual(free):
            s2 = s.copy()
            s2[q_i], s2[zw_i] = free[:3], free[3:7]
            if self.hidden.secondary_mass is not None:
                s2[-2] = free[7]
            d, _ = self.derivative(s2, np.zeros(4))
            r = np.concatenate([d[3:6], d[10:14]])
            return np.append(r, d[-1]) if self.hidden.secondary_mass is not None else r

        size = 8 if self.hidden.secondary_mass is not None else 7
        solution = root(residual, np.zeros(size), tol=1e-12).x
        s[q_i], s[zw_i] = solution[:3], solution[3:7]
        if self.hidden.secondary_mass is not None:
            s[-2] = solution[7]
        zw = s[zw_i]
        self.post_static = self.tyre(np.zeros(4), np.zeros(4), zw, np.zeros(4)) + self.car.post_mass * G
        return s

    def run(self, drives: list[np.ndarray], rate: float, substeps: int = 2) -> list[dict[str, np.ndarray]]:
        """Simulate ``drives`` (each samples x corners, m) at ``rate`` Hz side by side in one integration; each
        drive's channels at its own sample times (a shorter drive holds its last command beyond its end, which
        leaves its own samples exact)."""
        h = 1.0 / (rate * substeps)
        delay = self.hidden.valve[2] if self.hidden.valve is not None else self.car.servo_delay
        longest = max(drive.shape[0] for drive in drives)
        times = np.arange(2 * (longest - 1) * substeps + 1) * h / 2 - delay
        delayed = np.empty((times.size, len(drives), 4))
        for b, drive in enumerate(drives):
            own = np.clip(times, 0, (drive.shape[0] - 1) / rate)
            spline = CubicSpline(np.arange(drive.shape[0]) / rate, drive, axis=0)
            delayed[:, b] = np.where(times[:, None] < 0, 0.0, spline(own))
        start = self.rest()
        samples = rk4_samples(self.derivative, np.tile(start, (len(drives), 1)), delayed, substeps, h)
        x0 = start[6:10] - self.jacobian @ start[0:3]
        channels = {"sprung_acc": np.array([info["qdd"] @ self.jacobian_t for info in samples]),
                    "unsprung_acc": np.array([info["zwdd"] for info in samples]),
                    "susp_travel": np.array([info["x"] for info in samples]) - x0,
                    "actuator_disp": np.array([info["p"] for info in samples]),
                    "tyre_force": np.array([info["f_tyre"] for info in samples])}
        return [{name: values[:drive.shape[0], b] for name, values in channels.items()}
                for b, drive in enumerate(drives)]


QUANTITIES = ("sprung_acc", "unsprung_acc", "susp_travel", "actuator_disp", "tyre_force")  # measured, in draw order


def noise_draws(rng: np.random.Generator, samples: int) -> list[np.ndarray]:
    """One record's standard-normal noise, corner by corner, each corner's ``QUANTITIES`` in order."""
    return [rng.standard_normal(samples) for _ in CORNERS for _ in QUANTITIES]


def measured_records(sim: Simulator, drives: list[np.ndarray], draws: list[list[np.ndarray]], rate: float,
                     noise: float = 0.02) -> list[Record]:
    """Rig tests of ``drives`` simulated side by side: drives (exact), and post displacement, accelerations, travel
    and tyre force with ``draws`` (``noise_draws``) scaled to ``noise`` of each channel's RMS about its mean."""
    records = []
    for drive, out, draw in zip(drives, sim.run(drives, rate), draws):
        channels, unit_noise = {}, iter(draw)
        for i, corner in enumerate(CORNERS):
            channels[f"{corner}/drive"] = drive[:, i]
            for quantity in QUANTITIES:
                name = f"{corner}/{quantity}"
                clean = out[quantity][:, i]
                if name in sim.hidden.sensor_delay:  # a skewed channel: linear between samples, held before the start
                    t = np.arange(clean.size) / rate
                    clean = np.interp(t - sim.hidden.sensor_delay[name], t, clean)
                clean = clean * sim.hidden.sensor_gain.get(name, 1.0)
                channels[name] = clean + next(unit_noise) * noise * np.std(clean)
        records.append(Record(rate, channels, metadata={"test": "rig",
                                                        "source": "independent simulator (tests/independent_rig.py)"}))
    return records


def rig_records(sim: Simulator, drives: list[np.ndarray], rate: float, rng: np.random.Generator,
                noise: float = 0.02) -> list[Record]:
    """Measured rig tests of ``drives``, their noise drawn from ``rng`` drive by drive (``noise_draws``)."""
    return measured_records(sim, drives, [noise_draws(rng, drive.shape[0]) for drive in drives], rate, noise)


def rig_record(sim: Simulator, drive: np.ndarray, rate: float, rng: np.random.Generator,
               noise: float = 0.02) -> Record:
    """A measured rig test: drives (exact), and noisy post displacement, accelerations, travel and tyre force."""
    return rig_records(sim, [drive], rate, rng, noise)[0]


def independent_records(vehicle, hidden: Hidden, seed: int, duration: float = 30.0, holdout: float = 30.0,
                        rate: float = 512.0, events: float = 0.035) -> tuple[Record, Record, Simulator]:
    """Measured and held-out rig records of ``vehicle`` off by up to 3 % with ``hidden`` effects; ``events``: the
    road events' height (m; rig/diagnosis/rig_test/synthetic.py ``event_drive``: at 35 mm a rear tyre of a car lifts
    off). Each drive is drawn, then its noise, as if the two were run one after the other."""
    from rig.diagnosis.rig_test.synthetic import event_drive

    rng = np.random.default_rng(seed)
    nominal = Car.from_vehicle(vehicle)
    sim = Simulator(perturbed(nominal, rng), hidden, preload_car=nominal)
    drives, draws = [], []
    for length in (duration, holdout):
        drives.append(event_drive(vehicle.corners, length, rate, rng, amplitude=events))
        draws.append(noise_draws(rng, drives[-1].shape[0]))
    measured, held_out = measured_records(sim, drives, draws, rate)
    return measured, held_out, sim


def rk4_samples(derivative, state: np.ndarray, inputs: np.ndarray, substeps: int, h: float) -> list[dict]:
    """Classic RK4 of ``derivative(state, u) -> (rate, info)`` with steps of ``h`` s and the inputs at half steps
    (``inputs[2 k]`` at step k's start, ``inputs[2 k + 1]`` at its middle); ``info`` at every ``substeps``-th step,
    the first at the start and the last at the inputs' end."""
    steps = (inputs.shape[0] - 1) // 2
    samples = []
    for k in range(steps + 1):
        if k % substeps == 0:
            samples.append(derivative(state, inputs[2 * k])[1])
        if k == steps:
            break
        u0, u1, u2 = inputs[2 * k], inputs[2 * k + 1], inputs[2 * k + 2]
        k1 = derivative(state, u0)[0]
        k2 = derivative(state + h / 2 * k1, u1)[0]
        k3 = derivative(state + h / 2 * k2, u1)[0]
        k4 = derivative(state + h * k3, u2)[0]
        state = state + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
    return samples
