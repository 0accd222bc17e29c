"""Hardpoints identified from K&C curves (rig/diagnosis/kc/hardpoint_fit.py, ``rig kc --fit``) and the kinematic
diagnosis (``hardpoint_error``), on curves of the independent solver (tests/kinematics_reference.py) with noise."""

from __future__ import annotations

import tomllib

import numpy as np
import pytest

from kinematics_reference import sweep
from rig.diagnosis.kc.hardpoint_fit import fit_hardpoints, parse_free
from rig.diagnosis.kc.kinematic_diagnosis import diagnose_kc
from rig.io.kc_record import KcResult
from rig.vehicle.suspensions.hardpoints import KinematicsError
from rig.vehicle.vehicle_file import load_vehicle, resolve_vehicle_path

NOISE = 0.02  # deg, on every angle (the check); 0.01 mm on track change
MOVES = {"upper_outer": [0.002, -0.002, 0.003], "tie_rod_outer": [0.0, 0.003, -0.003]}  # 4.1 and 4.2 mm


def measured(points: dict, seed: int, samples: int = 17) -> list[KcResult]:
    """Travel (+-60 mm) and steer (+-20 mm) records of both front corners from the independent solver, noisy."""
    rng = np.random.default_rng(seed)
    records = []
    for test, values in (("travel", np.linspace(-0.06, 0.06, samples)), ("steer", np.linspace(-0.02, 0.02, samples))):
        curves = {}
        for corner, side in (("FL", 1), ("FR", -1)):
            reference = sweep(points, side, **({"travels": values} if test == "travel" else {"racks": values}))
            curves[f"{corner}/travel"] = values if test == "travel" else 0.0 * values
            for quantity in ("camber", "toe", "caster", "kingpin"):
                curves[f"{corner}/{quantity}"] = np.radians(reference[quantity] + rng.normal(0.0, NOISE, samples))
            curves[f"{corner}/track_change"] = reference["track_change"] + rng.normal(0.0, 1e-5, samples)
        records.append(KcResult("fs_car", test, "travel" if test == "travel" else "rack", values, ("FL", "FR"), curves))
    return records


@pytest.fixture(scope="module")
def fs_car():
    vehicle = load_vehicle("fs_car")
    table = tomllib.loads(resolve_vehicle_path("fs_car").read_text())["front"]["kinematics"]
    moved = {**table, **{name: list(np.add(table[name], offset)) for name, offset in MOVES.items()}}
    return vehicle, table, moved


@pytest.mark.parametrize("method", ["lm", pytest.param("nelder-mead", marks=pytest.mark.slow)])
def test_two_moved_hardpoints_are_recovered_within_half_a_millimetre(fs_car, method):
    vehicle, _, moved = fs_car
    free = parse_free("front.upper_outer,front.tie_rod_outer", vehicle)
    fit = fit_hardpoints(vehicle, measured(moved, seed=1), free, method=method)
    truth = np.concatenate([moved["upper_outer"], moved["tie_rod_outer"]])
    error = np.abs(fit.fitted - truth)
    assert np.max(error) < 5e-4, error
    assert np.max(np.abs(fit.fitted - fit.nominal)) > 2.5e-3  # they did move
    assert not fit.unidentifiable and np.all(error < 3 * fit.interval)  # intervals of the right size
    assert np.degrees(fit.residual_rms["camber"]) == pytest.approx(NOISE, rel=0.3)


def test_what_the_curves_cannot_identify_is_named(fs_car):
    """Both inner pivots of the lower wishbone sliding along x move its axis along itself: the curves cannot tell."""
    vehicle, table, _ = fs_car
    fit = fit_hardpoints(vehicle, measured(table, seed=2), parse_free("lower_front.x,lower_rear.x,upper_outer.z",
                                                                      vehicle))
    assert fit.unidentifiable == ["front.lower_front.x", "front.lower_rear.x"]
    assert np.isfinite(fit.interval[2]) and abs(fit.fitted[2] - fit.nominal[2]) < 5e-4


def test_bad_free_names_are_refused(fs_car):
    vehicle, _, _ = fs_car
    with pytest.raises(KinematicsError, match="no hardpoint 'upper_outr'"):
        parse_free("upper_outr", vehicle)
    with pytest.raises(KinematicsError, match="a coordinate is x, y or z"):
        parse_free("upper_outer.w", vehicle)


def test_the_kinematic_diagnosis_names_a_hardpoint_error_and_not_noise(fs_car):
    """On K&C records of the moved hardpoints the verdict is hardpoint_error, and the extended vehicle (all the
    coordinates the curves identify, fitted together) leaves only the noise; on records of the table's own
    hardpoints (noise only) it is none."""
    vehicle, table, moved = fs_car
    moved_records = measured(moved, seed=3, samples=13)
    result = diagnose_kc(vehicle, moved_records)
    assert result.verdict == "hardpoint_error" and result.hardpoints.significance.p_value < 1e-6
    assert "upper_outer" in result.extended_vehicle.extensions["hardpoint_error"]["front"]
    assert all(np.degrees(result.hardpoints.fit.residual_rms[q]) < 1.5 * NOISE
               for q in ("camber", "toe", "caster", "kingpin"))
    assert diagnose_kc(vehicle, measured(table, seed=4, samples=13)).verdict == "none"


@pytest.mark.slow
def test_rig_kc_on_a_car_with_a_hidden_hardpoint_error_is_diagnosed(fs_car):
    """End to end: two hardpoints moved 3-5 mm at random (the cause's own ``hidden``), the car measured by ``rig kc``
    (MuJoCo), the records diagnosed against the table's car: hardpoint_error, residuals at the rig's precision."""
    from rig.causes.hardpoint_error import CAUSE
    from rig.sim.kc import run_kc

    vehicle, _, _ = fs_car
    truth = CAUSE.hidden(vehicle, np.random.default_rng(5))
    records = [run_kc(truth, test, steps=13) for test in ("travel", "steer")]
    result = diagnose_kc(vehicle, records)
    assert result.verdict == "hardpoint_error"
    assert max(np.degrees(result.hardpoints.fit.residual_rms[q]) for q in ("camber", "toe", "caster", "kingpin")) < 1e-3
