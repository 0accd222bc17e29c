"""Drive estimation by the neuro form: Nurhadiyanto's inverse model (Eq 5.1 through the servo, controllers/
inverse_model.py) whose suspension force is the neuro-model paper's network ("Neuro Model for Passive Suspension of a
Light Car" (paper)), learned from a training record's drives.

Eq 5.1 through the servo is linear in the wheel's acceleration W and in the suspension's force on the wheel F_s:
drive = G_W W + G_T (m_t W + F_s) per frequency line (``DriveOperators``). The linear inverse takes F_s from the data
sheet's spring and damper; here F_s is a network of sigmoid units on the suspension's compression x and on its rate
v (the spring and damper groups of the paper's network, rig/signal/neuro_network.py), beside linear terms of x and v
and, as the paper's neuro model takes powers of its deflection and its rate, x^3, v |v| and |v| (a spring that
stiffens, a damper stiffer one way: terms that extrapolate as the physics does, where a sigmoid unit saturates; not
x^2, which took up the asymmetric damper's pumping where the travel is integrated, not measured: the independent
large-event case's worst corner without a measured travel 20.9 % with it, 15.0 % without). The network is
trained by unitwise Fisher scoring on what the training record's drive leaves after G_W W + G_T m_t W, its output
observed through G_T (each corner's segment on its own) and at the rate the band resolves; one network per axle,
its corners side by side. The car itself does the rest: the same structure holds on a target that goes further
than the training, where a free-running black box (the NARX) has only its training to go on.

x is the measured travel where the records carry ``susp_travel``, v the rate blended from the travel's derivative and
the relative acceleration's integral (rig/signal/complementary.py). Where the travel is not measured, v is that
integral and x the travel controllers/travel_estimate.py gives with the law learned so far: in training, the
relative acceleration integrated twice above a crossover and the post's displacement less the tyre's and the body's
below it, and in training and target the slow travel the load balance asks; the form is fitted on it again, ROUNDS
times (the independent large-event car without travel or tyre-force channels: worst corner 15.0 % with the travel
integrated twice, 12.2 % so).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from controllers.inverse_model import DriveOperators
from controllers.travel_estimate import ROUNDS, estimated_travel, has_post, integrated_travel
from rig.causes import axles_of
from rig.io.channels import channel, corner_axle
from rig.io.record import Record
from rig.signal.complementary import blended_rate
from rig.signal.filters import band_pass, integrate
from rig.signal.neuro_network import NetworkFit, train
from rig.signal.residual_tests import TESTED_SHARE
from rig.vehicle.ride_model import static_loads
from rig.vehicle.vehicle_file import Vehicle

INPUTS = ("travel", "rate", "travel_cubed", "rate_abs_rate", "abs_rate")
MAX_UNITS = 4  # per group


@dataclass
class NeuroInverse:
    """The fitted neuro form: one network per axle (rig/signal/neuro_network.py ``NetworkFit``)."""

    vehicle: Vehicle
    band: tuple[float, float]
    fits: dict[str, NetworkFit]
    measured_travel: bool

    def drive(self, record: Record) -> np.ndarray:
        """The drive (samples x corners, m) for the record's responses."""
        corners = self.vehicle.corners
        operators = DriveOperators(self.vehicle, corners, record.n_samples, record.rate, self.band)
        force = self.force(self.inputs(record))
        wheel, displacement = _wheel(record, corners, operators, self.band, self.measured_travel)
        return operators.drive(wheel, operators.spectrum(force - force.mean(axis=0)), displacement)

    def tyre_load(self, record: Record) -> np.ndarray:
        """The tyres' loads (samples x corners, N) from the wheel's equilibrium: static load, m_t a_t and the learned
        suspension force's dynamic part; where the record measures none, they say when a tyre leaves its post."""
        force = self.force(self.inputs(record))
        unsprung = np.array([self.vehicle.axle(c).unsprung_mass for c in self.vehicle.corners])
        return (static_loads(self.vehicle).tyre_force + unsprung * record.quantity("unsprung_acc", self.vehicle.corners)
                + force - force.mean(axis=0))

    def inputs(self, record: Record) -> np.ndarray:
        """The networks' inputs (samples x corners x INPUTS): the measured travel, or where none is, the travel the
        accelerations and the load balance give with the learned law (controllers/travel_estimate.py; a target's
        post displacement, where it has one, is not used: a road target has none)."""
        inputs = suspension_inputs(record, self.vehicle.corners, self.band, self.measured_travel)
        if self.measured_travel:
            return inputs
        return _with_travel(inputs, estimated_travel(self.vehicle, record, self.band[0] / 2, self.law, False))

    def force(self, inputs: np.ndarray) -> np.ndarray:
        """The learned suspension force on the body (samples x corners, N) for inputs (samples x corners x INPUTS)."""
        return np.column_stack([self.fits[corner_axle(c)].network.predict(inputs[:, i, :])
                                for i, c in enumerate(self.vehicle.corners)])

    def law(self, x: np.ndarray, v: np.ndarray) -> np.ndarray:
        """The learned force (samples x corners, N) at travel x and rate v (samples x corners), zero at rest."""
        return self.force(_powers(x, v)) - self.force(_powers(np.zeros((1, x.shape[1])), np.zeros((1, x.shape[1]))))

    def describe(self) -> str:
        units = "; ".join(f"{axle}: {fit.order.get('spring', 0)} spring + {fit.order.get('damper', 0)} damper units"
                          for axle, fit in self.fits.items())
        travel = "the measured travel" if self.measured_travel else "the travel estimated without a travel channel"
        return (f"Eq 5.1 through the servo with the suspension force a network on {travel} and its rate ({units}), "
                f"trained by unitwise Fisher scoring")


def fit_neuro_inverse(vehicle: Vehicle, train_record: Record, band: tuple[float, float], measured_travel: bool
                      ) -> NeuroInverse:
    """The neuro form fitted on a training record with drives and responses (module docstring); without a measured
    travel, fitted again on the travel its law gives (controllers/travel_estimate.py), ROUNDS times."""
    inputs = suspension_inputs(train_record, vehicle.corners, band, measured_travel)
    inverse = NeuroInverse(vehicle, band, _networks(vehicle, train_record, band, inputs, measured_travel),
                           measured_travel)
    post = has_post(train_record, vehicle.corners)
    for _ in range(0 if measured_travel else ROUNDS):
        travel = estimated_travel(vehicle, train_record, band[0] / 2, inverse.law, post)
        inverse = NeuroInverse(vehicle, band, _networks(vehicle, train_record, band, _with_travel(inputs, travel),
                                                         False), False)
    return inverse


def _networks(vehicle: Vehicle, train_record: Record, band: tuple[float, float], inputs: np.ndarray,
              measured: bool) -> dict[str, NetworkFit]:
    """One network per axle, trained on what the training record's drive leaves after the linear part."""
    corners = vehicle.corners
    rate, n = train_record.rate, train_record.n_samples
    operators = DriveOperators(vehicle, corners, n, rate, band)
    wheel, displacement = _wheel(train_record, corners, operators, band, measured)
    linear_part = operators.drive(wheel, np.zeros_like(wheel), displacement)
    target = band_pass(train_record.quantity("drive", corners), rate, band) - linear_part
    step = max(1, int(rate / (2 * TESTED_SHARE * band[1])))
    fits = {}
    for axle in axles_of(vehicle):
        mine = [i for i, c in enumerate(corners) if corner_axle(c) == axle]

        def observe(columns: np.ndarray, mine=mine) -> np.ndarray:
            parts = np.split(columns, len(mine))
            return np.vstack([operators.of_force(part - part.mean(axis=0), i)[::step] for part, i in zip(parts, mine)])

        x = np.vstack([inputs[:, i, :] for i in mine])
        y = np.concatenate([target[::step, i] for i in mine])
        fits[axle] = train(x, y, INPUTS, {"spring": (0,), "damper": (1,)}, tuple(range(len(INPUTS))), observe,
                           MAX_UNITS)
    return fits


def _wheel(record: Record, corners: tuple[str, ...], operators: DriveOperators, band: tuple[float, float],
           measured: bool) -> tuple[np.ndarray, np.ndarray | None]:
    """The spectra of the wheel's acceleration and, with a measured travel, of its displacement: the body's
    (its acceleration integrated twice) plus the travel, from 0.8 of the band's lower edge (below, the body's integral
    holds mostly amplified noise, and the travel its slow settling)."""
    wheel = operators.spectrum(record.quantity("unsprung_acc", corners))
    if not measured:
        return wheel, None
    body = integrate(record.quantity("sprung_acc", corners), record.rate, band[0] / 2, 2, pad=True)
    displacement = band_pass(body + record.quantity("susp_travel", corners), record.rate, (0.8 * band[0], band[1]))
    return wheel, operators.spectrum(displacement)


def suspension_inputs(record: Record, corners: tuple[str, ...], band: tuple[float, float], measured: bool
                      ) -> np.ndarray:
    """The network's inputs (samples x corners x INPUTS): compression x, its rate v and their power terms."""
    rate = record.rate
    relative = record.quantity("unsprung_acc", corners) - record.quantity("sprung_acc", corners)
    if measured:
        x = record.quantity("susp_travel", corners)
        v = np.column_stack([blended_rate(x[:, i], relative[:, i], rate) for i in range(len(corners))])
    else:
        x, v = integrated_travel(record, corners, band[0] / 2)
    return _powers(x, v)


def _powers(x: np.ndarray, v: np.ndarray) -> np.ndarray:
    """The networks' inputs (samples x corners x INPUTS) for travel x and rate v (samples x corners)."""
    return np.stack([x, v, x**3, v * np.abs(v), np.abs(v)], axis=2)


def _with_travel(inputs: np.ndarray, travel: np.ndarray) -> np.ndarray:
    """``inputs`` with the travel (samples x corners, m) replaced, its rate kept."""
    return _powers(travel, inputs[:, :, 1])


def has_travel(records: list[Record | None], corners: tuple[str, ...]) -> bool:
    """Whether every record given measures every corner's travel."""
    return all(channel(c, "susp_travel") in r for r in records if r is not None for c in corners)
