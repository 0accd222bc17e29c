"""Damper laws with the dynamics real dampers show (rig/diagnosis/dyno/damper_dynamics.py, dynamic_damper_fit.py): the
lag
and Dahl's friction against their closed forms and ODEs, a damper whose force lags its law by 25 ms with the seals'
friction fitted to its noise from records integrated by an ODE solver (tests/dyno_cases.py), the residual tests that
tell the law from a static one, the law written into a vehicle file, and a monotube damper simulated from its
hydraulics (tests/independent_damper.py) as a stand-in for a real record."""

import json

import numpy as np
import pytest
from dyno_cases import LAGGING, dyno_records
from scipy.integrate import solve_ivp

from rig.cli.main import main
from rig.diagnosis.dyno.damper_dynamics import friction_shape, lagged
from rig.diagnosis.dyno.damper_in_vehicle import damper_in_vehicle
from rig.diagnosis.dyno.damper_choice import fit_damper
from rig.diagnosis.dyno.damper_law import DamperLaw
from rig.diagnosis.dyno.dyno_test import dyno_test
from rig.io.files import write_record
from rig.vehicle.vehicle_file import load_vehicle

LAWS = ["digressive+preload", "digressive+preload+series", "digressive+preload+lag+hysteresis"]


@pytest.fixture(scope="module")
def records():
    """The lagging damper's programme: 2 % noise on the force, 0.5 % on the displacement (an LVDT's)."""
    return dyno_records(LAGGING, noise=0.02, displacement_noise=0.005)


@pytest.fixture(scope="module")
def lagging(records):
    return dyno_test(records)


def test_the_lag_is_the_first_order_lag_in_closed_form():
    """A ramp r t through tau F' + F = u from rest: F = r (t - tau (1 - exp(-t / tau))), exact at the samples."""
    rate, tau, r = 300.0, 0.025, 2.0
    t = np.arange(600) / rate
    np.testing.assert_allclose(lagged(r * t, rate, tau), r * (t - tau * (1 - np.exp(-t / tau))), atol=1e-12)
    np.testing.assert_allclose(lagged(np.full(50, 3.0), rate, tau), 3.0)  # from rest at its first value


def test_the_friction_is_dahl_s_model():
    """Along a sine stroke, the closed form per stroke against dF/dx = (1 / x_f) (1 - F sgn x') integrated in time;
    it saturates at +-1 away from the reversals."""
    t = np.linspace(0.0, 3.0, 30001)
    x, v, reach = 0.02 * np.sin(2 * np.pi * t), 0.04 * np.pi * np.cos(2 * np.pi * t), 0.001
    solution = solve_ivp(lambda s, f: [np.interp(s, t, v) / reach * (1 - f[0] * np.sign(np.interp(s, t, v)))],
                         (0.0, 3.0), [0.0], t_eval=t, rtol=1e-10, atol=1e-12, max_step=1e-3)
    shape = friction_shape(x, v, reach)
    assert np.max(np.abs(shape - solution.y[0])) < 2e-3
    assert shape[np.argmin(np.abs(t - 0.5))] == pytest.approx(-1.0, abs=1e-6)  # 20 mm after the top reversal


def test_a_damper_with_25_ms_of_lag_and_hysteresis_is_fitted_to_its_noise_and_told_from_a_static_law(lagging):
    """The acceptance case: a digressive damper lagging 25 ms with 120 N of seal friction, 2 % force noise. The law
    with a lag and a hysteresis is chosen and leaves 2.22 % (the true law itself 2.23 %; within 3 % asked), its lag
    within 3 % and its friction within 10 %; its residual is white against the velocity and the displacement (its
    auto-correlation is not: the velocity's own error spans the differentiator's window). The static law's and the
    series law's residuals follow both inputs (the whiteness that fails on a wrong model): 47 % and 27 % left."""
    fit = fit_damper(lagging, LAWS)
    chosen = fit.chosen
    assert chosen.law.name == "digressive+preload+lag+hysteresis", [(f.law.name, f.bic) for f in fit.forms]
    assert chosen.residual_rms_pct < 3.0
    assert chosen.law.coefficients["lag_time"] == pytest.approx(0.025, rel=0.03)
    assert chosen.law.coefficients["friction"] == pytest.approx(120.0, rel=0.1)
    assert all(c.white for c in chosen.tests.cross), chosen.tests.describe()
    for name in LAWS[:2]:
        wrong = fit.form(name)
        assert wrong.residual_rms_pct > 20.0
        assert not any(c.white for c in wrong.tests.cross), wrong.tests.describe()


def test_a_lag_and_a_friction_are_written_as_a_series_stiffness_and_strut_friction():
    """Through motion ratio 0.7: the lag as the mean slope from zero over the lag (4500 N s/m / 25 ms at the damper,
    x MR^2 at the wheel), the friction as Coulomb friction x MR."""
    law = DamperLaw("digressive", dict(LAGGING, gas_rate=0.0), preload=True, lag=True, hysteresis=True)
    written = damper_in_vehicle(load_vehicle("proton_x"), "front", law, 0.7, speeds=(1.0, 1.0))
    front = written.vehicle.extensions
    assert front["top_mount_compliance"]["front"].rate == pytest.approx(4500.0 / 0.025 * 0.49, rel=1e-3)
    assert front["strut_friction"]["front"].force == pytest.approx(120.0 * 0.7)
    assert any("25.0 ms" in note for note in written.notes)


def test_rig_dyno_writes_the_residual_tests(records, tmp_path, capsys):
    files = []
    for name, record in records[3:6]:
        files.append(tmp_path / f"{name}.csv")
        write_record(files[-1], record)
    out = tmp_path / "out"
    assert main(["dyno", "--record", *map(str, files), "--out", str(out), "--law",
                 "digressive+preload+lag+hysteresis"]) == 0
    document = json.loads((out / "damper.json").read_text())
    assert document["law"] == "digressive+preload+lag+hysteresis"
    tests = document["residual_tests"]
    assert set(tests["cross_correlation"]) == {"velocity", "displacement"}
    assert tests["autocorrelation"]["threshold"] == pytest.approx(37.57, abs=0.01)  # the paper's 37.6
    assert (out / "residual_tests.png").exists() and "residual" in capsys.readouterr().out


@pytest.mark.slow
def test_every_law_is_tried_and_the_dynamic_one_chosen(lagging):
    """All 40 static laws leave 24 % or more and no white residual: the laws with dynamics are tried (24 more) and
    the lagging one is chosen by BIC."""
    fit = fit_damper(lagging)
    assert fit.tried_dynamics and len(fit.forms) == 64
    assert fit.chosen.law.name == "digressive+preload+lag+hysteresis", [f.law.name for f in fit.forms[:4]]
    assert fit.chosen.law.coefficients["lag_time"] == pytest.approx(0.025, rel=0.03)


@pytest.mark.slow
def test_a_monotube_damper_simulated_from_its_hydraulics_is_fitted_within_10_percent():
    """The stand-in for a real record (tests/independent_damper.py: bushings, aerated oil, a gas charge, valves that
    blow off, seal friction; 300 Hz, sine and triangle tests): the best static law leaves 7.3 %, and the one chosen
    before the dynamics and the floor on the effective samples (quadratic_asymmetric+preload+series) 11.3 %; the
    chosen law now leaves 6.2 % (digressive+preload+series+hysteresis)."""
    from independent_damper import damper_records

    fit = fit_damper(dyno_test(damper_records()))
    assert fit.chosen.residual_rms_pct < 10.0, [(f.law.name, f.residual_rms_pct) for f in fit.forms[:4]]
