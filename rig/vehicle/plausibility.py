"""Plausibility of a vehicle file that fits every real vehicle and rig, from a lab quarter car to a laden truck.

Absolute ranges of masses and rates would refuse real rigs (a university bench's 2.1 kg body on a 1.5 kN/m spring)
or real trucks; a file written in the wrong units (a mass in g or t, a rate in N/mm, a damping in N s/mm) shows
instead in what its numbers make of each wheel station. Per axle, with m_c the sprung mass a station carries (the
static loads of a rigid body on the axles' ride rates), k_s the suspension rate (spring + parasitic), k_t the tyre
rate of the station (twice a tyre's for dual tyres), m_u the unsprung mass, c and c_t the damping and tyre damping:

- rate ratios: k_p / k_spring (bushings softer than the spring, 0-2), k_s / k_t (0.01-5);
- the mass ratio m_u / m_c (0.005-10);
- the body (ride) frequency sqrt(k_ride / m_c) / 2 pi, k_ride = k_s k_t / (k_s + k_t): 0.3-10 Hz;
- the wheel-hop frequency sqrt((k_s + k_t) / m_u) / 2 pi: 1.5-60 Hz;
- the damping ratios c / (2 sqrt(k_s m_c)) (0.002-5 where there is a damper) and c_t / (2 sqrt(k_t m_u)) (0-2);
- the sprung body's radii of gyration over its wheelbase (pitch, yaw: 0.1-2) and track (roll: 0.05-2).

Each band holds cars, race cars, trucks and lab benches with margin; a factor of 1000 (or its square root, for a
frequency) leaves it. ``corner_findings`` returns what is out, each a sentence naming the check and its numbers.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from rig.io.units import STANDARD_GRAVITY

if TYPE_CHECKING:
    from rig.vehicle.parts import Axle, Vehicle

BODY_HZ = (0.3, 10.0)
WHEEL_HOP_HZ = (1.5, 60.0)
SPRING_TO_TYRE = (0.01, 5.0)
PARASITIC_TO_SPRING = (0.0, 2.0)
UNSPRUNG_TO_SPRUNG = (0.005, 10.0)
BODY_DAMPING_RATIO = (0.002, 5.0)
TYRE_DAMPING_RATIO = (0.0, 2.0)
PITCH_GYRATION_TO_WHEELBASE = (0.1, 2.0)
ROLL_GYRATION_TO_TRACK = (0.05, 2.0)
HINT = "vehicle files are in SI units (kg, N/m, N s/m, kg m^2): a value in g, t, N/mm or mm?"


@dataclass(frozen=True)
class Station:
    """What the numbers of one axle make of each of its wheel stations (SI)."""

    axle: str
    sprung_mass: float     # kg carried by the station
    suspension_rate: float  # N/m, spring + parasitic
    tyre_rate: float       # N/m, the station's tyres together
    body_hz: float
    wheel_hop_hz: float
    body_damping_ratio: float
    tyre_damping_ratio: float


def axle_loads(vehicle: Vehicle) -> np.ndarray:
    """Static load of each axle (N, front to rear): the sprung body (with a truck's cab and driveline) as a rigid
    body in heave and pitch on the axles' ride rates; for two axles, the lever rule."""
    axles = vehicle.axles
    weights = [(vehicle.sprung_mass, vehicle.cg_to_front_axle)]
    weights += [(body.mass, body.position) for body in (vehicle.cab, vehicle.driveline) if body is not None]
    total = sum(m for m, _ in weights) * STANDARD_GRAVITY
    if len(axles) == 1:
        return np.array([total])
    moment = sum(m * x for m, x in weights) * STANDARD_GRAVITY / total  # m behind the front axle
    positions = np.array([_position(vehicle, i) for i in range(len(axles))])
    rates = np.array([_ride_rate(a) for a in axles])
    # loads k_i (z + theta x_i): sum = total, sum x_i = total * moment
    matrix = np.array([[rates.sum(), rates @ positions], [rates @ positions, rates @ positions**2]])
    z, theta = np.linalg.solve(matrix, [total, total * moment])
    return rates * (z + theta * positions)


def stations(vehicle: Vehicle) -> list[Station]:
    """Each axle's station figures, front to rear."""
    loads = axle_loads(vehicle)
    per_axle = vehicle.layout_type.corners_per_axle
    found = []
    for name, axle, load in zip(vehicle.axle_names, vehicle.axles, loads):
        mass = float(load) / STANDARD_GRAVITY / per_axle
        k_s, k_t = axle.suspension_rate, _tyre_rate(axle)
        ride = k_s * k_t / (k_s + k_t) if k_s > 0 else 0.0
        found.append(Station(
            name, mass, k_s, k_t, _hz(ride, mass), _hz(k_s + k_t, axle.unsprung_mass),
            axle.damping / (2 * math.sqrt(k_s * mass)) if k_s > 0 and mass > 0 else math.inf,
            axle.tyre_damping / (2 * math.sqrt(k_t * axle.unsprung_mass))))
    return found


def corner_findings(vehicle: Vehicle) -> list[str]:
    """What is implausible about the vehicle's stations and body, each one sentence (empty: plausible)."""
    found = []
    for station, axle in zip(stations(vehicle), vehicle.axles):
        found += _station_findings(station, axle, _label(vehicle, station.axle))
    return found + _inertia_findings(vehicle)


def _station_findings(s: Station, axle: Axle, label: str) -> list[str]:
    tyre = "tyre_rate" + (" x 2 (dual)" if axle.tyres == "dual" else "")
    per_station = f"{s.sprung_mass:.4g} kg of sprung mass per station"
    checks = [
        ("suspension rate / tyre rate", s.suspension_rate / s.tyre_rate, "", SPRING_TO_TYRE,
         f"spring + parasitic {s.suspension_rate:g} N/m over {tyre} {s.tyre_rate:g} N/m"),
        ("body (ride) frequency", s.body_hz, " Hz", BODY_HZ,
         f"{per_station} on spring + parasitic {s.suspension_rate:g} N/m and {tyre} {s.tyre_rate:g} N/m"),
        ("wheel-hop frequency", s.wheel_hop_hz, " Hz", WHEEL_HOP_HZ,
         f"unsprung_mass = {axle.unsprung_mass:g} kg on {s.suspension_rate + s.tyre_rate:g} N/m"),
        ("unsprung / sprung mass", axle.unsprung_mass / s.sprung_mass, "", UNSPRUNG_TO_SPRUNG,
         f"unsprung_mass = {axle.unsprung_mass:g} kg over the {per_station}"),
        ("tyre damping ratio", s.tyre_damping_ratio, "", TYRE_DAMPING_RATIO,
         f"tyre_damping = {axle.tyre_damping:g} N s/m on unsprung_mass and {tyre}"),
    ]
    if axle.spring_rate > 0:
        checks.insert(0, ("parasitic_rate / spring_rate", axle.parasitic_rate / axle.spring_rate, "",
                          PARASITIC_TO_SPRING,
                          f"{axle.parasitic_rate:g} / {axle.spring_rate:g} N/m: bushings stiffer than the spring"))
    if axle.damping > 0:
        checks.append(("body damping ratio", s.body_damping_ratio, "", BODY_DAMPING_RATIO,
                       f"damping = {axle.damping:g} N s/m on the {per_station} and {s.suspension_rate:g} N/m"))
    return [f"{label} {check} = {value:.3g}{unit} ({detail}) is outside the plausible {low:g}..{high:g}{unit} of any "
            f"vehicle or rig; {HINT}" for check, value, unit, (low, high), detail in checks if not low <= value <= high]


def _inertia_findings(vehicle: Vehicle) -> list[str]:
    """Radii of gyration of the sprung body against its wheelbase and track (cars and trucks)."""
    if not vehicle.layout_type.footprint:
        return []
    track = max(vehicle.track_front, vehicle.track_rear)
    checks = [("pitch_inertia", vehicle.pitch_inertia, vehicle.wheelbase, "wheelbase", PITCH_GYRATION_TO_WHEELBASE),
              ("yaw_inertia", vehicle.yaw_inertia, vehicle.wheelbase, "wheelbase", PITCH_GYRATION_TO_WHEELBASE),
              ("roll_inertia", vehicle.roll_inertia, track, "track", ROLL_GYRATION_TO_TRACK)]
    found = []
    for key, inertia, length, name, (low, high) in checks:
        ratio = math.sqrt(inertia / vehicle.sprung_mass) / length
        if not low <= ratio <= high:
            found.append(f"[sprung] {key.split('_')[0]} radius of gyration / {name} = {ratio:.3g} ({key} = "
                         f"{inertia:g} kg m^2 on mass = {vehicle.sprung_mass:g} kg: "
                         f"{math.sqrt(inertia / vehicle.sprung_mass):.3g} m over {length:g} m) is outside the "
                         f"plausible {low:g}..{high:g} of any vehicle or rig; {HINT}")
    return found


def _label(vehicle: Vehicle, axle: str) -> str:
    if not vehicle.layout_type.axle_list:
        return f"[{axle}]"
    index = vehicle.axle_names.index(axle)
    return f"[[axles]] {index + 1} ({axle})"


def _position(vehicle: Vehicle, index: int) -> float:
    """Axle ``index``'s distance behind the front axle (m)."""
    if vehicle.layout_type.axle_list:
        return vehicle.axles[index].position
    return 0.0 if index == 0 else vehicle.wheelbase


def _tyre_rate(axle: Axle) -> float:
    return axle.tyre_rate * (2 if axle.tyres == "dual" else 1)


def _ride_rate(axle: Axle) -> float:
    k_s, k_t = axle.suspension_rate, _tyre_rate(axle)
    return k_s * k_t / (k_s + k_t)


def _hz(rate: float, mass: float) -> float:
    return math.sqrt(rate / mass) / (2 * math.pi) if mass > 0 else math.inf
