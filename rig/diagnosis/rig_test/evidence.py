"""Evidence that does not depend on a cause's law, from a model's residual: residual RMS per channel, per-channel
gain and time shift, the residual body acceleration against suspension compression and its rate (stiffening
shows as a slope change with travel, damping asymmetry as one with the sign of the rate, friction as a step at
zero rate), the residual's phase against frequency, and where the residual lives (channels, band, amplitude
dependence) when no cause explains it.

The phase of the measured channel against the model's, per frequency, tells a time shift from a car's lag: a
delay's phase falls on a line through zero (-2 pi f tau at every frequency), while a damper acting through a
compliance (a top mount, hydraulic compliance) lags only where the damper works, by an angle that follows the
series stiffness (atan(2 pi f c / k)) and fades where the damper has little to do. ``PhaseCurve`` holds the
curve, the delay whose line fits it best and how much of the curve that line explains.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass, field

import numpy as np
from scipy import signal

from rig.diagnosis.core.experiment import Experiment
from rig.io.channels import channel
from rig.signal.alignment import channel_delays, channel_gains
from rig.signal.metrics import tddi

PHASE_SEGMENT_S = 2.0   # s: Welch segments of the phase curves (0.5 Hz resolution)
MIN_COHERENCE = 0.5     # frequencies where measured and model are this coherent carry the phase curve
#: quantiles bounding the bins of the residual against travel and its rate: finer toward the tails, where a stop or a
#: progressive spring shows (bins of equal count put the last 10 % in one, its mean a few millimetres out)
BIN_EDGES = (0.005, 0.02, 0.06, 0.15, 0.3, 0.5, 0.7, 0.85, 0.94, 0.98, 0.995)


@dataclass(frozen=True)
class Binned:
    """Mean residual (m/s^2) in bins of a quantity (``x``: bin means, SI)."""

    x: list[float]
    residual: list[float]


@dataclass
class PhaseCurve:
    """The measured channel's phase against the model's per frequency (rad, negative: the measurement lags)."""

    channel: str
    frequency: np.ndarray = field(repr=False)   # Hz
    response: np.ndarray = field(repr=False)    # complex H1 from the model's channel to the measured one
    weight: np.ndarray = field(repr=False)      # coherence weight per frequency (0 where incoherent)
    delay_s: float                              # the delay whose line -2 pi f tau fits the curve best
    linearity: float                            # share of the curve's weighted power that line explains (<= 1)

    @property
    def phase(self) -> np.ndarray:
        return np.angle(self.response)

    def to_json(self) -> dict:
        return {"delay_s": self.delay_s, "linearity": self.linearity}


@dataclass
class Evidence:
    """Law-independent evidence from a model's held-out residual (car channels)."""

    residual_rms_share: dict[str, float]        # residual RMS over the measured RMS
    channel_gain: dict[str, float]              # least-squares factor measured / model
    channel_delay_s: dict[str, float]           # time shift that aligns the model with the measurement (s)
    phase: dict[str, PhaseCurve]                # the residual's phase against frequency
    residual_vs_travel: Binned | None = None    # body-acceleration residual against compression (m)
    residual_vs_travel_rate: Binned | None = None  # ... against compression rate (m/s)

    def to_json(self) -> dict:
        document = {"residual_rms_share": self.residual_rms_share, "channel_gain": self.channel_gain,
                    "channel_delay_s": self.channel_delay_s,
                    "residual_phase": {n: c.to_json() for n, c in self.phase.items()}}
        for key in ("residual_vs_travel", "residual_vs_travel_rate"):
            binned = getattr(self, key)
            if binned is not None:
                document[key] = {"x": binned.x, "residual": binned.residual}
        return document


@dataclass
class Remainder:
    """Where a model's held-out residual lives: the channels beyond the noise (worst first), the band holding
    10-90 % of their residual power (Hz), its peak (Hz), and the amplitude dependence (residual share in the
    loudest third of the record over the quietest: 1 for a linear model error, more for a nonlinearity)."""

    channels: list[str]
    band_hz: tuple[float, float] | None
    peak_hz: float | None
    amplitude_dependence: float | None

    def to_json(self) -> dict:
        return {"channels": self.channels, "band_hz": list(self.band_hz) if self.band_hz else [],
                "peak_hz": self.peak_hz, "amplitude_dependence": self.amplitude_dependence}

    def text(self, most: int | None = None) -> str:
        """Where the residual lives, in words (at most ``most`` channels named, worst first)."""
        if not self.channels:
            return "within a few times the noise floor on every channel"
        named = self.channels[:most]
        more = f" and {len(self.channels) - len(named)} more" if len(named) < len(self.channels) else ""
        band = (f" in {self.band_hz[0]:.1f}-{self.band_hz[1]:.1f} Hz (peak {self.peak_hz:.2f} Hz)"
                if self.band_hz else "")
        return f"on {', '.join(named)}{more}{band}"


def residual_evidence(test: Experiment, simulated: np.ndarray) -> Evidence:
    """Evidence from held-out car channels (band-passed, samples x ``test.car_channels``)."""
    measured = test.measured
    car = test.car_channels
    residual = measured - simulated
    share = np.sqrt(np.mean(residual**2, axis=0) / np.mean(measured**2, axis=0))
    rate = test.record.rate
    evidence = Evidence(dict(zip(car, map(float, share))),
                        dict(zip(car, map(float, channel_gains(measured, simulated)))),
                        dict(zip(car, map(float, channel_delays(measured, simulated, rate)))),
                        phase_curves(measured, simulated, car, rate, test.band))
    travel_names = [channel(c, "susp_travel") for c in test.corners]
    sprung_names = [channel(c, "sprung_acc") for c in test.corners]
    if all(n in car for n in travel_names + sprung_names):
        travel = measured[:, [car.index(n) for n in travel_names]]
        travel_rate = np.gradient(travel, axis=0) * rate
        body = residual[:, [car.index(n) for n in sprung_names]]
        evidence.residual_vs_travel = _binned(travel, body)
        evidence.residual_vs_travel_rate = _binned(travel_rate, body)
    return evidence


def transfer(source: np.ndarray, target: np.ndarray, rate: float, band: tuple[float, float]
             ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per channel (samples x channels), H1 from ``source`` to ``target`` and their coherence in ``band``:
    (frequency Hz, H1 (F x channels), coherence (F x channels))."""
    nperseg = min(source.shape[0], int(PHASE_SEGMENT_S * rate))
    frequency, cross = signal.csd(source, target, rate, nperseg=nperseg, axis=0)
    _, auto = signal.welch(source, rate, nperseg=nperseg, axis=0)
    _, coherence = signal.coherence(source, target, rate, nperseg=nperseg, axis=0)
    inside = (frequency >= band[0]) & (frequency <= band[1])
    return frequency[inside], cross[inside] / np.maximum(auto[inside], 1e-300), coherence[inside]


def phase_curves(measured: np.ndarray, simulated: np.ndarray, names: list[str], rate: float,
                 band: tuple[float, float]) -> dict[str, PhaseCurve]:
    """Per channel (samples x ``names``), the measured channel against the model's (H1 from model to measurement)
    in ``band``, weighted by coherence, and the delay line that fits its phase best."""
    frequency, response, coherence = transfer(simulated, measured, rate, band)
    curves = {}
    for i, name in enumerate(names):
        weight = np.where(coherence[:, i] >= MIN_COHERENCE, coherence[:, i], 0.0)
        delay, linearity = delay_line(frequency, np.angle(response[:, i]), weight)
        curves[name] = PhaseCurve(name, frequency, response[:, i], weight, delay, linearity)
    return curves


def delay_line(frequency: np.ndarray, phase: np.ndarray, weight: np.ndarray) -> tuple[float, float]:
    """The delay tau (s) whose phase -2 pi f tau fits ``phase`` (rad) best in weighted least squares, and the share
    of the curve's weighted power it explains (1: a pure delay; 0 or less: no line through zero fits)."""
    slope = -2 * np.pi * frequency
    norm = np.sum(weight * slope**2)
    power = np.sum(weight * phase**2)
    if norm == 0 or power == 0:
        return 0.0, 0.0
    tau = float(np.sum(weight * slope * phase) / norm)
    return tau, float(1 - np.sum(weight * (phase - slope * tau) ** 2) / power)


def signature_misfit(curve: PhaseCurve, predicted: np.ndarray) -> float:
    """Weighted RMS of ``curve``'s response minus a ``predicted`` complex response at the same frequencies: for
    unit magnitudes, about the phase difference in rad."""
    total = np.sum(curve.weight)
    if total == 0:
        return 0.0
    return float(np.sqrt(np.sum(curve.weight * np.abs(curve.response - predicted) ** 2) / total))


def _binned(x: np.ndarray, y: np.ndarray) -> Binned:
    """Mean of ``y`` in bins of ``x`` between quantiles BIN_EDGES: the tails in bins of their own."""
    edges = np.quantile(x, BIN_EDGES)
    centres, means = [], []
    for low, high in itertools.pairwise(edges):
        inside = (x >= low) & (x < high)
        if inside.any():
            centres.append(float(np.mean(x[inside])))
            means.append(float(np.mean(y[inside])))
    return Binned(centres, means)


def locate_residual(test: Experiment, measured: np.ndarray, simulated: np.ndarray, floors: np.ndarray,
                    beyond: float) -> Remainder:
    """Where a model's held-out residual lives (samples x ``test.names`` arrays; ``floors``: each channel's
    noise-floor TDDI): the channels whose TDDI exceeds ``beyond`` times their floor (worst first), the band
    holding 10-90 % of their residual power above the noise in the experiment's band, its peak, and the amplitude
    dependence."""
    rate = test.record.rate
    scores = np.array([tddi(measured[:, i], simulated[:, i]) for i in range(measured.shape[1])])
    excess = scores / np.maximum(floors, 1e-12)
    order = [i for i in np.argsort(-scores) if excess[i] > beyond]
    channels = [i for i in order if scores[i] >= 0.3 * scores[order[0]]] if order else []
    if not channels:
        return Remainder([], None, None, None)
    residual = measured[:, channels] - simulated[:, channels]
    frequency, psd = signal.welch(residual, rate, nperseg=min(residual.shape[0], int(4 * rate)), axis=0)
    power = np.sum(psd / np.mean(measured[:, channels] ** 2, axis=0), axis=1)  # each channel relative to its size
    inside = (frequency >= test.band[0]) & (frequency <= test.band[1])
    power = np.where(inside, power, 0.0)
    cumulative = np.cumsum(power) / np.sum(power)
    low, high = frequency[np.searchsorted(cumulative, 0.1)], frequency[np.searchsorted(cumulative, 0.9)]
    window = max(1, int(0.5 * rate))
    loudness = np.sqrt(np.convolve(np.sum(measured[:, channels] ** 2, axis=1), np.ones(window) / window, "same"))
    quiet, loud = loudness <= np.quantile(loudness, 1 / 3), loudness >= np.quantile(loudness, 2 / 3)

    def share(part):
        return np.sqrt(np.sum(residual[part] ** 2) / np.sum(measured[part][:, channels] ** 2))

    return Remainder([test.names[i] for i in channels], (float(low), float(high)),
                     float(frequency[np.argmax(power)]), float(share(loud) / share(quiet)))
