"""The suspension's force law learned per axle as the neuro-model paper's networks, with the residual tests the paper
judges its model by ("Neuro Model for Passive Suspension of a Light Car" (paper)).

The data are the force laws' (rig/diagnosis/rig_test/force_laws.py): per corner the suspension force from the wheel's
equilibrium, F = F_tyre - m_u (g + a_u), low-passed to the band's top, against the compression x and its rate v. The
network (rig/signal/neuro_network.py) has spring units on x alone and damper units on v alone, and an output unit
that also weighs, linearly, x and v, the wheel's acceleration (the data sheet's unsprung mass a few percent off
bends F by the error times it) and, where the other side is measured, x less the other side's (an anti-roll bar):
these effects do not bend the curves. Not the acceleration relative to the body: with the wheel's it makes the
body's, and on a quarter car F is the body's mass times it, a fit that says nothing of the law. The inputs are taken
at every sample (x low-passed to the band's top, v blended from the travel's derivative and the relative
acceleration's integral: rig/signal/complementary.py, far less noise than either), and the network's output is
observed as the force is: its content below 70 % of the band's top, at twice that rate, where the residual tests
take it (``tested_samples``: a law's harmonics above the band leave the measured force, not the law of low-passed
inputs, and there the samples are independent: the FPE that sets its order counts those). The spring and damper
curves are the axle's ``neuro_law`` (rig/causes/neuro_law.py), and the network's residual is tested for whiteness
against the travel and its rate (rig/signal/residual_tests.py).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy import signal

from rig.causes import axles_of
from rig.causes.neuro_law import KNOTS, REACH_MARGIN, NeuroLaw
from rig.constants import ANALYSIS_BAND
from rig.diagnosis.rig_test.force_laws import MIN_SECONDS, other_side, suspension_force
from rig.io.channels import channel
from rig.io.record import Record
from rig.signal.complementary import blended_rate
from rig.signal.neuro_network import NetworkFit, train
from rig.signal.residual_tests import ResidualTests, residual_tests, tested_samples
from rig.vehicle.vehicle_file import Vehicle

NEEDED = ("unsprung_acc", "susp_travel", "sprung_acc")  # and the tyre's force, or the post's displacement and the
#                                                        tyre's data-sheet rate (rig/diagnosis/rig_test/force_laws.py)
MAX_UNITS = 4      # per curve: the paper's networks are small
#: a unit's rise from 10 to 90 % of its span, in its net input (2 ln 9): the law is realised by chords
#: (rig/causes/neuro_law.py), and a unit that rises within less than one is a step the chords cannot hold; unbounded,
#: units that explained next to nothing steepened past the vehicle file's limits (8 of the 14 independent benchmark
#: cases) and the learned law could not be simulated
RISE = 2 * np.log(9.0)
REACH = (0.005, 0.995)  # the trained reach: these quantiles of the travel and of its rate


@dataclass(frozen=True)
class LearnedLaw:
    """An axle's learned law: the section it becomes, the network fit (its FPE per order) and its residual's tests,
    over ``corners``."""

    axle: str
    law: NeuroLaw
    fit: NetworkFit = field(repr=False)
    tests: ResidualTests
    corners: tuple[str, ...]

    def to_json(self) -> dict:
        order = self.fit.order
        return {"corners": list(self.corners), "spring_units": order.get("spring", 0),
                "damper_units": order.get("damper", 0), "parameters": self.fit.network.parameters,
                "fpe": {"+".join(map(str, k)): v for k, v in self.fit.orders.items()},
                "effective_samples": self.fit.effective_samples, "residual_tests": self.tests.to_json()}


def learn_laws(record: Record, vehicle: Vehicle, saturated: tuple[str, ...] = (),
               band: tuple[float, float] = ANALYSIS_BAND) -> dict[str, LearnedLaw]:
    """The learned law of each axle whose corners measure what a force law needs (others left out); none from a
    record shorter than the force laws need."""
    if record.duration < MIN_SECONDS:
        return {}
    laws = {}
    for axle in axles_of(vehicle):
        def measured(c: str, quantity: str) -> bool:
            return channel(c, quantity) in record and channel(c, quantity) not in saturated

        corners = tuple(c for c in vehicle.corners if c[0] == axle[0].upper()
                        and all(measured(c, q) for q in NEEDED) and (measured(c, "tyre_force")
                                                                       or measured(c, "actuator_disp")))
        if corners:
            loaded = {c: measured(c, "tyre_force") for c in corners}
            laws[axle] = _learn(axle, corners, record, vehicle, saturated, band, loaded)
    return laws


def _learn(axle: str, corners: tuple[str, ...], record: Record, vehicle: Vehicle, saturated: tuple[str, ...],
           band: tuple[float, float], loaded: dict[str, bool]) -> LearnedLaw:
    """One axle's network: its corners' inputs at every sample, their forces observed as the force laws see them
    (``loaded``: per corner, whether a load cell measured the tyre's force)."""
    rate, top = record.rate, band[1]
    smooth = signal.butter(4, top, fs=rate, output="sos")  # the travel's noise above the band, as the force laws'

    def observe(columns: np.ndarray) -> np.ndarray:
        """Each corner's content below 70 % of the band's top, at twice that rate (the residual tests' samples): the
        corners' samples one after another, resampled together (the record's length each)."""
        by_corner = columns.reshape(len(corners), record.n_samples, -1).swapaxes(0, 1)
        tested = tested_samples(by_corner, rate, (0.0, top))[0]
        return tested.swapaxes(0, 1).reshape(-1, columns.shape[1])

    inputs, forces = [], []
    for corner in corners:
        travel = record[channel(corner, "susp_travel")]
        relative = record[channel(corner, "unsprung_acc")] - record[channel(corner, "sprung_acc")]
        other = channel(other_side(corner), "susp_travel")
        coupled = len(corners) > 1 and other in record and other not in saturated
        columns = [signal.sosfiltfilt(smooth, travel), blended_rate(travel, relative, rate),
                   record[channel(corner, "unsprung_acc")]] + ([travel - record[other]] if coupled else [])
        inputs.append(np.column_stack(columns))
        forces.append(suspension_force(record, vehicle, corner, band, loaded[corner]))
    width = min(part.shape[1] for part in inputs)
    names = ("travel", "rate", "wheel_acceleration", "coupling")[:width]

    x = np.vstack([part[:, :width] for part in inputs])
    reaches = [_reach(x[:, index]) for index in (0, 1)]  # the travel's and its rate's
    fit = train(x, observe(np.concatenate(forces)[:, None])[:, 0], names, {"spring": (0,), "damper": (1,)},
                tuple(range(width)), observe, MAX_UNITS, _steepest(reaches, width))
    seen = observe(x[:, :2])
    tested_rate = rate * seen.shape[0] / x.shape[0]
    tests = residual_tests(f"neuro law, {axle} axle", fit.residual, {"travel": seen[:, 0], "rate": seen[:, 1]},
                           fit.network.parameters, tested_rate)
    return LearnedLaw(axle, _section(fit, reaches), fit, tests, corners)


def _reach(values: np.ndarray) -> tuple[float, float]:
    """The trained reach of one input: its REACH quantiles, widened to hold ride height."""
    low, high = np.quantile(values, REACH)
    return float(min(low, 0.0)), float(max(high, 0.0))


def _steepest(reaches: list[tuple[float, float]], width: int) -> np.ndarray:
    """The steepest weight a unit may put on each of the ``width`` inputs: on the travel and its rate (1/m, s/m; their
    ``reaches``) one RISE per chord of the law as realised (KNOTS per side over REACH_MARGIN times the reach's longer
    side); no unit sees the others."""
    chords = [REACH_MARGIN * max(-low, high) / KNOTS for low, high in reaches]
    return np.append(RISE / np.array(chords), np.full(width - 2, np.inf))


def _section(fit: NetworkFit, reaches: list[tuple[float, float]]) -> NeuroLaw:
    """The spring and damper curves as a ``neuro_law`` section, with the ``reaches`` (travel, rate) they were trained
    over."""
    net = fit.network
    parts = {}
    for group, index, name in (("spring", 0, "travel"), ("damper", 1, "rate")):
        mine = [j for j, g in enumerate(net.groups) if g == group]
        parts[f"{name}_linear"] = float(net.linear[index])
        parts[f"{name}_weights"] = tuple(float(net.weights[j][0]) for j in mine)
        parts[f"{name}_biases"] = tuple(float(net.biases[j]) for j in mine)
        parts[f"{name}_outputs"] = tuple(float(net.outputs[j]) for j in mine)
        parts[f"{name}_reach"] = reaches[index]
    return NeuroLaw(**parts)
