"""NARX drive model (seed 002, 002_5996ee37d1f414f5.txt, sections 3.3 and 5.2): the post drive of each
corner from measured responses and its own past drives, through one hidden layer of linear and tanh neurons.

The seed's network: inputs the body acceleration and the drive at t-1 and t-2, hidden neurons [L L L L H H]
(four linear, two tanh), one linear output, trained on an identification record. Here, per corner,

    u(t) = c + V [W_L z(t) + b_L ; tanh(W_H z(t) + b_H)],
    z(t) = [responses of the corner at the offsets ``response_lags`` ; u(t-1) ... u(t-drive_lags)],

with the corner's body and wheel accelerations as responses, and optionally their band-limited integrals at t
(velocity and displacement, rig/signal/filters.py ``integrate``: what seed 002's Eq 5.1 needs). Offsets may
be negative (future samples): the drive leads the response through the servo's delay and lag, and a target
is estimated offline as a whole. One network per corner (the four share a structure): Eq 5.1 shows each
corner's drive follows from that corner's body and wheel.

Weights are fitted series-parallel (past drives from the record) by ``scipy.optimize.least_squares``
(Levenberg-Marquardt, analytic Jacobian), started from the linear least-squares ARX fit; the structure is
chosen on a validation split by the free-run error, where u(t-k) are the model's own past outputs, never the
true drive. The network and its Jacobian are written by hand (no deep-learning framework): a one-layer
network is a few lines of NumPy.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from scipy.optimize import least_squares

from rig.constants import ANALYSIS_BAND
from rig.io.record import Record, RecordError
from rig.signal.filters import band_pass, integrate

RESPONSES = ("sprung_acc", "unsprung_acc")


@dataclass(frozen=True)
class NarxStructure:
    """A NARX structure: response offsets (samples, positive = past), past drives, hidden neurons."""

    response_lags: tuple[int, ...]
    drive_lags: int
    linear: int
    tanh: int
    integrated: bool  # also the responses' band-limited velocity and displacement at t

    def describe(self) -> str:
        lags = ",".join(f"t{-k:+d}" if k else "t" for k in self.response_lags)
        integrals = "; their velocity and displacement at t" if self.integrated else ""
        drives = f"drive at t-1..t-{self.drive_lags}" if self.drive_lags else "no past drives"
        return (f"body and wheel acceleration at {lags}{integrals}; {drives}; "
                f"{self.linear} linear + {self.tanh} tanh neurons")

    @property
    def order(self) -> int:
        """Samples of history (and of future) a prediction needs."""
        return max(max(self.response_lags), self.drive_lags, -min(self.response_lags), 0)


#: seed 002 section 3.3: inputs at t-1 and t-2, hidden [L L L L H H]
SEED_STRUCTURE = NarxStructure(response_lags=(1, 2), drive_lags=2, linear=4, tanh=2, integrated=False)

#: the structures the validation split chooses from (the seed's among them)
CANDIDATES = (
    SEED_STRUCTURE,
    NarxStructure((-2, -1, 0, 1, 2), 0, 1, 4, True),
)


@dataclass
class NarxModel:
    """A fitted NARX drive model: one parameter vector per corner, and the scales of features and drives."""

    structure: NarxStructure
    corners: tuple[str, ...]
    rate: float
    band: tuple[float, float]
    parameters: np.ndarray     # corners x parameters (``_unpack``)
    feature_scale: np.ndarray  # corners x features
    drive_scale: np.ndarray    # corners, m

    def simulate(self, record: Record) -> np.ndarray:
        """Free-run drive (samples x corners, m) for the record's responses: the past drives it feeds back are
        its own outputs, from rest before the start."""
        features = features_of(record, self.corners, self.structure, self.band) / self.feature_scale[None]
        n, na, lin = features.shape[0], self.structure.drive_lags, self.structure.linear
        w, b, v, c = zip(*(_unpack(p, self.structure, features.shape[2] + na) for p in self.parameters))
        w, b, v, c = np.stack(w), np.stack(b), np.stack(v), np.array(c)
        w_features, w_past = w[:, :, :features.shape[2]], w[:, :, features.shape[2]:]
        fixed = np.einsum("chj,ncj->nch", w_features, features) + b[None]
        if na == 0:
            drive = _output(fixed, v, c, lin)
        else:
            drive = np.zeros((n + na, len(self.corners)))  # scaled, at rest before the start
            for t in range(n):
                past = drive[t:t + na][::-1].T  # corners x lags, u(t-1) first
                drive[t + na] = _output(fixed[t] + np.einsum("chk,ck->ch", w_past, past), v, c, lin)
            drive = drive[na:]
        return drive * self.drive_scale[None]


@dataclass
class NarxFit:
    """The chosen model, and every candidate's free-run drive error on the validation split (% per corner)."""

    model: NarxModel
    validation_error_pct: dict[NarxStructure, np.ndarray]

    @property
    def structure(self) -> NarxStructure:
        return self.model.structure


def fit_narx(train: Record, corners: tuple[str, ...], candidates: tuple[NarxStructure, ...] = CANDIDATES,
             validation: float = 0.25, band: tuple[float, float] = ANALYSIS_BAND,
             progress: Callable[[str], None] | None = None) -> NarxFit:
    """Fit every candidate on the first part of ``train`` (drives and responses), score each by its free-run
    drive error on the last ``validation`` share, and keep the one with the lowest worst-corner error."""
    check_training_record(train, corners, max(s.order for s in candidates))
    cut = int(round((1 - validation) * train.n_samples))
    first, last = _part(train, 0, cut), _part(train, cut, train.n_samples)
    errors, models = {}, {}
    for structure in candidates:
        models[structure] = _fit(first, corners, structure, band)
        estimate = models[structure].simulate(last)
        errors[structure] = drive_error_pct(last.quantity("drive", corners), estimate, train.rate, band)
        if progress is not None:
            progress(f"NARX {structure.describe()}: validation drive error "
                     + ", ".join(f"{c} {e:.2f} %" for c, e in zip(corners, errors[structure])))
    best = min(candidates, key=lambda s: errors[s].max())
    return NarxFit(models[best], errors)


def drive_error_pct(true: np.ndarray, estimate: np.ndarray, rate: float,
                    band: tuple[float, float] = ANALYSIS_BAND) -> np.ndarray:
    """Seed 002's drive error per corner: RMS of (estimate - true drive) over the true drive's RMS, both
    band-passed to the drive band, in %."""
    difference = band_pass(estimate - true, rate, band)
    reference = band_pass(true, rate, band)
    return 100 * np.sqrt(np.mean(difference**2, axis=0) / np.mean(reference**2, axis=0))


def check_training_record(record: Record, corners: tuple[str, ...], order: int) -> None:
    """Refuse a training record without drives or responses, or too short for the model order."""
    record.quantity("drive", corners)
    for quantity in RESPONSES:
        record.quantity(quantity, corners)
    needed = max(200 * order, int(4 * record.rate / ANALYSIS_BAND[0]))
    if record.n_samples < needed:
        raise RecordError(f"the training record has {record.n_samples} samples; a NARX of order {order} needs "
                          f"at least {needed} ({needed / record.rate:g} s at {record.rate:g} Hz)")


# ---- fitting ---------------------------------------------------------------------------------------------
def _fit(record: Record, corners: tuple[str, ...], structure: NarxStructure, band: tuple[float, float]) -> NarxModel:
    features = features_of(record, corners, structure, band)
    drive = band_pass(record.quantity("drive", corners), record.rate, band)  # what the drive error measures
    feature_scale = np.std(features, axis=0) + 1e-12
    drive_scale = np.std(drive, axis=0)
    features, drive = features / feature_scale[None], drive / drive_scale[None]
    na, edge = structure.drive_lags, structure.order
    rows = np.arange(edge, drive.shape[0] - edge, _TRAINING_STRIDE)
    parameters = []
    for i in range(len(corners)):
        past = np.column_stack([drive[rows - k, i] for k in range(1, na + 1)]) if na else np.empty((rows.size, 0))
        inputs = np.column_stack([features[rows, i], past])
        parameters.append(_fit_corner(inputs, drive[rows, i], structure, seed=i))
    return NarxModel(structure, corners, record.rate, band, np.array(parameters), feature_scale, drive_scale)


_TRAINING_STRIDE = 2    # every other sample: neighbours at 512 Hz add little, and the Jacobian halves
_RIDGE = 1e-6           # of the mean eigenvalue, in the linear start
_WEIGHT_DECAY = 1e-3    # residual per parameter: keeps the redundant linear neurons bounded
_ITERATIONS = 60        # Levenberg-Marquardt evaluations


def _fit_corner(inputs: np.ndarray, target: np.ndarray, structure: NarxStructure, seed: int) -> np.ndarray:
    """Series-parallel Levenberg-Marquardt fit of one corner's network, started from the linear ARX fit."""
    n_in, lin, hidden = inputs.shape[1], structure.linear, structure.linear + structure.tanh
    design = np.column_stack([inputs, np.ones(len(target))])
    # ridge: neighbouring samples of smooth responses are nearly collinear
    normal = design.T @ design
    linear = np.linalg.solve(normal + _RIDGE * np.trace(normal) / normal.shape[0] * np.eye(normal.shape[0]),
                             design.T @ target)
    rng = np.random.default_rng(seed)
    w = rng.normal(0.0, 0.3 / np.sqrt(n_in), (hidden, n_in))
    b = np.zeros(hidden)
    v = np.full(hidden, 0.01)
    w[0], v[0] = linear[:-1], 1.0
    start = _pack(w, b, v, linear[-1])
    decay = _WEIGHT_DECAY * np.sqrt(len(target) / start.size)

    def residual(p: np.ndarray) -> np.ndarray:
        w, b, v, c = _unpack(p, structure, n_in)
        return np.concatenate([_output(inputs @ w.T + b, v, c, lin) - target, decay * p])

    def jacobian(p: np.ndarray) -> np.ndarray:
        w, b, v, c = _unpack(p, structure, n_in)
        pre = inputs @ w.T + b
        act = np.concatenate([pre[:, :lin], np.tanh(pre[:, lin:])], axis=1)
        slope = np.concatenate([np.ones((len(target), lin)), 1 - act[:, lin:] ** 2], axis=1) * v  # d u / d pre
        rows = np.column_stack([(slope[:, :, None] * inputs[:, None, :]).reshape(len(target), -1), slope, act,
                                np.ones(len(target))])
        return np.vstack([rows, decay * np.eye(p.size)])

    return least_squares(residual, start, jac=jacobian, method="lm", max_nfev=_ITERATIONS).x


def _output(pre: np.ndarray, v: np.ndarray, c, linear: int) -> np.ndarray:
    """Network output from the hidden neurons' net inputs (... x hidden): linear, then tanh neurons."""
    act = np.concatenate([pre[..., :linear], np.tanh(pre[..., linear:])], axis=-1)
    return np.sum(act * v, axis=-1) + c


def _pack(w: np.ndarray, b: np.ndarray, v: np.ndarray, c: float) -> np.ndarray:
    return np.concatenate([w.ravel(), b, v, [c]])


def _unpack(p: np.ndarray, structure: NarxStructure, n_in: int):
    hidden = structure.linear + structure.tanh
    w = p[:hidden * n_in].reshape(hidden, n_in)
    rest = p[hidden * n_in:]
    return w, rest[:hidden], rest[hidden:2 * hidden], rest[2 * hidden]


# ---- inputs ----------------------------------------------------------------------------------------------
def features_of(record: Record, corners: tuple[str, ...], structure: NarxStructure,
                band: tuple[float, float]) -> np.ndarray:
    """Network inputs from responses (samples x corners x features): the accelerations at each offset (zero
    beyond the record's ends), then their integrals at t."""
    accelerations = np.stack([record.quantity(q, corners) for q in RESPONSES], axis=2)  # samples x corners x 2
    shifted = [_shift(accelerations, k) for k in structure.response_lags]
    if structure.integrated:  # in the drive band: below it the integrals hold mostly amplified noise
        shifted += [band_pass(integrate(accelerations, record.rate, band[0] / 2, times, pad=True), record.rate, band)
                    for times in (1, 2)]
    return np.concatenate(shifted, axis=2)


def _shift(values: np.ndarray, lag: int) -> np.ndarray:
    """values(t - lag) along the first axis, zero beyond the ends."""
    out = np.zeros_like(values)
    if lag >= 0:
        out[lag:] = values[:values.shape[0] - lag]
    else:
        out[:lag] = values[-lag:]
    return out


def _part(record: Record, start: int, stop: int) -> Record:
    return Record(record.rate, {n: v[start:stop] for n, v in record.channels.items()}, dict(record.units),
                  dict(record.metadata), record.start_time + start / record.rate)
