"""An independent simulator of a car driven on a road, written from the equations for the tests (the transputer paper).

Neither MuJoCo nor the project's model builder, roads or track runs: the 7-DOF ride model (heave, pitch, roll,
four wheels) of tests/independent_rig.py's ``Car``, its tyres on the road instead of posts, linear about the
static equilibrium while every tyre touches the road (one in the air carries nothing):

    M q'' = J^T (k x + c x'),   m_w zw'' = kt (zr - zw) - (k x + c x') + F_u,   x = zw - J q (compression),

solved exactly for inputs linear between steps (first-order hold, matrix exponential) at ``OVERSAMPLE`` x the
record rate, switching the tyres' contact (a tyre pushes only) at those steps. The road is an ISO 8608 Gaussian
process generated here (complex Gaussian Fourier coefficients with the class PSD Gd(n0) (n / n0)^-2, not
rig/road's harmonic superposition), each wheel on its side's track, the rear wheels a wheelbase later. Every wheel
rolls at v / R_c with its own rolling radius; an unbalance m e at ``angle`` from a wheel's mark is the rotating hub
force F_u = m e omega^2 cos(theta_c + angle) (faded in with the road over the first 2 m, so that the record does not
start with a step of it). Records carry what a car on the road measures: body and wheel accelerations and suspension
travel with 2 % noise, and each wheel's angle (0 with its mark at the top, growing in the rolling direction).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from independent_rig import CORNERS, Car, G, perturbed
from scipy.linalg import expm

from rig.io.record import Record

OVERSAMPLE = 8
ENVELOPED = 3.0  # cycle/m: shorter wavelengths than a third of a metre are enveloped by the tyre's contact patch
N0 = 0.1  # cycle/m
GD_N0 = {"A": 16e-6, "B": 64e-6, "C": 256e-6}  # m^3, ISO 8608 class geometric means


@dataclass
class Unbalance:
    corner: str
    kgm: float       # m e
    angle_deg: float  # from the mark, in the rolling direction


@dataclass
class Drive:
    """One record's conditions: road class, speed, duration, rolling radii and the marks' angles at the start."""

    road_class: str
    speed: float
    duration: float
    radii: dict[str, float]
    start_angles: dict[str, float] = field(default_factory=dict)
    seed: int = 0


def gaussian_road(road_class: str, length: float, spacing: float, rng: np.random.Generator) -> np.ndarray:
    """Two independent tracks (2 x samples, m) of an ISO 8608 class: Gaussian Fourier coefficients with variance
    Gd(n) dn, from 0.01 cycle/m to what the tyre's contact patch does not envelop (``ENVELOPED``)."""
    n = int(np.ceil(length / spacing)) + 1
    frequency = np.fft.rfftfreq(n, spacing)
    psd = np.where((frequency >= 0.01) & (frequency <= ENVELOPED),
                   GD_N0[road_class] * (np.maximum(frequency, 1e-9) / N0) ** -2, 0.0)
    sigma = np.sqrt(psd * frequency[1] / 4)  # per real and imaginary part: a line (2 |c| cos) carries Gd dn of variance
    coefficients = (rng.standard_normal((2, frequency.size)) + 1j * rng.standard_normal((2, frequency.size))) * sigma
    return np.fft.irfft(coefficients * n, n, axis=1)


class TrackSimulator:
    """The truth car on the road: state (q, zw, q', zw'), inputs (road under each wheel, unbalance forces, and the
    static load a tyre no longer carries while it is off the ground)."""

    def __init__(self, car: Car, unbalance: Unbalance | None = None):
        self.car, self.unbalance = car, unbalance
        self.jacobian = np.column_stack([np.ones(4), -car.x, car.y])
        mass = np.zeros((7, 7))
        mass[:3, :3], mass[3:, 3:] = np.diag([car.mass, car.pitch_inertia, car.roll_inertia]), np.diag(car.unsprung)
        self.inverse = np.linalg.inv(mass)
        # compression x = T p with p = (q, zw): T = [-J, I]
        self.travel = np.hstack([-self.jacobian, np.eye(4)])
        self.suspension = self.travel.T @ np.diag(car.spring) @ self.travel
        self.damping = self.travel.T @ np.diag(car.damping) @ self.travel
        self.static_tyre = car.nominal_loads() + car.unsprung * G
        self._modes: dict[tuple[bool, ...], tuple] = {}

    def matrices(self, contact: tuple[bool, ...]) -> tuple[np.ndarray, np.ndarray]:
        """State and input matrices with the tyres in ``contact`` on the road (the others in the air)."""
        on = np.array(contact, float)
        stiffness = self.suspension.copy()
        stiffness[3:, 3:] += np.diag(self.car.tyre * on)
        a = np.block([[np.zeros((7, 7)), np.eye(7)], [-self.inverse @ stiffness, -self.inverse @ self.damping]])
        inputs = np.zeros((7, 12))
        inputs[3:, :4] = np.diag(self.car.tyre * on)  # road heights
        inputs[3:, 4:8] = np.eye(4)                    # unbalance forces on the hubs
        inputs[3:, 8:] = np.eye(4)                     # the static tyre load lost in the air
        return a, np.vstack([np.zeros((7, 12)), self.inverse @ inputs])

    def discrete(self, contact: tuple[bool, ...], h: float):
        """First-order-hold discretisation with the tyres in ``contact``: x+ = F x + G0 u + G1 (u+ - u)."""
        if contact not in self._modes:
            a, b = self.matrices(contact)
            n, m = a.shape[0], b.shape[1]
            block = np.zeros((n + 2 * m, n + 2 * m))
            block[:n, :n], block[:n, n:n + m] = a * h, b * h
            block[n:n + m, n + m:] = np.eye(m)
            e = expm(block)
            self._modes[contact] = (e[:n, :n], e[:n, n:n + m], e[:n, n + m:])
        return self._modes[contact]

    def run(self, drive: Drive, wheelbase: float, rate: float, rng: np.random.Generator) -> dict[str, np.ndarray]:
        """Channels (samples x corners) of one drive at ``rate`` Hz, noise-free, the wheels' angles and the road."""
        fine = rate * OVERSAMPLE
        samples = int(round(drive.duration * rate))
        steps = (samples - 1) * OVERSAMPLE + 1
        time = np.arange(steps) / fine
        spacing = 0.01
        tracks = gaussian_road(drive.road_class, drive.speed * drive.duration + 1.0, spacing, rng)
        distance = np.arange(tracks.shape[1]) * spacing
        fade = np.clip(distance / 2.0, 0.0, 1.0)  # the road fades in over 2 m, the car starting at rest on it
        roads = np.empty((steps, 4))
        for i, corner in enumerate(CORNERS):
            behind = wheelbase if corner[0] == "R" else 0.0
            track = tracks[0 if corner[1] == "L" else 1] * fade
            roads[:, i] = np.interp(drive.speed * time - behind, distance, track, left=0.0)
        angles = np.column_stack([drive.start_angles.get(c, 0.0) + drive.speed / drive.radii[c] * time
                                  for c in CORNERS])
        force = np.zeros((steps, 4))
        if self.unbalance is not None:
            c = CORNERS.index(self.unbalance.corner)
            omega = drive.speed / drive.radii[self.unbalance.corner]
            force[:, c] = self.unbalance.kgm * omega**2 * np.cos(angles[:, c] + np.radians(self.unbalance.angle_deg))
            force[:, c] *= np.interp(drive.speed * time, distance, fade)  # with the road: a test has no start
        u = np.hstack([roads, force, np.zeros((steps, 4))])
        on_road = (True,) * 4
        phi, g0, g1 = self.discrete(on_road, 1.0 / fine)
        drift, step_in = u @ (g0 - g1).T, u @ g1.T  # on the road throughout, the common case
        x = np.zeros((steps, 14))
        contact = np.ones((steps, 4), bool)
        for k in range(steps - 1):
            touching = self.static_tyre + self.car.tyre * (roads[k] - x[k, 3:7]) > 0
            contact[k] = touching
            if touching.all():
                x[k + 1] = phi @ x[k] + drift[k] + step_in[k + 1]
                continue
            mode = tuple(touching)
            f, h0, h1 = self.discrete(mode, 1.0 / fine)
            lost = -self.static_tyre * ~touching
            now, later = u[k].copy(), u[k + 1].copy()
            now[8:], later[8:] = lost, lost
            x[k + 1] = f @ x[k] + (h0 - h1) @ now + h1 @ later
        contact[-1] = self.static_tyre + self.car.tyre * (roads[-1] - x[-1, 3:7]) > 0
        pick = slice(None, None, OVERSAMPLE)
        x, u, roads, angles, contact = x[pick], u[pick], roads[pick], angles[pick], contact[pick]
        acc = np.empty((x.shape[0], 7))
        for mode in {tuple(m) for m in contact}:
            rows = np.all(contact == mode, axis=1)
            a, b = self.matrices(mode)
            inputs = u[rows].copy()
            inputs[:, 8:] = -self.static_tyre * ~np.array(mode)
            acc[rows] = x[rows] @ a[7:].T + inputs @ b[7:].T
        tyre = np.maximum(self.static_tyre + self.car.tyre * (roads - x[:, 3:7]), 0.0)
        return {"sprung_acc": acc[:, :3] @ self.jacobian.T, "unsprung_acc": acc[:, 3:7],
                "susp_travel": x[:, :7] @ self.travel.T, "wheel_angle": angles, "road": roads, "tyre_force": tyre}


def track_record(sim: TrackSimulator, drive: Drive, wheelbase: float, rate: float, rng: np.random.Generator,
                 noise: float = 0.02, road_channel: bool = False) -> Record:
    """A measured track test: noisy accelerations and travel, exact wheel angles (and the road, if asked)."""
    out = sim.run(drive, wheelbase, rate, rng)
    channels = {}
    for i, corner in enumerate(CORNERS):
        for quantity in ("sprung_acc", "unsprung_acc", "susp_travel"):
            clean = out[quantity][:, i]
            channels[f"{corner}/{quantity}"] = clean + rng.standard_normal(clean.size) * noise * np.std(clean)
        channels[f"{corner}/wheel_angle"] = out["wheel_angle"][:, i]
        if road_channel:
            channels[f"{corner}/road"] = out["road"][:, i]
    return Record(rate, channels, metadata={"test": "track", "speed": f"{drive.speed:g} m/s",
                                            "source": "independent simulator (tests/independent_track.py)"})


def random_radii(vehicle, rng: np.random.Generator, spread: float = 0.004) -> dict[str, float]:
    """Rolling radii differing by a few tenths of a percent about the tyre's."""
    return {c: vehicle.wheel_radius * (1 + rng.uniform(-spread, spread)) for c in CORNERS}


def independent_track_records(vehicle, unbalance: Unbalance | None, drives: list[Drive], seed: int,
                              rate: float = 512.0, error: float = 0.03, road_channel: bool = False
                              ) -> tuple[list[Record], TrackSimulator]:
    """Records of ``vehicle`` off by up to ``error`` (its linear parameters) with ``unbalance``, one per drive."""
    rng = np.random.default_rng(seed)
    car = Car.from_vehicle(vehicle)
    sim = TrackSimulator(perturbed(car, rng, error) if error else car, unbalance)
    return [track_record(sim, d, vehicle.wheelbase, rate, rng, road_channel=road_channel) for d in drives], sim
