"""Damper laws fitted to dynamometer tests (rig/diagnosis/dyno/damper_law.py, rig/diagnosis/dyno/dyno_test.py): records
generated from known laws (tests/dyno_cases.py: sine and triangle tests at nine speeds, 1 % noise, a 20 degC rise
over the programme) give back every coefficient within 3 %, and the information criterion picks the law that made
them; bad records are refused in one line."""

import dataclasses

import numpy as np
import pytest
from dyno_cases import LAWS, T_REF, dyno_records

from rig.diagnosis.dyno.damper_choice import fit_damper
from rig.diagnosis.dyno.damper_law import DamperLaw, candidate_names
from rig.diagnosis.dyno.dyno_test import DynoError, dyno_test
from rig.io.record import Record


@pytest.fixture(scope="module")
def tests():
    """The dyno test of each known law (seed 0)."""
    return {name: dyno_test(dyno_records(law)) for name, law in LAWS.items()}


@pytest.mark.parametrize("name", list(LAWS))
def test_coefficients_are_recovered_within_3_percent(tests, name):
    fitted = fit_damper(tests[name], laws=[name], reference_temperature=T_REF).chosen
    for key, true in LAWS[name].items():
        assert fitted.law.coefficients[key] == pytest.approx(true, rel=0.03), (key, fitted.law.coefficients)
        low, high = fitted.intervals[key]
        assert low < fitted.law.coefficients[key] < high
    assert fitted.residual_rms_pct < 4.0  # 1 % force noise, the velocity's own noise, the reversals


@pytest.mark.parametrize("name", ["digressive", "asymmetric+series"])
def test_the_criterion_picks_the_law_that_made_the_data(tests, name):
    """Among all 40 laws (5 forms x preload, series, temperature), the lowest BIC is the true one: a parameter the
    data do not need does not pay for itself."""
    fit = fit_damper(tests[name], reference_temperature=T_REF)
    assert len(fit.forms) == len(candidate_names(True)) == 40
    assert fit.chosen.law.name == name, [(f.law.name, round(f.bic - fit.chosen.bic, 1)) for f in fit.forms[:4]]
    assert fit.forms[1].bic > fit.chosen.bic


@pytest.mark.slow
@pytest.mark.parametrize("name", [n for n in LAWS if n not in ("digressive", "asymmetric+series")])
def test_the_criterion_picks_the_law_that_made_the_data_for_every_form(tests, name):
    fit = fit_damper(tests[name], reference_temperature=T_REF)
    assert fit.chosen.law.name == name, [(f.law.name, round(f.bic - fit.chosen.bic, 1)) for f in fit.forms[:4]]


def test_the_paper_form_is_c0_v_plus_cn_v_abs_v():
    """"Neuro Model for Passive Suspension of a Light Car" (paper): F = C0 v + Cn v^2, odd in v here."""
    law = DamperLaw("quadratic", {"c0": 1500.0, "cn": 800.0})
    v = np.array([-0.5, -0.1, 0.0, 0.2, 1.0])
    np.testing.assert_allclose(law.force(v), 1500.0 * v + 800.0 * v * np.abs(v))
    drift = DamperLaw("quadratic", {"c0": 1500.0, "cn": 800.0, "preload": 120.0, "temperature_drift": -0.005},
                      preload=True, temperature=True, reference_temperature=30.0)
    np.testing.assert_allclose(drift.force(v, temperature=50.0), 0.9 * (1500.0 * v + 800.0 * v * np.abs(v)) - 120.0)


def _record(channels, units=None):
    rate, n = 500.0, 1000
    t = np.arange(n) / rate
    values = {"damper/displacement": 0.02 * np.sin(2 * np.pi * 2 * t), "damper/force": 900 * np.cos(2 * np.pi * 2 * t)}
    return Record(rate, {k: values[k] for k in channels}, units or {k: "m" if "disp" in k else "N" for k in channels})


def test_a_record_without_force_is_refused_in_one_line():
    with pytest.raises(DynoError, match=r"dyno.csv: no 'damper/force' channel \(it has: damper/displacement\)") as err:
        dyno_test([("dyno.csv", _record(["damper/displacement"]))])
    assert "\n" not in str(err.value)


def test_a_force_that_never_changes_is_refused():
    record = _record(["damper/displacement", "damper/force"])
    record.channels["damper/force"] = np.zeros(record.n_samples)
    with pytest.raises(DynoError, match="channel 'damper/force' does not change"):
        dyno_test([("dyno.csv", record)])


def test_a_displacement_in_mm_without_a_unit_is_refused_naming_the_channel():
    """20 mm read as 20 m: a 40 m stroke at 250 m/s is no damper on a dynamometer."""
    record = _record(["damper/displacement", "damper/force"], {"damper/displacement": "", "damper/force": "N"})
    record.channels["damper/displacement"] = record["damper/displacement"] * 1e3
    message = (r"dyno.csv: channel 'damper/displacement' has no unit, and read in m it strokes 40 m at up to "
               r"25\d\.\d m/s: .*give its unit in the channel map")
    with pytest.raises(DynoError, match=message) as err:
        dyno_test([("dyno.csv", record)])
    assert "\n" not in str(err.value)


def test_a_displacement_without_a_unit_plausible_in_m_is_read_in_m_and_said_so():
    record = _record(["damper/displacement", "damper/force"], {"damper/displacement": "", "damper/force": "N"})
    test = dyno_test([("dyno.csv", record)])
    assert test.runs[0].stroke == pytest.approx(0.04, rel=1e-3)
    assert "has no unit; read in m" in test.notes[0]


def test_an_unknown_law_is_refused():
    test = dyno_test([("dyno.csv", _record(["damper/displacement", "damper/force"]))])
    with pytest.raises(DynoError, match="unknown damper law 'cubic'"):
        fit_damper(test, laws=["cubic"])
    with pytest.raises(DynoError, match="needs damper/temperature"):
        fit_damper(test, laws=["linear+temperature"])


@pytest.mark.parametrize("reversed_channel", ["damper/force", "damper/displacement"])
def test_a_channel_of_reversed_polarity_is_found_by_the_work_the_damper_would_do(reversed_channel):
    """A damper absorbs work: records in which its force does work on it have one channel reversed. The force is
    taken reversed and the law fitted as from right records; both channels are named, as the records cannot tell
    which one it is."""
    name = next(iter(LAWS))
    right = dyno_records(LAWS[name])
    wrong = [(run, dataclasses.replace(record, channels={**record.channels,
                                                         reversed_channel: -record[reversed_channel]}))
             for run, record in right]
    test = dyno_test(wrong)
    assert test.reversed_force and not dyno_test(right).reversed_force
    assert any("have opposite polarity" in note and "scale = -1" in note for note in test.notes)
    fitted, truth = (fit_damper(t, laws=[name], reference_temperature=T_REF).chosen for t in (test, dyno_test(right)))
    if reversed_channel == "damper/force":  # the force taken reversed is the right one; a reversed rod mirrors the law
        assert fitted.law.coefficients == pytest.approx(truth.law.coefficients, rel=1e-9)
    assert fitted.residual_rms_pct == pytest.approx(truth.residual_rms_pct, rel=0.1)
