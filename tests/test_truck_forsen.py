"""Forsén's test vehicle (Forsén 1999), laden and unladen: tractor_4x2 and tractor_4x2_unladen stand on the rig with
the axle loads of the thesis's Table 1, the cab on air springs as the thesis models it (adiabatic compression), the
MuJoCo model against the independent simulator (tests/independent_truck.py) with the cab's springs by the law itself."""

import dataclasses

import mujoco
import numpy as np
import pytest
from independent_truck import Truck

from rig import Record, load_vehicle, replay, tddi
from rig.diagnosis.rig_test.synthetic import event_drive
from rig.vehicle.mjcf import build_model
from rig.vehicle.statics import STATE_SPEC, settle
from rig.vehicle.vehicle_file import VehicleError, vehicle_from_dict, vehicle_to_toml

G = 9.80665
#: Forsén (1999), Table 1: the test vehicle's axle loads (kg), front and rear
THESIS_AXLE_LOADS = {"tractor_4x2": (7770.0, 13041.0), "tractor_4x2_unladen": (5441.0, 2306.0)}


def settled(vehicle):
    rig = build_model(vehicle, 256.0, "servo")
    static = settle(rig)
    data = mujoco.MjData(rig.model)
    mujoco.mj_setState(rig.model, data, static.state, STATE_SPEC)
    mujoco.mj_forward(rig.model, data)
    return rig, static, data


@pytest.mark.parametrize("name", THESIS_AXLE_LOADS)
def test_the_tractor_stands_on_the_thesiss_axle_loads_within_a_tenth_of_a_percent(name):
    rig, static, data = settled(load_vehicle(name))
    loads = static.tyre_force / G
    front, rear = loads[:2].sum(), loads[2:].sum()
    assert (front, rear) == pytest.approx(THESIS_AXLE_LOADS[name], rel=1e-3)
    # the level valve's work: the rear air springs and the cab's stand at their design height (within 1 mm)
    model = rig.model
    for corner in ("RL", "RR"):
        tendon = model.tendon(f"car.{corner}/suspension").id
        assert abs(data.ten_length[tendon] - model.tendon_lengthspring[tendon][0]) < 1e-3
    for mount in ("front_left", "rear_right"):
        assert abs(data.ten_length[model.tendon(f"car.cab/{mount}_mount").id]) < 1e-3


def test_laden_and_unladen_are_one_tractor_less_its_ballast():
    laden, unladen = load_vehicle("tractor_4x2"), load_vehicle("tractor_4x2_unladen")
    for key in ("wheelbase", "cab", "driveline", "front"):
        assert getattr(laden, key) == getattr(unladen, key), key
    assert laden.frame.bending_stiffness == unladen.frame.bending_stiffness
    assert laden.frame.torsion_stiffness == unladen.frame.torsion_stiffness
    assert dataclasses.replace(laden.rear.law, pressure=0.0) == dataclasses.replace(unladen.rear.law, pressure=0.0)
    ballast = laden.sprung_mass - unladen.sprung_mass
    assert ballast == pytest.approx(sum(THESIS_AXLE_LOADS["tractor_4x2"]) - sum(THESIS_AXLE_LOADS[
        "tractor_4x2_unladen"]))
    # the ballast's CG between the axles, ahead of the rear axle as a fifth wheel's load is
    at = (laden.sprung_mass * laden.cg_to_front_axle - unladen.sprung_mass * unladen.cg_to_front_axle) / ballast
    assert 2.5 < at < laden.wheelbase


@pytest.mark.parametrize("name", THESIS_AXLE_LOADS)
def test_the_tractor_with_its_cab_on_air_springs_matches_the_independent_simulator(name):
    """Rigid frame (the independent simulator's): leaf friction, rear and cab air springs by the polytropic law itself,
    twin tyres, four servo posts; the cab bounces at 1.39 Hz on its springs' rate at design height."""
    tractor = dataclasses.replace(load_vehicle(name), frame=None)
    cab = tractor.cab
    assert cab.air_spring is not None and cab.stiffness == pytest.approx(cab.air_spring.rate)
    assert np.sqrt(4 * cab.stiffness / cab.mass) / (2 * np.pi) == pytest.approx(1.39, abs=0.01)
    values = event_drive(tractor.corners, 3.0, 256.0, np.random.default_rng(4))
    model = replay(tractor, Record(256.0, {f"{c}/drive": values[:, i] for i, c in enumerate(tractor.corners)})).record
    independent = Truck(tractor).run(values, 256.0)
    worst = {"cab/seat_acc": tddi(model["cab/seat_acc"], independent["seat_acc"])}
    worst |= {f"{c}/{q}": tddi(model[f"{c}/{q}"], out[:, i]) for q, out in independent.items() if q != "seat_acc"
              for i, c in enumerate(tractor.corners)}
    assert max(worst.values()) <= 1e-3, sorted(worst.items(), key=lambda kv: -kv[1])[:3]
    assert np.ptp(model["cab/seat_acc"]) > 0.5  # the cab moves on its springs


def test_a_cab_on_air_springs_reads_back_and_refuses_a_stiffness_beside_them():
    tractor = load_vehicle("tractor_4x2")
    import tomllib

    table = tomllib.loads(vehicle_to_toml(tractor))
    assert vehicle_from_dict(table, tractor.source) == tractor
    table["cab"]["stiffness"] = 3e4
    with pytest.raises(VehicleError, match=r"\[cab\] give stiffness or \[cab.air_spring\]"):
        vehicle_from_dict(table)
