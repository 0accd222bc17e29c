"""The truck causes (rig/causes/: leaf_friction, air_spring_law, frame_flexibility, cab_mounts, cab_air_spring,
driveline_mounts, and mass_error's truck payload): each realised in the MuJoCo model as the independent simulator
(tests/independent_truck.py) computes the same physics from the equations, its hidden instance readable back from a
vehicle file, and its section refused where it cannot apply."""

import dataclasses
import tomllib

import numpy as np
import pytest
from independent_truck import Truck, equivalent

from support.frames import frame_frequencies

from rig import Record, load_vehicle, replay, tddi
from rig.causes import CAUSES, causes_seen_on
from rig.diagnosis.rig_test.selection import screened
from rig.diagnosis.rig_test.synthetic import event_drive
from rig.elements.frame import Frame
from rig.vehicle.truck_mjcf import frame_of
from rig.vehicle.vehicle_file import VehicleError, vehicle_from_dict, vehicle_to_toml

RATE = 256.0
TRUCK_CAUSES = ("leaf_friction", "air_spring_law", "frame_flexibility", "cab_mounts", "driveline_mounts")


@pytest.fixture(scope="module")
def rigid():
    return dataclasses.replace(load_vehicle("truck_6x4"), frame=None)


def worst_tddi(with_cause, equivalent) -> float:
    """Worst per-channel TDDI (the seat's too) between the MuJoCo replay of ``with_cause`` and the independent
    simulator's run of ``equivalent`` (the same physics written into the vehicle's own parameters)."""
    values = event_drive(with_cause.corners, 2.0, RATE, np.random.default_rng(2))
    model = replay(with_cause, Record(RATE, {f"{c}/drive": values[:, i] for i, c in enumerate(with_cause.corners)}))
    independent = Truck(equivalent).run(values, RATE)
    seat = [tddi(model.record["cab/seat_acc"], independent["seat_acc"])] if "seat_acc" in independent else []
    return max(seat + [tddi(model.record[f"{c}/{q}"], out[:, i]) for q, out in independent.items() if q != "seat_acc"
                       for i, c in enumerate(with_cause.corners)])


def test_hidden_leaf_friction_is_fanchers_law_on_the_front_springs(rigid):
    truth = CAUSES["leaf_friction"].hidden(rigid, np.random.default_rng(1))
    law = truth.extensions["leaf_friction"]["front"]
    assert law != rigid.front.law
    assert worst_tddi(truth, rigid.with_axle("front", dataclasses.replace(rigid.front, law=law))) <= 1e-3


def test_hidden_air_spring_law_is_the_polytropic_law_on_the_tandem(rigid):
    truth = CAUSES["air_spring_law"].hidden(rigid, np.random.default_rng(1))
    laws = truth.extensions["air_spring_law"]
    assert set(laws) == {"middle", "rear"} and laws["middle"].volume < rigid.axle_named("middle").law.volume
    equivalent = rigid
    for axle, law in laws.items():
        equivalent = equivalent.with_axle(axle, dataclasses.replace(equivalent.axle_named(axle), law=law))
    assert worst_tddi(truth, equivalent) <= 1e-3


def test_hidden_cab_mounts_are_the_cabs_springs_and_dampers(rigid):
    truth = CAUSES["cab_mounts"].hidden(rigid, np.random.default_rng(1))
    mounts = truth.extensions["cab_mounts"]
    assert mounts.stiffness < 0.75 * rigid.cab.stiffness
    equivalent = dataclasses.replace(rigid, cab=dataclasses.replace(rigid.cab, stiffness=mounts.stiffness,
                                                                    damping=mounts.damping))
    assert worst_tddi(truth, equivalent) <= 1e-3


@pytest.mark.parametrize("name, vehicle", [("driveline_mounts", "truck_6x4"), ("cab_mounts", "tractor_4x2"),
                                           ("cab_air_spring", "tractor_4x2"), ("mass_error", "truck_6x4")])
def test_hidden_mounts_cab_air_springs_and_a_trucks_payload_are_what_the_independent_simulator_computes(name, vehicle):
    """The driveline's mounts, a cab on air springs given linear mounts or another volume, a payload of tonnes: the
    simulator takes each written into the truck's own tables (``equivalent``)."""
    truck = dataclasses.replace(load_vehicle(vehicle), frame=None)
    truth = CAUSES[name].hidden(dataclasses.replace(truck, extensions={}), np.random.default_rng(5))
    if name == "mass_error":  # on the centre line: the simulator's sprung body has no product of inertia
        truth = dataclasses.replace(truth, extensions={name: dataclasses.replace(truth.extensions[name], y=0.0)})
        assert truth.extensions[name].mass > 0.1 * truck.sprung_mass  # a truck's scale: tonnes
    assert worst_tddi(truth, equivalent(truth)) <= 1e-3


def test_hidden_frame_flexibility_gives_the_rigid_truck_a_frame_with_the_drawn_torsion_mode(rigid):
    truth = CAUSES["frame_flexibility"].hidden(rigid, np.random.default_rng(1))
    flex = truth.extensions["frame_flexibility"]
    frame = frame_of(truth)
    assert isinstance(frame, Frame) and frame.segments == 8
    uniform = dataclasses.replace(frame, damping_ratio=0.0)
    bending, torsion = frame_frequencies(uniform, rigid.sprung_mass, rigid.roll_inertia)
    assert torsion[0] / (2 * np.pi) == pytest.approx(flex.torsion_frequency, rel=0.01)
    assert bending[0] / (2 * np.pi) == pytest.approx(flex.bending_frequency, rel=0.01)
    values = event_drive(rigid.corners, 2.0, RATE, np.random.default_rng(2))
    drive = Record(RATE, {f"{c}/drive": values[:, i] for i, c in enumerate(rigid.corners)})
    flexible, stiff = replay(truth, drive).record, replay(rigid, drive).record
    assert tddi(stiff["FL/sprung_acc"], flexible["FL/sprung_acc"]) > 0.01  # the frame's modes show on the body


@pytest.mark.parametrize("name", TRUCK_CAUSES)
def test_a_truck_cause_reads_back_from_its_vehicle_file_and_cannot_hide_in_a_car(rigid, name):
    truth = CAUSES[name].hidden(load_vehicle("truck_6x4"), np.random.default_rng(3))
    assert vehicle_from_dict(tomllib.loads(vehicle_to_toml(truth)), truth.source).extensions == truth.extensions
    with pytest.raises(ValueError):
        CAUSES[name].hidden(load_vehicle("proton_x"), np.random.default_rng(3))


def test_a_trucks_rig_diagnosis_screens_the_truck_causes_and_a_cars_does_not():
    quantities = {"drive", "actuator_disp", "sprung_acc", "unsprung_acc", "susp_travel"}
    truck = screened(causes_seen_on("rig"), "truck", quantities)
    car = screened(causes_seen_on("rig"), "full", quantities)
    assert set(TRUCK_CAUSES) <= set(truck) and not set(TRUCK_CAUSES) & set(car)
    # a beam axle has no strut: its friction is the leaves', its damper has no top mount
    assert {"strut_friction", "top_mount_compliance"} <= set(car) - set(truck)
    assert {"damper_asymmetry", "tyre_damping", "mass_error", "actuator_lag", "sensor_gain"} <= set(truck) & set(car)
    assert "bearing_friction" not in truck and "measured_law" not in truck  # a bench's; a generic element
    assert "force_constant_error" not in truck  # it needs an active_force record


def test_truck_cause_sections_are_refused_where_they_cannot_apply():
    car = tomllib.loads(vehicle_to_toml(load_vehicle("proton_x")))
    with pytest.raises(VehicleError, match=r"\[cab_mounts\] applies to layout truck"):
        vehicle_from_dict({**car, "cab_mounts": {"stiffness": 2e4, "damping": 1e3}})
    truck = tomllib.loads(vehicle_to_toml(load_vehicle("truck_6x4")))
    with pytest.raises(VehicleError, match=r"\[leaf_friction\] rear: not on leaf springs"):
        vehicle_from_dict({**truck, "leaf_friction": {"rear": {"friction": 2000.0, "decay_length": 0.004}}})
    no_cab = {k: v for k, v in truck.items() if k != "cab"}
    with pytest.raises(VehicleError, match="needs a \\[cab\\]"):
        vehicle_from_dict({**no_cab, "cab_mounts": {"stiffness": 2e4, "damping": 1e3}})
