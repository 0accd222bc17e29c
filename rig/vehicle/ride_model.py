"""The analytic linear ride model built directly from a vehicle file: the closed-form reference.

- Quarter car of Nurhadiyanto's thesis (section 3.2, eq. 3.1-3.6): sprung mass m_b on
  k_s + k_p and c_s, unsprung mass m_t on the tyre k_t; transfer functions X_b/X_r (3.5), X_t/X_r (3.6), and from a
  force F between body and wheel (on the body, up positive; -F on the wheel): X_b/F, X_t/F.
- Full car, 7 DOF (heave z, pitch theta about +y, roll phi about +x, four wheel heights): M, C, K about
  static equilibrium, static loads and deflections, and modal frequencies and damping ratios.
A corner at (x, y) from the CG moves by z - x*theta + y*phi (z up, x forward, y left).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rig.io.units import STANDARD_GRAVITY
from rig.vehicle.parts import Vehicle


def quarter_car_frf(vehicle: Vehicle, corner: str, frequency: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Sprung (eq. 3.5) and unsprung (eq. 3.6) displacement over road displacement at ``frequency`` Hz.

    Uses the corner's axle and the sprung mass carried by that corner (the whole sprung mass for a
    quarter-car vehicle file). Tyre damping, if any, is included as c_t in parallel with k_t.
    """
    axle = vehicle.axle(corner)
    m_b = corner_sprung_mass(vehicle, corner)
    m_t, k, c = axle.unsprung_mass, axle.suspension_rate, axle.damping
    s = 2j * np.pi * np.asarray(frequency, dtype=float)
    tyre = axle.tyre_rate + axle.tyre_damping * s
    suspension = c * s + k
    denominator = (m_t * s**2 + suspension + tyre) * (m_b * s**2 + suspension) - suspension**2
    return suspension * tyre / denominator, (m_b * s**2 + suspension) * tyre / denominator


def quarter_car_force_frf(vehicle: Vehicle, corner: str, frequency: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Sprung and unsprung displacement (m) over the force F (N) of an actuator between body and wheel, the road
    still: (m_b s^2 + z) X_b - z X_t = F and -z X_b + (m_t s^2 + z + t) X_t = -F, with z = c s + k the suspension's
    and t = c_t s + k_t the tyre's impedance: X_b / F = (m_t s^2 + t) / D, X_t / F = -m_b s^2 / D."""
    axle = vehicle.axle(corner)
    m_b = corner_sprung_mass(vehicle, corner)
    s = 2j * np.pi * np.asarray(frequency, dtype=float)
    tyre = axle.tyre_rate + axle.tyre_damping * s
    suspension = axle.damping * s + axle.suspension_rate
    denominator = (axle.unsprung_mass * s**2 + suspension + tyre) * (m_b * s**2 + suspension) - suspension**2
    return (axle.unsprung_mass * s**2 + tyre) / denominator, -m_b * s**2 / denominator


def quarter_car_on_servo_frf(vehicle: Vehicle, corner: str, frequency: np.ndarray) -> dict[str, np.ndarray]:
    """Closed-form FRFs from post drive for a quarter car standing on one servo post.

    Post model as in rig/vehicle/rig_config.py: reference a = e^(-sT) / (1 + s tau) * drive; post mass m_p with
    m_p x_p'' = kp (a - x_p) - kv x_p' - F_tyre. Returns post, unsprung and sprung displacement over drive.
    """
    rig = vehicle.rig
    axle = vehicle.axle(corner)
    m_b = corner_sprung_mass(vehicle, corner)
    s = 2j * np.pi * np.asarray(frequency, dtype=float)
    reference = np.exp(-s * rig.servo_delay) / (1 + s * rig.lag_time_constant)
    tyre = axle.tyre_rate + axle.tyre_damping * s
    suspension = axle.suspension_rate + axle.damping * s
    servo = rig.loop_stiffness + rig.loop_damping_coefficient * s
    post_x, wheel_x, body_x = [], [], []
    for k, s_k in enumerate(s):
        dynamic = np.array([
            [rig.post_mass * s_k**2 + servo[k] + tyre[k], -tyre[k], 0.0],
            [-tyre[k], axle.unsprung_mass * s_k**2 + tyre[k] + suspension[k], -suspension[k]],
            [0.0, -suspension[k], m_b * s_k**2 + suspension[k]],
        ])
        x = np.linalg.solve(dynamic, np.array([rig.loop_stiffness * reference[k], 0.0, 0.0]))
        post_x.append(x[0]), wheel_x.append(x[1]), body_x.append(x[2])
    return {"post": np.array(post_x), "unsprung": np.array(wheel_x), "sprung": np.array(body_x)}


def corner_sprung_mass(vehicle: Vehicle, corner: str) -> float:
    """Sprung mass carried statically by one corner in kg (lateral symmetry; the whole mass for a quarter car)."""
    if not vehicle.layout_type.footprint:
        return vehicle.sprung_mass
    if vehicle.layout_type.axle_list:
        raise ValueError(f"{vehicle.name}: the closed-form ride model is a car's; a truck's axles share its load "
                         f"as its springs and frame say (rig.vehicle.statics.settle solves it)")
    b = vehicle.wheelbase - vehicle.cg_to_front_axle
    axle_share = b / vehicle.wheelbase if corner[0] == "F" else vehicle.cg_to_front_axle / vehicle.wheelbase
    return vehicle.sprung_mass * axle_share / 2


@dataclass(frozen=True)
class StaticLoads:
    tyre_force: np.ndarray          # N per corner
    spring_force: np.ndarray        # N per corner (suspension: spring + parasitic rate)
    tyre_deflection: np.ndarray     # m per corner
    spring_deflection: np.ndarray   # m per corner


def static_loads(vehicle: Vehicle) -> StaticLoads:
    """Closed-form static corner loads and deflections (laterally symmetric car, g = 9.80665 m/s^2)."""
    corners = vehicle.corners
    spring = np.array([corner_sprung_mass(vehicle, c) * STANDARD_GRAVITY for c in corners])
    tyre = spring + np.array([vehicle.axle(c).unsprung_mass * STANDARD_GRAVITY for c in corners])
    return StaticLoads(
        tyre_force=tyre,
        spring_force=spring,
        tyre_deflection=tyre / np.array([vehicle.axle(c).tyre_rate for c in corners]),
        spring_deflection=spring / np.array([vehicle.axle(c).suspension_rate for c in corners]),
    )


def mck(vehicle: Vehicle) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Mass, damping and stiffness matrices about static equilibrium.

    Coordinates: full car [z, theta, phi, z_FL, z_FR, z_RL, z_RR]; quarter car [z_b, z_t].
    """
    corners = vehicle.corners
    n_body = len(vehicle.layout_type.ride_motions)
    n = n_body + len(corners)
    body_inertia = [vehicle.sprung_mass, vehicle.pitch_inertia, vehicle.roll_inertia][:n_body]
    mass = np.diag(body_inertia + [vehicle.axle(c).unsprung_mass for c in corners])
    damping, stiffness = np.zeros((n, n)), np.zeros((n, n))
    for i, corner in enumerate(corners):
        x, y = vehicle.corner_position(corner)
        axle = vehicle.axle(corner)
        compression = np.zeros(n)  # body corner height minus wheel height
        compression[:n_body] = [1.0, -x, y][:n_body]
        compression[n_body + i] = -1.0
        wheel = np.zeros(n)
        wheel[n_body + i] = 1.0
        stiffness += axle.suspension_rate * np.outer(compression, compression) + axle.tyre_rate * np.outer(wheel, wheel)
        damping += axle.damping * np.outer(compression, compression) + axle.tyre_damping * np.outer(wheel, wheel)
    return mass, damping, stiffness


def state_matrix(mass: np.ndarray, damping: np.ndarray, stiffness: np.ndarray) -> np.ndarray:
    """First-order state matrix A of M q'' + C q' + K q = 0, state [q, q']."""
    n = mass.shape[0]
    inverse = np.linalg.inv(mass)
    return np.block([[np.zeros((n, n)), np.eye(n)], [-inverse @ stiffness, -inverse @ damping]])


def modes(a: np.ndarray) -> list[tuple[float, float]]:
    """Undamped natural frequency (Hz) and damping ratio of each mode of state matrix ``a``, ascending.

    A complex pair counts once; real (overdamped) roots are reported as a frequency |s|/2pi with
    damping ratio 1 each.
    """
    roots = np.linalg.eigvals(a)
    result = []
    for s in roots:
        if s.imag < -1e-12:
            continue
        magnitude = abs(s)
        result.append((magnitude / (2 * np.pi), 1.0 if abs(s.imag) <= 1e-12 else -s.real / magnitude))
    return sorted(result)
