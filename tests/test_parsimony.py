"""Measurement explanations first (rig/diagnosis/core/parsimony.py): two models are alike when their held-out TDDIs'
paired log ratio over the held-out pieces lies within its scatter; a car cause that is not better than a measurement
explanation beyond that scatter yields to it, and both are stated with the test that would separate them."""

from types import SimpleNamespace

import numpy as np

from rig.diagnosis.core.parsimony import compare
from rig.diagnosis.rig_test.diagnosis_results import Candidate
from rig.diagnosis.rig_test.selection import _by_parsimony

SAMPLES, CHANNELS = 16 * 512, 4
RNG = np.random.default_rng(0)
MEASURED = RNG.standard_normal((SAMPLES, CHANNELS))


def model(error: float | np.ndarray, seed: int) -> np.ndarray:
    """The measured channels missed by ``error`` (of their RMS; per sample where an array) of independent noise."""
    noise = np.random.default_rng(seed).standard_normal((SAMPLES, CHANNELS))
    return MEASURED + np.asarray(error).reshape(-1, 1) * noise


def test_models_that_miss_alike_are_alike_and_a_better_one_is_not():
    assert compare(MEASURED, model(0.1, 1), model(0.1, 2)).alike
    better = compare(MEASURED, model(0.05, 1), model(0.1, 2))
    assert not better.alike and better.log_ratio < 0  # half the error: a quarter of the TDDI
    assert 0.2 < np.exp(better.log_ratio) < 0.3


def test_an_improvement_where_the_effect_is_is_no_scatter():
    """A friction's gain is large where the motion is small and nothing elsewhere: still not alike."""
    error = np.where(np.arange(SAMPLES) % 4096 < 1024, 0.02, 0.1)  # a quarter of each piece-pair much better
    assert not compare(MEASURED, model(error, 1), model(0.1, 2)).alike


def candidate(effect: str, simulated: np.ndarray, gain: float) -> Candidate:
    return Candidate(effect, {}, None, 0.0, simulated, gain=gain)


def test_a_car_cause_that_is_not_better_yields_to_the_measurement_explanation_named_beside_it():
    run = SimpleNamespace(measured=MEASURED)
    body = candidate("secondary_mass", model(0.1, 1), 0.62)
    force = candidate("force_constant_error", model(0.1, 2), 0.60)
    chosen = _by_parsimony(run, body, [body, force])
    assert chosen is force
    said = force.alike["secondary_mass"]
    assert "force_constant_error and secondary_mass gain alike (0.600 and 0.620" in said
    assert "cannot separate them" in said and "a run with the force actuator off" in said
    assert body.why_not == said
    clearly = candidate("secondary_mass", model(0.03, 1), 0.95)
    assert _by_parsimony(run, clearly, [clearly, candidate("force_constant_error", model(0.1, 2), 0.6)]) is clearly
