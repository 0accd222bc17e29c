"""The neuro-model paper's network and its training ("Neuro Model for Passive Suspension of a Light Car" (paper),
sections 2-3): hidden units of the sigmoid of eq. 42, f(net) = e^net / (1 + e^net) - 0.5 (its c taken into the
weights), each seeing a group of inputs, and an output unit that sums them with a constant and, as the paper's
quarter car does (its K0 x + Kn x^2 and C0 v + Cn v^2), direct linear terms of the inputs:

    y = c + sum_i l_i x_i + sum_j a_j f(w_j . x_(S_j) + b_j)

Spring and damper networks are groups: units on the travel alone and units on its rate alone, so the law is
separable and each part a curve (rig/causes/neuro_law.py realises them inside mj_step); an inverse model's units see
every input.

Training is the paper's unitwise Fisher scoring (its eqs. 22-35, after Kurita's iteratively weighted least squares):
each unit's weights are estimated in turn, the others held, by the weighted least-squares normal equation of its
Fisher information, X^T Q X W* = X^T Q (s + Q^-1 d) (eq. 23). For a squared error the information of a hidden unit
j is Q = diag((a_j f'(net_j))^2), its working response s the unit's net input and d = a_j f'(net_j) r (r the
residual), so that W* = W + (X^T Q X)^-1 X^T d: a Gauss-Newton step on that unit alone; for the linear output unit
the normal equation is ordinary least squares, solved exactly. A step that does not lower the squared error is
shortened (a Levenberg term on the unit's normal equation: a safeguard the paper does not need for its small data).
The paper's recursive form (eqs. 32-35) updates the same estimate sample by sample; here every sample is at hand and
the normal equations are solved in one go.

A measured target is often observed through a filter: a force low-passed to the analysis band. A nonlinear law of
low-passed inputs is not the low-passed law (its harmonics above the band stay in the one and not in the other), so
the network's output is observed as the target was (``observe``: a linear map from every sample to the observed
ones, a low-pass and a decimation), and so is each unit's Jacobian: the normal equations keep their form.

A unit's slope may be bounded per input (``max_slopes``): where the network is realised by chords, a unit steeper
than a chord is a step the realisation cannot hold, and a unit that explains next to nothing is otherwise free to
steepen without end (its weights diverge while its output weight shrinks). A step past the bound is scaled back onto
it about the unit's centre.

Model order by the final prediction error (the paper's FPE, Akaike's MSE (N + p) / (N - p)): units are added one at
a time to the group whose new unit lowers the FPE most, each new unit placed where the residual needs it (its centre
and slope the best of a grid by the error it takes off), until no unit lowers it (each order trained for
TRIAL_SWEEPS passes, the chosen one to convergence). N counts the observed samples, which should be independent (a
low-passed record is observed at the rate its band resolves), else FPE's penalty vanishes. Written by hand: no
library trains unit by unit; the linear algebra is NumPy's.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

SWEEPS = 100            # passes over the units, at most, in the final training...
TRIAL_SWEEPS = 20       # ... and in training each order the FPE compares
TOLERANCE = 1e-6        # a pass that lowers the squared error by less than this share ends the training
RIDGE = 1e-9            # of the normal matrix's mean diagonal: keeps the output unit's equation regular
MAX_UNITS = 6           # per group
_CENTRES = np.linspace(0.05, 0.95, 10)  # a new unit's centre: these quantiles of its input's projection
_SLOPES = (0.5, 1.5, 4.0, 10.0)         # ... its slope, per standard deviation of that projection (either sign)


def unit(net: np.ndarray) -> np.ndarray:
    """The paper's sigmoid (eq. 42 with c = 1): e^net / (1 + e^net) - 0.5, odd, within +-0.5."""
    return 0.5 * np.tanh(0.5 * net)


def unit_slope(net: np.ndarray) -> np.ndarray:
    """d unit / d net = 0.25 - unit^2."""
    return 0.25 - unit(net) ** 2


@dataclass(frozen=True)
class Network:
    """A trained network in the inputs' own units: hidden units (``seen``: the inputs each sees, ``weights`` on them,
    ``biases``, ``outputs``: their weights in the output unit), the output unit's ``linear`` weights on every input
    (zero where it has none) and its ``constant``; ``groups`` names each unit's group."""

    inputs: tuple[str, ...]
    groups: tuple[str, ...]
    seen: tuple[tuple[int, ...], ...]
    weights: tuple[np.ndarray, ...]
    biases: np.ndarray
    outputs: np.ndarray
    linear: np.ndarray
    constant: float

    @property
    def parameters(self) -> int:
        """Fitted weights: each unit's input weights, bias and output weight, the linear terms and the constant."""
        return int(sum(w.size + 2 for w in self.weights) + np.count_nonzero(self.linear) + 1)

    def hidden(self, x: np.ndarray) -> np.ndarray:
        """Each unit's output (samples x units) for inputs ``x`` (samples x inputs)."""
        x = np.atleast_2d(x)
        if not self.weights:
            return np.empty((x.shape[0], 0))
        return np.column_stack([unit(x[:, list(s)] @ w + b) for s, w, b in zip(self.seen, self.weights, self.biases)])

    def predict(self, x: np.ndarray) -> np.ndarray:
        """The output for inputs ``x`` (samples x inputs)."""
        x = np.atleast_2d(x)
        return self.constant + x @ self.linear + self.hidden(x) @ self.outputs

    def group_curve(self, group: str, index: int, values: np.ndarray) -> np.ndarray:
        """The units of ``group`` (each seeing input ``index`` alone) at ``values`` of that input, without the
        linear terms or the constant."""
        values = np.asarray(values, float)
        total = np.zeros_like(values)
        for g, s, w, b, a in zip(self.groups, self.seen, self.weights, self.biases, self.outputs):
            if g == group:
                if s != (index,):
                    raise ValueError(f"units of group {group} see inputs {s}, not input {index} alone")
                total += a * unit(w[0] * values + b)
        return total

    def units_of(self, group: str) -> int:
        return sum(g == group for g in self.groups)


@dataclass(frozen=True)
class NetworkFit:
    """A trained network, the FPE of every order tried (``orders``: units per group -> FPE), the samples the FPE
    counted, the residual (target minus observed output) and the training's passes over the units."""

    network: Network
    orders: dict[tuple[int, ...], float]
    effective_samples: float
    residual: np.ndarray = field(repr=False)
    sweeps: int = 0

    @property
    def order(self) -> dict[str, int]:
        names = dict.fromkeys(self.network.groups)
        return {g: self.network.units_of(g) for g in names}


Observe = Callable[[np.ndarray], np.ndarray]


@dataclass
class _Problem:
    """What a network is trained on: the normalised inputs (every sample), the observed linear columns (the constant
    and the linear inputs), the normalised target (observed samples), the observation (every sample's columns to
    the observed samples: a linear map) and the steepest slope on each input (normalised inputs; inf: unbounded)."""

    xn: np.ndarray
    base: np.ndarray
    yn: np.ndarray
    observe: Observe
    max_slopes: np.ndarray

    def bounded(self, weights: np.ndarray, seen: tuple[int, ...]) -> np.ndarray:
        """A unit's [w..., b] on inputs ``seen`` with each weight held within its input's bound, the centre kept."""
        excess = float(np.max(np.abs(weights[:-1]) / self.max_slopes[list(seen)]))
        return weights / excess if excess > 1.0 else weights


@dataclass
class _State:
    """A network during training: each unit's [w..., b], the output unit's columns (the problem's ``base``, then each
    unit's observed output, kept up to date in place) and its weights [constant, linear on the ``linear`` inputs...,
    units...]."""

    groups: list[str]
    seen: list[tuple[int, ...]]
    weights: list[np.ndarray]
    design: np.ndarray          # observed samples x (base columns + units)
    head: np.ndarray

    def output(self) -> np.ndarray:
        return self.design @ self.head


def train(x: np.ndarray, y: np.ndarray, names: tuple[str, ...], groups: dict[str, tuple[int, ...]],
          linear: tuple[int, ...], observe: Observe | None = None, max_units: int = MAX_UNITS,
          max_slopes: np.ndarray | None = None) -> NetworkFit:
    """Train a network on inputs ``x`` (samples x inputs named ``names``) for target ``y``, its order chosen by FPE:
    ``groups`` maps a group's name to the inputs its units see; ``linear`` the inputs the output unit weighs
    directly. ``observe`` maps columns at every sample of ``x`` to the samples ``y`` holds (a linear map: a low-pass
    and a decimation, as the target was measured; default: the samples as they are), which are the independent
    samples the FPE counts. ``max_slopes``: per input, the steepest weight a unit may put on it, in 1 / the input's
    unit (module docstring; default unbounded)."""
    x, y = np.asarray(x, float), np.asarray(y, float)
    observe = observe or (lambda columns: columns)
    x_scale = np.std(x, axis=0)
    x_scale[x_scale == 0] = 1.0
    x_mean = np.mean(x, axis=0)
    y_mean, y_scale = float(np.mean(y)), float(np.std(y)) or 1.0
    xn = (x - x_mean) / x_scale
    problem = _Problem(xn, observe(np.column_stack([np.ones(x.shape[0]), xn[:, list(linear)]])),
                       (y - y_mean) / y_scale, observe,
                       np.full(x.shape[1], np.inf) if max_slopes is None else np.asarray(max_slopes, float) * x_scale)
    state = _State([], [], [], problem.base.copy(), np.zeros(problem.base.shape[1]))
    _solve_head(state, problem)
    best_fpe = _fpe(state, problem)
    orders = {tuple(0 for _ in groups): best_fpe}
    sweeps = 0
    while True:
        trials = []
        for group, seen in groups.items():
            if state.groups.count(group) >= max_units:
                continue
            trial = _with_unit(state, group, seen, problem)
            sweeps += _fisher_scoring(trial, problem, TRIAL_SWEEPS)
            fpe = _fpe(trial, problem)
            orders[tuple(trial.groups.count(g) for g in groups)] = fpe
            trials.append((fpe, trial))
        if not trials:
            break
        fpe, trial = min(trials, key=lambda item: item[0])
        if fpe >= best_fpe:
            break
        state, best_fpe = trial, fpe
    sweeps += _fisher_scoring(state, problem, SWEEPS)
    network = _network(state, names, linear, x_mean, x_scale, y_mean, y_scale)
    residual = y - observe(network.predict(x)[:, None])[:, 0]
    return NetworkFit(network, orders, float(y.size), residual, sweeps)


def _solve_head(state: _State, problem: _Problem) -> None:
    """The output unit's Fisher scoring: for a linear output unit, least squares, exact."""
    normal = state.design.T @ state.design
    ridge = RIDGE * np.trace(normal) / normal.shape[0]
    state.head = np.linalg.solve(normal + ridge * np.eye(normal.shape[0]), state.design.T @ problem.yn)


def _sse(state: _State, problem: _Problem) -> float:
    return float(np.sum((problem.yn - state.output()) ** 2))


def _fisher_scoring(state: _State, problem: _Problem, sweeps: int) -> int:
    """Unitwise Fisher scoring (module docstring), each unit followed by the output unit, until a pass lowers the
    squared error by less than TOLERANCE or after ``sweeps`` passes; returns the passes made. A unit's Jacobian is
    observed as its output is: a_j f'(net_j) [x, 1] at every sample, then ``observe``."""
    sse = _sse(state, problem)
    first = problem.base.shape[1]
    for sweep in range(1, sweeps + 1):
        before = sse
        for j, seen in enumerate(state.seen):
            z = np.column_stack([problem.xn[:, list(seen)], np.ones(problem.xn.shape[0])])
            jacobian = problem.observe(z * (state.head[first + j] * unit_slope(z @ state.weights[j]))[:, None])
            information = jacobian.T @ jacobian
            scale = np.trace(information) / z.shape[1]
            if not scale > 0:  # a unit with no output weight, or saturated everywhere: nothing to learn
                continue
            score = jacobian.T @ (problem.yn - state.output())
            damping, old, column = RIDGE * scale, state.weights[j], state.design[:, first + j].copy()
            for _ in range(8):  # shortened while it does not lower the error (a Levenberg term)
                state.weights[j] = problem.bounded(old + np.linalg.solve(information + damping * np.eye(z.shape[1]),
                                                                         score), seen)
                state.design[:, first + j] = problem.observe(unit(z @ state.weights[j])[:, None])[:, 0]
                trial = _sse(state, problem)
                if trial < sse:
                    sse = trial
                    break
                state.weights[j], state.design[:, first + j] = old, column
                damping = max(10 * damping, 1e-3 * scale)
            _solve_head(state, problem)
            sse = _sse(state, problem)
        if before - sse < TOLERANCE * before:
            return sweep
    return sweeps


def _with_unit(state: _State, group: str, seen: tuple[int, ...], problem: _Problem) -> _State:
    """``state`` with a unit added to ``group``, placed where the residual needs it: along the residual's least-
    squares direction in the unit's inputs (its input itself for one), at the centre and slope of a grid whose
    observed unit output, beside the present columns, takes the most off the squared error; the output unit solved
    again."""
    residual = problem.yn - state.output()
    inputs = problem.xn[:, list(seen)]
    direction = np.ones(1) if len(seen) == 1 else \
        np.linalg.lstsq(problem.observe(inputs), residual, rcond=None)[0]
    direction = direction / (np.linalg.norm(direction) or 1.0)
    projection = inputs @ direction
    spread = float(np.std(projection)) or 1.0
    grid = [(slope / spread, centre) for centre in np.quantile(projection, _CENTRES) for slope in _SLOPES]
    outputs = problem.observe(np.column_stack([unit(g * (projection - c)) for g, c in grid]))
    basis, _ = np.linalg.qr(state.design)
    new = outputs - basis @ (basis.T @ outputs)  # what each candidate adds to the present columns
    scores = (new.T @ residual) ** 2 / (np.sum(new**2, axis=0) + 1e-300)  # the squared error it takes off
    best = int(np.argmax(scores))
    gain, centre = grid[best]
    weights = problem.bounded(np.append(gain * direction, -gain * centre), seen)
    column = problem.observe(unit(inputs @ weights[:-1] + weights[-1])[:, None])
    trial = _State([*state.groups, group], [*state.seen, tuple(seen)], [*(w.copy() for w in state.weights), weights],
                   np.column_stack([state.design, column]), state.head)
    _solve_head(trial, problem)
    return trial


def _fpe(state: _State, problem: _Problem) -> float:
    """Akaike's final prediction error on the observed samples (normalised target)."""
    n = problem.yn.size
    p = problem.base.shape[1] + sum(w.size + 1 for w in state.weights)
    return float(_sse(state, problem) / n * (n + p) / max(n - p, 1.0))


def _network(state: _State, names: tuple[str, ...], linear: tuple[int, ...], x_mean: np.ndarray,
             x_scale: np.ndarray, y_mean: float, y_scale: float) -> Network:
    """The trained state in the inputs' and the target's own units."""
    first = 1 + len(linear)
    lin = np.zeros(len(names))
    lin[list(linear)] = state.head[1:first] / x_scale[list(linear)] * y_scale
    constant = y_mean + y_scale * (state.head[0] - np.dot(state.head[1:first], x_mean[list(linear)]
                                                          / x_scale[list(linear)]))
    weights, biases = [], []
    for s, w in zip(state.seen, state.weights):
        idx = list(s)
        weights.append(w[:-1] / x_scale[idx])
        biases.append(w[-1] - float(np.dot(w[:-1], x_mean[idx] / x_scale[idx])))
    return Network(tuple(names), tuple(state.groups), tuple(state.seen), tuple(weights), np.array(biases),
                   state.head[first:] * y_scale, lin, float(constant))
