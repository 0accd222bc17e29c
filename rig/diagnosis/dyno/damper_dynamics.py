"""The dynamics real dampers show on a dynamometer, beside their force law of velocity: the oil's and the gas's
compressibility (the force lags the law) and the seals' friction (a hysteresis in displacement).

- ``lag``: the law's force passes a first-order lag, tau F' + F = f(v): a damper whose oil (with its entrained gas)
  is a spring in series with the valve, linearised (a Maxwell element c in series with k lags by tau = c / k). Exact
  for an input linear between samples (the ramp-invariant discretisation: F_n = a F_(n-1) + b0 f_n + b1 f_(n-1),
  a = exp(-h / tau), b0 = 1 - tau (1 - a) / h, b1 = tau (1 - a) / h - a), from the quasi-static force at a run's
  start (SciPy's ``lfilter``).
- ``hysteresis``: the forces of the rod's path, the seals' friction and the gas spring. The friction as Dahl's model,
  dF/dx = (F_f / x_f) (1 - F / F_f sgn x'): rate-independent, it turns over a reach x_f after each reversal towards
  +-F_f. Along each stroke between reversals (the velocity's sign), F = s F_f + (F_0 - s F_f) exp(-|x - x_0| / x_f),
  in closed form, from the friction at the previous reversal (the first stroke from zero). The gas charge pushes
  the rod out less as it comes out: a rate k_g x about the preload.

Written here: the two closed forms (a loop over strokes, not samples); the filter is SciPy's.
"""

from __future__ import annotations

from itertools import pairwise

import numpy as np
from scipy import signal


def lagged(values: np.ndarray, rate: float, tau: float) -> np.ndarray:
    """``values`` (one run, samples at ``rate`` Hz) through a first-order lag of ``tau`` s (module docstring), from
    rest at their first value."""
    values = np.asarray(values, float)
    if tau <= 0:
        return values
    h = 1.0 / rate
    a = np.exp(-h / tau)
    b0 = 1.0 - tau * (1.0 - a) / h
    b1 = tau * (1.0 - a) / h - a
    start = signal.lfiltic([b0, b1], [1.0, -a], [values[0]], [values[0]])
    return signal.lfilter([b0, b1], [1.0, -a], values, zi=start)[0]


def friction_shape(displacement: np.ndarray, velocity: np.ndarray, reach: float) -> np.ndarray:
    """Dahl's friction of unit force along one run (positive resisting extension), turning over ``reach`` m after
    each reversal of ``velocity``'s sign (module docstring)."""
    x = np.asarray(displacement, float)
    sign = np.where(np.asarray(velocity) >= 0.0, 1.0, -1.0)
    starts = np.concatenate([[0], np.flatnonzero(np.diff(sign)) + 1, [x.size]])
    out = np.empty_like(x)
    state = 0.0
    for begin, end in pairwise(starts):
        s = sign[begin]
        origin = x[begin - 1] if begin > 0 else x[0]
        out[begin:end] = s + (state - s) * np.exp(-np.abs(x[begin:end] - origin) / max(reach, 1e-12))
        state = out[end - 1]
    return out
