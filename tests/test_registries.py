"""A new suspension type, a new record file format and a new cause are each one module and nothing else: a throwaway
one of each (tests/throwaway_*.py) is registered at test time and works end to end, checked against physics."""

import dataclasses
import tomllib

import numpy as np
import pytest
import throwaway_cause
import throwaway_format
import throwaway_suspension
from independent_truck import Truck

from rig import Record, load_vehicle, replay, tddi
from rig.causes import CAUSES, register_cause, unregister_cause
from rig.cli.main import main
from rig.diagnosis.rig_test.synthetic import event_drive
from rig.io.files import read_record, register_format, unregister_format, write_record, writable_suffixes
from rig.io.record import RecordError
from rig.io.units import STANDARD_GRAVITY
from rig.vehicle.assets import vehicle_path
from rig.vehicle.mjcf import build_model
from rig.vehicle.statics import settle
from rig.vehicle.suspensions import register_suspension, suspensions, unregister_suspension
from rig.vehicle.vehicle_file import VehicleError, vehicle_from_dict, vehicle_to_toml

RATE = 256.0
COIL_RATE = 3.5e5  # N/m: truck_6x4's front leaf springs' rate, given to coils instead


@pytest.fixture
def beam_coil():
    register_suspension(throwaway_suspension.SUSPENSION)
    yield throwaway_suspension.SUSPENSION
    unregister_suspension(throwaway_suspension.SUSPENSION.name)


@pytest.fixture
def npz_format():
    register_format(throwaway_format.FORMAT)
    yield throwaway_format.FORMAT
    unregister_format(throwaway_format.FORMAT)


@pytest.fixture
def ballast():
    register_cause(throwaway_cause.CAUSE)
    yield throwaway_cause.CAUSE
    unregister_cause(throwaway_cause.CAUSE.name)


def _truck_on_coils() -> dict:
    """truck_6x4's tables with its front axle on ``beam_coil`` springs, their rate in their own sub-table."""
    data = tomllib.loads(vehicle_path("truck_6x4").read_text())
    front = data["axles"][0]
    for key in ("spring_rate", "leaf_spring"):
        del front[key]
    front.update(suspension="beam_coil", coil_spring={"rate": COIL_RATE})
    return data


def test_a_suspension_type_with_a_parameter_of_its_own_reads_writes_and_simulates_as_an_independent_model(beam_coil):
    """The new type's truck, rigid frame, replayed on six servo posts, against the independent truck simulator given
    the same axle as a frictionless leaf-sprung one (a linear spring of the coil's rate): TDDI <= 1e-3 per channel."""
    truck = vehicle_from_dict(_truck_on_coils(), "coil truck")
    assert truck.front.suspension == "beam_coil" and truck.front.spring_rate == COIL_RATE  # the type's law_rate
    assert "coil_spring" in vehicle_to_toml(truck) and vehicle_from_dict(tomllib.loads(vehicle_to_toml(truck))) == \
        dataclasses.replace(truck, source="vehicle")
    rigid = dataclasses.replace(truck, frame=None)
    twin = rigid.with_axle("front", dataclasses.replace(rigid.front, suspension="beam_leaf", law=None))
    values = event_drive(rigid.corners, 3.0, RATE, np.random.default_rng(1))
    drive = Record(RATE, {f"{c}/drive": values[:, i] for i, c in enumerate(rigid.corners)})
    model = replay(rigid, drive).record
    independent = Truck(twin).run(values, RATE)
    worst = max(tddi(model[f"{c}/{quantity}"], out[:, i]) for quantity, out in independent.items()
                if quantity != "seat_acc" for i, c in enumerate(rigid.corners))
    assert worst <= 1e-3
    assert np.ptp(model["FL/unsprung_acc"]) > 20.0  # the events shake the coil-sprung axle


def test_a_suspension_type_refuses_its_own_table_missing_and_is_gone_when_unregistered(beam_coil):
    data = _truck_on_coils()
    del data["axles"][0]["coil_spring"]
    with pytest.raises(VehicleError, match=r"a beam_coil axle needs its \[axles.coil_spring\] table"):
        vehicle_from_dict(data, "coil truck")
    unregister_suspension("beam_coil")
    assert "beam_coil" not in suspensions()
    with pytest.raises(VehicleError, match=r"suspension must be one of .*got 'beam_coil'"):
        vehicle_from_dict(_truck_on_coils(), "coil truck")


def test_a_record_format_reads_what_it_writes_through_the_record_functions_and_the_command_line(npz_format, tmp_path):
    drive = event_drive(("FL",), 2.0, RATE, np.random.default_rng(2))[:, 0]
    record = Record(RATE, {"FL/drive": drive}, units={"FL/drive": "m"})
    write_record(tmp_path / "drive.npz", record)
    back = read_record(tmp_path / "drive.npz")
    assert back.rate == RATE and np.array_equal(back["FL/drive"], record["FL/drive"])
    assert ".npz" in writable_suffixes()
    (tmp_path / "drive.xyz").write_text("x")
    listed = r"use \.csv, RPC III \.rsp/\.drv/\.tim, MDF \.mf4, TDMS \.tdms or NumPy \.npz"
    with pytest.raises(RecordError, match=listed):
        read_record(tmp_path / "drive.xyz")
    assert main(["replay", "--vehicle", "proton_x_quarter", "--drive", str(tmp_path / "drive.npz"),
                 "--out", str(tmp_path / "response.npz")]) == 0
    response = read_record(tmp_path / "response.npz")
    assert response.rate == RATE and response.n_samples == 512 and np.ptp(response["FL/sprung_acc"]) > 0


def test_a_format_cannot_take_a_suffix_another_format_has(npz_format):
    with pytest.raises(ValueError, match=r"\.npz already"):
        register_format(throwaway_format.FORMAT)


def test_a_cause_joins_the_vocabulary_and_builds_into_the_model_where_statics_say(ballast, capsys):
    """50 kg at a quarter car's CG: the body's mass in the model rises by it, the tyre carries its weight more, and
    the body settles lower by m g (1 / (k_s + k_p) + 1 / k_t), the hub by m g / k_t."""
    assert "ballast" in CAUSES
    assert main(["causes"]) == 0
    assert "ballast (car): the body carries a mass at its CG" in capsys.readouterr().out
    plain = load_vehicle("proton_x_quarter")
    data = tomllib.loads(vehicle_to_toml(plain)) | {"ballast": {"mass": 50.0}}
    loaded = vehicle_from_dict(data, "ballasted")
    assert loaded.extensions["ballast"] == throwaway_cause.Ballast(50.0)
    assert "[ballast]" in vehicle_to_toml(loaded)
    states = [settle(build_model(v, RATE)) for v in (plain, loaded)]
    models = [build_model(v, RATE).model for v in (plain, loaded)]
    body = [m.body("car.body").id for m in models]
    assert models[1].body_mass[body[1]] - models[0].body_mass[body[0]] == pytest.approx(50.0)
    weight, axle = 50.0 * STANDARD_GRAVITY, plain.front
    assert states[1].tyre_force[0] - states[0].tyre_force[0] == pytest.approx(weight, rel=1e-6)
    drops = states[0].heights - states[1].heights  # body site, hub
    assert drops[0] == pytest.approx(weight * (1 / axle.suspension_rate + 1 / axle.tyre_rate), rel=1e-4)
    assert drops[1] == pytest.approx(weight / axle.tyre_rate, rel=1e-4)


def test_a_cause_is_gone_from_vehicle_files_when_unregistered(ballast):
    data = tomllib.loads(vehicle_to_toml(load_vehicle("proton_x_quarter"))) | {"ballast": {"mass": 50.0}}
    unregister_cause("ballast")
    with pytest.raises(VehicleError, match=r"unknown section\(s\) ballast"):
        vehicle_from_dict(data, "ballasted")
