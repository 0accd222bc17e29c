"""Residual tests of a fitted model, as the neuro-model paper judges its networks ("Neuro Model for Passive
Suspension of a Light Car" (paper), section 6): the mean square error, Akaike's final prediction error, and whether
the residual is white: its auto-correlation and its cross-correlation with each input within 99 % limits.

For a residual e (mean removed) of N samples and an input u:

    r_ee(k) = sum_t e_t e_(t-k) / sum_t e_t^2                           k = 1 .. LAGS
    r_eu(k) = sum_t e_t u_(t-k) / sqrt(sum_t e_t^2 sum_t u_t^2)         k = 0 .. LAGS - 1 (the input leading)

Each lag's 99 % limit is +-2.576 / sqrt(N) (a white residual's correlations are normal with variance 1 / N), and the
paper's statistic over the lags, N sum_k r(k)^2, is chi-squared with LAGS degrees of freedom for a white residual
independent of the input: below its 99 % point (37.6 for 20 lags, the paper's limit) the test passes. A model that
leaves a law it does not hold in its residual fails: the residual then follows the input.

A residual of a sampled record has passed the analysis's filters (the band-pass, a differentiator's window) and is
correlated over the samples a filter spans even where the model is right: at 512 Hz a residual band-passed to
0.5-50 Hz is correlated from one sample to the next by the filter alone. It is tested where the filter leaves it
white: ``tested_samples`` keeps its content below TESTED_SHARE of the band's top (where the project's band-pass
passes at least 96 % of the power), resampled at twice that (the spectrum cut there, SciPy's Fourier resampling),
after dropping the band-pass's settling at each end (half a period of the band's lower edge). Below the lower edge
the band-pass has removed the residual's content; a white residual so cut has the correlation
r_H(k) = -sin(2 pi f_lo k / f_s) / (pi k (1 - 2 f_lo / f_s)) at lag k, which is taken off its auto-correlation
before the statistic is formed (about -0.015 per lag at 0.5 Hz in a 35 Hz band; on a minute of data it would
otherwise fail the test by itself). MSE, FPE (MSE (N + p) / (N - p), p the fitted parameters) and AIC
(N ln MSE + 2 p) are taken on the tested samples too: the samples a filter repeats carry no further information.

Written here: the statistics (a few lines of NumPy); the resampling and the chi-squared and normal quantiles are
SciPy's.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import signal, stats

LAGS = 20             # lags tested: the paper's "limit interval 20"
CONFIDENCE = 0.99     # the paper's "99 % confident limit"
TESTED_SHARE = 0.7    # of a band's top: the content tested


@dataclass(frozen=True)
class Correlation:
    """One correlation function of the residual (``name``: ``residual`` for the auto-correlation, else the input's)
    at ``lags`` (tested samples), its 99 % limit per lag, the statistic N sum r^2 and its 99 % point."""

    name: str
    lags: np.ndarray
    values: np.ndarray
    limit: float
    statistic: float
    threshold: float

    @property
    def white(self) -> bool:
        return bool(self.statistic <= self.threshold)

    @property
    def outside(self) -> list[int]:
        """The lags (tested samples) whose correlation lies beyond the 99 % limit."""
        return [int(k) for k, r in zip(self.lags, self.values) if abs(r) > self.limit]

    def to_json(self, step_s: float) -> dict:
        return {"statistic": round(self.statistic, 3), "threshold": round(self.threshold, 3), "white": self.white,
                "limit": round(self.limit, 5), "lags_outside": self.outside,
                "lags_outside_s": [round(k * step_s, 6) for k in self.outside]}


@dataclass(frozen=True)
class ResidualTests:
    """The tests of one model's residual: MSE, FPE and AIC on ``samples`` tested samples (at ``rate`` Hz) for
    ``parameters`` fitted, the residual's RMS over all its samples, and the correlations (``cross``: one per
    input)."""

    model: str
    samples: int
    rate: float
    parameters: int
    mse: float
    fpe: float
    aic: float
    rms: float
    autocorrelation: Correlation
    cross: tuple[Correlation, ...]

    @property
    def white(self) -> bool:
        """Whether every correlation passes its 99 % test."""
        return self.autocorrelation.white and all(c.white for c in self.cross)

    @property
    def failures(self) -> list[Correlation]:
        return [c for c in (self.autocorrelation, *self.cross) if not c.white]

    def describe(self) -> str:
        """One line: white, or which correlations fail and at which lags."""
        tested = f"{self.samples} samples at {self.rate:.4g} Hz"
        if self.white:
            return (f"{self.model}: residual white ({tested}; auto-correlation {self.autocorrelation.statistic:.1f}, "
                    f"cross-correlations up to {max((c.statistic for c in self.cross), default=0.0):.1f}, "
                    f"99 % point {self.autocorrelation.threshold:.1f})")
        parts = []
        for c in self.failures:
            what = "auto-correlation" if c is self.autocorrelation else f"cross-correlation with {c.name}"
            lags = ", ".join(f"{1e3 * k / self.rate:.4g}" for k in c.outside[:8]) or "none singly"
            more = f" (+{len(c.outside) - 8} more)" if len(c.outside) > 8 else ""
            parts.append(f"{what} {c.statistic:.1f} > {c.threshold:.1f} at lags {lags}{more} ms")
        return f"{self.model}: residual not white ({tested}): " + "; ".join(parts)

    def to_json(self) -> dict:
        step_s = 1.0 / self.rate
        return {"model": self.model, "white": self.white, "samples": self.samples, "rate_hz": round(self.rate, 4),
                "parameters": self.parameters, "mse": self.mse, "fpe": self.fpe, "aic": round(self.aic, 3),
                "rms": self.rms, "lags": LAGS, "confidence": CONFIDENCE,
                "autocorrelation": self.autocorrelation.to_json(step_s),
                "cross_correlation": {c.name: c.to_json(step_s) for c in self.cross},
                "text": self.describe()}


def tested_samples(values: np.ndarray, rate: float, band: tuple[float, float] | None) -> tuple[np.ndarray, float]:
    """``values`` (along the first axis) as tested for a band (Hz; its lower edge 0 for a low-pass alone): the
    band-pass's settling dropped at each end, the content below TESTED_SHARE of the band's top resampled at twice
    that; and the tested rate (Hz). Without a band, as they are."""
    if band is None:
        return np.asarray(values, float), rate
    values = np.asarray(values, float)
    if band[0] > 0:
        trim = int(round(0.5 * rate / band[0]))
        values = values[trim:values.shape[0] - trim] if values.shape[0] > 4 * trim else values
    tested = 2.0 * TESTED_SHARE * band[1]
    if tested >= rate:
        return values, rate
    count = int(round(values.shape[0] * tested / rate))
    return signal.resample(values, count, axis=0), rate * count / values.shape[0]


def residual_tests(model: str, residual: np.ndarray, inputs: dict[str, np.ndarray], parameters: int, rate: float,
                   band: tuple[float, float] | None = None, lags: int = LAGS) -> ResidualTests:
    """The tests of ``residual`` (one model's, samples) against ``inputs`` (name -> samples, each as long), for a
    model of ``parameters`` fitted parameters, sampled at ``rate`` Hz and filtered to ``band`` Hz (None: every
    sample tested as it is)."""
    e, tested = tested_samples(residual, rate, band)
    n = e.size
    if n <= 2 * lags + parameters:
        raise ValueError(f"{model}: {n} tested samples; residual tests over {lags} lags need more than "
                         f"{2 * lags + parameters}")
    mse = float(np.mean(e**2))
    p = min(parameters, n - 1)
    fpe = mse * (n + p) / (n - p)
    aic = n * np.log(max(mse, 1e-300)) + 2 * p
    centred = e - e.mean()
    limit = float(stats.norm.ppf(0.5 + CONFIDENCE / 2) / np.sqrt(n))
    threshold = float(stats.chi2.ppf(CONFIDENCE, lags))
    auto_lags = np.arange(1, lags + 1)
    auto = _correlation(centred, centred, auto_lags) - _cut_below(auto_lags, band[0] if band else 0.0, tested)
    autocorrelation = Correlation("residual", auto_lags, auto, limit, float(n * np.sum(auto**2)), threshold)
    cross = []
    cross_lags = np.arange(lags)
    for name, values in inputs.items():
        u = tested_samples(values, rate, band)[0]
        if u.size != n:
            raise ValueError(f"{model}: input {name} has {u.size} tested samples, the residual {n}")
        r = _correlation(centred, u - u.mean(), cross_lags)
        cross.append(Correlation(name, cross_lags, r, limit, float(n * np.sum(r**2)), threshold))
    return ResidualTests(model, n, tested, parameters, mse, float(fpe), float(aic),
                         float(np.sqrt(np.mean(np.asarray(residual, float) ** 2))), autocorrelation, tuple(cross))


def _cut_below(lags: np.ndarray, low: float, rate: float) -> np.ndarray:
    """The auto-correlation of white noise with nothing below ``low`` Hz, sampled at ``rate`` Hz, at ``lags``."""
    if low <= 0:
        return np.zeros(lags.size)
    share = 2.0 * low / rate
    return -np.sin(np.pi * share * lags) / (np.pi * lags * (1.0 - share))


def _correlation(e: np.ndarray, u: np.ndarray, lags: np.ndarray) -> np.ndarray:
    """sum_t e_t u_(t-k) / sqrt(sum e^2 sum u^2) at each lag k >= 0."""
    scale = np.sqrt(np.sum(e**2) * np.sum(u**2))
    if scale == 0.0:
        return np.zeros(lags.size)
    return np.array([np.dot(e[k:], u[:e.size - k]) for k in lags]) / scale
