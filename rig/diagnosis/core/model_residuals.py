"""The residual tests of a diagnosis's final model (rig/signal/residual_tests.py): per compared channel of the held-out
data, measured minus simulated in the analysis band, its auto-correlation and its cross-correlation with the
model's inputs (the measured post displacements at every corner; for an achieved post displacement, the drives),
against 99 % limits. A model whose residual follows its inputs leaves a law it does not hold; a white residual
is what the noise alone would leave."""

from __future__ import annotations

import numpy as np

from rig.diagnosis.core.experiment import Experiment
from rig.io.channels import channel, split_channel
from rig.signal.filters import band_pass
from rig.signal.residual_tests import ResidualTests, residual_tests


def model_residual_tests(test: Experiment, measured: np.ndarray, simulated: np.ndarray, parameters: int
                         ) -> list[ResidualTests]:
    """The tests of each compared channel (``measured`` and ``simulated``: samples x ``test.names``) for a model
    of ``parameters`` fitted parameters."""
    rate, band, corners = test.record.rate, test.band, test.corners
    posts = band_pass(test.record.quantity("actuator_disp", corners), rate, band)[test.settle:]
    inputs = {channel(c, "actuator_disp"): posts[:, i] for i, c in enumerate(corners)}
    drives = {}
    if test.drive is not None:
        values = band_pass(test.drive.quantity("drive", corners), rate, band)[test.settle:]
        drives = {channel(c, "drive"): values[:, i] for i, c in enumerate(corners)}
    tests = []
    for i, name in enumerate(test.names):
        against = drives if split_channel(name)[1] == "actuator_disp" and drives else inputs
        tests.append(residual_tests(name, measured[:, i] - simulated[:, i], against, parameters, rate, band))
    return tests


def parameters_of(run, named: list, generic=None) -> int:
    """The parameters a diagnosis's final model fitted: the linear factors, each named cause's and a generic
    element's."""
    return len(run.linear) + sum(c.n_params for c in named) + (generic.n_params if generic is not None else 0)
