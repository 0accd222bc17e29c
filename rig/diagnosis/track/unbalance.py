"""A rolling wheel's unbalance identified from a track test (the transputer paper, Eismann's deterministic relations).

The road is a stochastic excitation nobody measured; it is treated as noise. What is locked to a wheel's
measured angle theta_c (impulse transducer, ``<corner>/wheel_angle``) is the response to that wheel's own
nonuniformities, first of all its unbalance m e at an angle phi from the mark, which pushes the hub with
m e omega^2 cos(theta_c + phi). Per record (one constant speed):

1. **order analysis**: every measured channel y_k is cross-correlated with harmonic functions of each wheel's
   own angle (complex demodulation, Z_kc = 2/N sum y_k exp(-i theta_c)); the wheels roll at slightly
   different speeds (rolling radii differ by tenths of a percent), so their orders part over a long enough
   record, and where they do not, the overlap of their harmonic functions D_cd = 1/N sum exp(i(theta_d -
   theta_c)) is carried exactly: Z_kc = sum_d G_kd U_d D_cd + noise (wheels at one speed are then told apart
   by the pattern of their responses over the channels);
2. **the model's response** G_kc(omega_c) to a rotating unit unbalance at wheel c at that wheel's own speed,
   simulated with the cause's realisation (rig/causes/wheel_unbalance.py) on a flat road (the response is
   linear in m e);
3. **the noise** at the order frequency: the cross-spectral matrix P of what the road leaves in the channels
   (the record with its order lines removed), from its coefficients at neighbouring frequencies, which makes
   the coefficients' covariance (2 / T) P_kl D_cd: correlated between channels (a rear wheel meets the front
   wheel's road a wheelbase later) and between wheels whose orders overlap.

The complex unbalances U_c = m e exp(i phi) of all wheels follow by weighted least squares over every channel,
wheel and speed recorded, weighted by the noise's covariance (``_weights``), with their covariance from an
independent estimate of it (the other half of the neighbouring frequencies). A wheel is called unbalanced when
its U_c stands out of that covariance: Hotelling's T^2 = 2 |U_c|^2 / cov_cc beyond ``detection_threshold``
(T^2 / 2 is F-distributed for a balanced wheel: one is called unbalanced with probability ``FALSE_ALARM``); a
held-out record at another speed must then show the predicted order content. The residual's chi^2 over its
degrees of freedom says whether the model's FRF pattern over the channels and speeds explains the order content.
The standard deviations are conservative: the neighbouring frequencies see the front-rear relation turned a
little (by the wheelbase delay), so they overstate the noise left where the weights cancel the road most (on
balanced cars of the independent simulator T^2 averages about 0.6 instead of 2).

Not done: the transputer paper's covariance method for the road part (the road's unknown covariances identified with the
car's parameters); the speed must be constant within a record (``SPEED_TOLERANCE``): a record whose speed
varies is refused.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from rig.causes import with_extension
from rig.causes.wheel_unbalance import CAUSE as UNBALANCE
from rig.causes.wheel_unbalance import RIM_RADIUS_SHARE, WheelUnbalance
from rig.diagnosis.core.experiment import CAR_QUANTITIES
from rig.io.channels import channel, split_channel
from rig.io.record import Record, RecordError
from rig.signal.filters import band_pass
from rig.sim.replay import Replayer
from rig.vehicle.vehicle_file import Vehicle

UNIT_UNBALANCE = 0.01     # kg m: the model's FRF is simulated with this unbalance (the response is linear in it)
SETTLE = 1.0              # s left out at a record's start (the road fades in, a test starts from rest)
SPEED_TOLERANCE = 0.02    # largest relative spread of a wheel's speed over 1 s blocks of a record
FALSE_ALARM = 1e-5        # probability that a balanced wheel is called unbalanced
NOISE_HALF_BAND = 0.2     # Hz: the noise at the order frequency is taken from the residual within this of it (the
#                           channels' cross-spectra turn with frequency: the rear wheels see the road a wheelbase later)
NOISE_SAMPLES = 24        # but from at least this many neighbouring frequencies
WEIGHT_FLOOR = 0.01       # each channel's own noise added, relative, to the covariance the weights come from
SPECTRUM_HALF_BAND = 0.4  # Hz: the order spectra shown span the wheels' frequencies +- this
HIGH_PASS_SHARE = 0.3     # channels are high-passed at this share of the lowest order frequency before demodulation
FRF_SECONDS = 6.0         # s simulated for the model's FRF; its second half is fitted (the start has died out)


@dataclass
class OrderRecord:
    """One record's order analysis: per channel k and wheel c the demodulated coefficient Z[k, c] (a channel is
    Re{Z exp(i theta_c)} at that wheel's order), the overlap D of the wheels' harmonic functions and the
    road's cross-spectral density at the order frequency (one-sided, unit^2/Hz)."""

    channels: list[str]
    corners: tuple[str, ...]
    omega: np.ndarray         # rad/s per wheel (mean rate of its angle)
    duration: float           # s analysed
    coefficients: np.ndarray  # K x C complex
    overlap: np.ndarray       # C x C complex, D[c, d] = mean exp(i (theta_d - theta_c))
    noise: np.ndarray         # K x K complex, residual CSD at the orders' frequency (for the estimate's covariance)
    noise_samples: int        # neighbouring frequencies ``noise`` comes from (its degrees of freedom, complex)
    weighting: np.ndarray     # K x K complex, the same from other neighbouring frequencies (for the weights)
    speed: float | None       # m/s, from the metadata or a speed channel
    spectrum_hz: np.ndarray = field(repr=False, default_factory=lambda: np.zeros(0))
    spectrum: np.ndarray = field(repr=False, default_factory=lambda: np.zeros((0, 0)))  # K x frequencies, amplitude

    @property
    def frequency(self) -> np.ndarray:
        """Each wheel's order frequency in Hz."""
        return self.omega / (2 * np.pi)

    def covariance(self) -> np.ndarray:
        """Covariance of the flattened coefficients (index k * C + c): (2 / T) P_kl D_cd."""
        return 2.0 / self.duration * np.kron(self.noise, self.overlap)

    def design(self, frf: np.ndarray) -> np.ndarray:
        """Coefficients per unit unbalance of each wheel (K * C x C): G[k, d] D[c, d], for ``frf`` (K x C) of
        each channel to each wheel's unit unbalance at that wheel's speed."""
        return (frf[:, None, :] * self.overlap[None, :, :]).reshape(-1, len(self.corners))


@dataclass
class WheelEstimate:
    """The unbalance identified at one wheel, with its standard deviation and significance."""

    corner: str
    unbalance_kgm: float
    angle_deg: float
    std_kgm: float
    std_deg: float
    t2: float  # Hotelling's T^2 of U against zero (T^2 / 2 is F(2, 2 m) distributed for a balanced wheel)
    threshold: float  # T^2 beyond which the wheel is unbalanced (``detection_threshold``)

    @property
    def significant(self) -> bool:
        return self.t2 > self.threshold

    @property
    def detection_limit_kgm(self) -> float:
        """The smallest m e this record set would call unbalanced."""
        return float(np.sqrt(self.threshold) * self.std_kgm)

    def to_json(self) -> dict:
        return {"corner": self.corner, "unbalance_kgm": self.unbalance_kgm, "angle_deg": self.angle_deg,
                "std_kgm": self.std_kgm, "std_deg": self.std_deg, "t2": self.t2, "significant": self.significant,
                "threshold": self.threshold, "detection_limit_kgm": self.detection_limit_kgm}


@dataclass
class UnbalanceIdentification:
    """What ``identify_unbalance`` found: per wheel estimates, the records' order analyses and the model's FRFs
    there, the fit's consistency, and the held-out check."""

    wheels: dict[str, WheelEstimate]
    unbalance: np.ndarray           # complex U per wheel (kg m, angle from the mark)
    covariance: np.ndarray          # C x C complex
    records: list[OrderRecord]
    frfs: list[np.ndarray]          # per record, K x C: channel per unit unbalance of each wheel at its speed
    chi2: float                     # whitened residual, chi^2 (real) units
    dof: int
    holdout: OrderRecord | None = None
    holdout_frf: np.ndarray | None = None
    holdout_chi2: tuple[float, float] | None = None  # held-out order content: chi^2 before and after the prediction
    wheel_radius: float = 0.3

    @property
    def named(self) -> WheelEstimate | None:
        """The unbalanced wheel the verdict names: the most significant one, if significant and (with a held-out
        record) its prediction explains held-out order content."""
        best = max(self.wheels.values(), key=lambda w: w.t2)
        if not best.significant or (self.holdout_chi2 is not None and self.holdout_chi2[1] >= self.holdout_chi2[0]):
            return None
        return best

    @property
    def verdict(self) -> str:
        return UNBALANCE.name if self.named is not None else "none"

    @property
    def consistency(self) -> float:
        """Residual chi^2 over its degrees of freedom: about 1 when the model's FRF explains the order content."""
        return self.chi2 / max(self.dof, 1)

    def predicted(self, record: OrderRecord, frf: np.ndarray, corner: str) -> np.ndarray:
        """The order coefficient per channel (K) that ``corner``'s identified unbalance makes at ``record``'s speed."""
        c = record.corners.index(corner)
        return frf[:, c] * self.unbalance[self.corners.index(corner)]

    @property
    def corners(self) -> tuple[str, ...]:
        return tuple(self.wheels)

    def balancing(self) -> dict | None:
        """What balancing the named wheel removes: the weight on the rim opposite the unbalance, and the order
        response it takes away per channel and record (model: |G U|; measured: the wheel's order amplitude)."""
        named = self.named
        if named is None:
            return None
        rim = RIM_RADIUS_SHARE * self.wheel_radius
        removed = []
        for record, frf in zip(self.records + ([self.holdout] if self.holdout else []),
                               self.frfs + ([self.holdout_frf] if self.holdout else [])):
            c = record.corners.index(named.corner)
            model = np.abs(self.predicted(record, frf, named.corner))
            removed.append({"speed": record.speed, "frequency_hz": float(record.frequency[c]),
                            "channels": {n: {"removed": float(m), "measured_order": float(abs(z))}
                                         for n, m, z in zip(record.channels, model, record.coefficients[:, c])}})
        return {"corner": named.corner, "weight_kg": named.unbalance_kgm / rim, "rim_radius_m": rim,
                "weight_angle_deg": float((named.angle_deg + 180.0 + 180.0) % 360.0 - 180.0), "removed": removed}

    def to_json(self) -> dict:
        document = {"verdict": self.verdict, "wheels": {c: w.to_json() for c, w in self.wheels.items()},
                    "consistency": {"chi2": self.chi2, "dof": self.dof, "ratio": self.consistency},
                    "records": [_record_json(r) for r in self.records]}
        if self.holdout is not None:
            before, after = self.holdout_chi2
            document["holdout"] = {**_record_json(self.holdout), "chi2_before": before, "chi2_after": after,
                                   "explained": 1.0 - after / before if before > 0 else 0.0}
        balancing = self.balancing()
        if balancing is not None:
            document["balancing"] = balancing
        return document


def _record_json(record: OrderRecord) -> dict:
    return {"speed": record.speed, "duration_s": record.duration,
            "frequency_hz": dict(zip(record.corners, map(float, record.frequency))),
            "order_amplitude": {c: {n: float(abs(z)) for n, z in zip(record.channels, record.coefficients[:, i])}
                                for i, c in enumerate(record.corners)}}


# ---- records ---------------------------------------------------------------------------------------------
def is_track_record(record: Record) -> bool:
    """A record of a test driven on the road: ``# test: track``, or wheel angles without post channels."""
    test = record.metadata.get("test", "").strip().lower()
    if test:
        return test == "track"
    return bool(record.corners_with("wheel_angle")) and not record.corners_with("drive") \
        and not record.corners_with("actuator_disp")


def record_speed(record: Record) -> float | None:
    """The driving speed in m/s: the mean of a ``speed`` channel, or the metadata's ``speed`` (``25 m/s``)."""
    if "speed" in record:
        return float(np.mean(record["speed"]))
    text = record.metadata.get("speed")
    if text is None:
        return None
    value, _, unit = text.strip().partition(" ")
    try:
        number = float(value)
    except ValueError:
        raise RecordError(f"metadata 'speed: {text}' is not a number of m/s") from None
    factors = {"": 1.0, "m/s": 1.0, "km/h": 1 / 3.6}
    if unit.strip() not in factors:
        raise RecordError(f"metadata 'speed: {text}': unit must be m/s or km/h")
    return number * factors[unit.strip()]


def wheel_speeds(record: Record, corners: Sequence[str]) -> np.ndarray:
    """Each wheel's angular speed (rad/s) from its angle; a record whose speed varies is refused."""
    rate = record.rate
    block = max(2, int(round(rate)))
    speeds = []
    for corner in corners:
        name = channel(corner, "wheel_angle")
        angle = record[name]
        blocks = (angle[block::block] - angle[:-block:block][: angle[block::block].size]) * rate / block
        if blocks.size == 0:
            raise RecordError(f"{name}: the record is shorter than a second")
        mean = float(np.mean(blocks))
        if abs(mean) < 1.0:
            raise RecordError(f"{name}: the wheel turns at {mean:.3g} rad/s: it does not roll")
        spread = float((blocks.max() - blocks.min()) / abs(mean))
        if spread > SPEED_TOLERANCE:
            raise RecordError(f"{name}: the wheel's speed varies by {100 * spread:.1f} % over the record "
                              f"(from {blocks.min():.2f} to {blocks.max():.2f} rad/s): the unbalance "
                              f"identification needs constant speed; cut the record into constant-speed parts")
        speeds.append((angle[-1] - angle[0]) * rate / (angle.size - 1))
    return np.array(speeds)


def order_analysis(record: Record, vehicle: Vehicle, settle: float = SETTLE) -> OrderRecord:
    """Demodulate every car channel of ``record`` at every wheel's order (see the module docstring)."""
    corners = tuple(c for c in vehicle.corners if channel(c, "wheel_angle") in record)
    if not corners:
        wanted = ", ".join(channel(c, "wheel_angle") for c in vehicle.corners)
        raise RecordError(f"record has no wheel angles ({wanted}): "
                          "the order analysis needs each wheel's measured angle")
    names = [channel(c, q) for q in CAR_QUANTITIES for c in vehicle.corners if channel(c, q) in record]
    if not names:
        raise RecordError(f"record has none of {', '.join(CAR_QUANTITIES)} to analyse")
    omega = wheel_speeds(record, corners)
    start = int(round(settle * record.rate))
    if record.n_samples - start < 4 * record.rate:
        raise RecordError(f"record lasts {record.duration:.1f} s: the order analysis needs at least {settle + 4:g} s")
    # well below the orders, the body's motion is far larger than anything at them: take it out (zero-phase, unit
    # gain at the orders) so that a finite record's leakage from it does not reach them
    values = band_pass(np.column_stack([record[n] for n in names]), record.rate,
                       (HIGH_PASS_SHARE * float(omega.min()) / (2 * np.pi), 0.45 * record.rate))[start:]
    theta = np.column_stack([record[channel(c, "wheel_angle")][start:] for c in corners])
    n = theta.shape[0]
    harmonic = np.exp(-1j * theta)
    coefficients = 2.0 / n * values.T @ harmonic
    overlap = harmonic.T @ harmonic.conj() / n
    # the road's part: the record without its order lines (a free fit of every wheel's harmonics per channel)
    regressors = np.column_stack([np.cos(theta), np.sin(theta), np.ones(n)])
    residual = values - regressors @ np.linalg.lstsq(regressors, values, rcond=1e-10)[0]
    noise, weighting, count = _noise_at_orders(residual, theta[:, 0], n / record.rate)
    spectrum_hz, spectrum = _order_spectrum(values, record.rate, omega / (2 * np.pi))
    return OrderRecord(names, corners, omega, n / record.rate, coefficients, overlap, noise, count, weighting,
                       record_speed(record),
                       spectrum_hz, spectrum)


def _noise_at_orders(residual: np.ndarray, theta: np.ndarray, duration: float) -> tuple[np.ndarray, np.ndarray, int]:
    """The residual's cross-spectral density (K x K, one-sided, unit^2/Hz) at the order frequency, twice: from its
    coefficients at neighbouring frequencies, offset by whole cycles over the record (2, 3, ... on either side,
    within ``NOISE_HALF_BAND``, at least ``NOISE_SAMPLES``), each distributed as the order's own noise; the odd
    and the even offsets give two independent estimates, one to weight with and one to judge the weighted
    estimate by (an estimate that chose its weights could not judge them without bias). Returns both and the
    number of frequencies in each."""
    n = residual.shape[0]
    count = max(NOISE_SAMPLES // 2, int(NOISE_HALF_BAND * duration) - 1)
    offsets = np.concatenate([-np.arange(2, count + 2), np.arange(2, count + 2)])
    phase = np.exp(-1j * (theta[:, None] + 2 * np.pi * np.arange(n)[:, None] * offsets[None, :] / n))
    samples = 2.0 / n * residual.T @ phase  # K x offsets

    def density(part: np.ndarray) -> np.ndarray:
        return duration / 2 * part @ part.conj().T / part.shape[1]

    odd = offsets % 2 == 1
    return density(samples[:, odd]), density(samples[:, ~odd]), int(odd.sum())


def _order_spectrum(values: np.ndarray, rate: float, frequency: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Amplitude spectra (K x frequencies) of the channels around the wheels' order frequencies (Hann window,
    amplitude-corrected: a sine of amplitude A at a line reads A)."""
    n = values.shape[0]
    window = np.hanning(n)
    hz = np.fft.rfftfreq(n, 1.0 / rate)
    keep = (hz >= frequency.min() - SPECTRUM_HALF_BAND) & (hz <= frequency.max() + SPECTRUM_HALF_BAND)
    spectrum = np.abs(np.fft.rfft(values * window[:, None], axis=0)[keep]) * 2 / window.sum()
    return hz[keep], spectrum.T


# ---- the model ---------------------------------------------------------------------------------------------
def unbalance_frf(vehicle: Vehicle, corner: str, omega: np.ndarray, rate: float, channels: Sequence[str]) -> np.ndarray:
    """The model's order response (len(omega) x channels, complex: a channel is Re{G exp(i theta)} per kg m) to a
    unit unbalance at the mark of ``corner``'s wheel turning at each ``omega`` rad/s, on a flat road."""
    unit = with_extension(vehicle, UNBALANCE.name, WheelUnbalance(corner, UNIT_UNBALANCE, 0.0))
    samples = int(round(FRF_SECONDS * rate))
    time = np.arange(samples) / rate
    omega = np.atleast_1d(np.asarray(omega, float))
    angles = np.repeat((omega[:, None] * time[None, :])[:, :, None], len(vehicle.corners), axis=2)
    player = Replayer(unit, rate, "ideal")
    runs = player.play(np.zeros(angles.shape), limits=False, wheel_angles=angles)
    fitted = slice(samples // 2, None)
    frf = np.empty((omega.size, len(channels)), complex)
    for i, (w, run) in enumerate(zip(omega, runs)):
        theta = w * time[fitted]
        regressors = np.column_stack([np.cos(theta), np.sin(theta), np.ones(theta.size)])
        values = np.column_stack([_model_channel(run.record, n)[fitted] for n in channels])
        (a, b, _), *_ = np.linalg.lstsq(regressors, values, rcond=None)
        frf[i] = (a - 1j * b) / UNIT_UNBALANCE
    return frf


def _model_channel(record: Record, name: str) -> np.ndarray:
    if name not in record:
        raise RecordError(f"the model has no channel '{name}' to compare ({split_channel(name)[1]} is not simulated)")
    return record[name]


def record_frfs(vehicle: Vehicle, records: Sequence[OrderRecord], rate: float) -> list[np.ndarray]:
    """Per record, the model's FRF (channels x wheels) of every channel to each wheel's unit unbalance at that
    wheel's own speed."""
    frfs = [np.empty((len(r.channels), len(r.corners)), complex) for r in records]
    for corner in {c for r in records for c in r.corners}:
        at = [(i, r.corners.index(corner)) for i, r in enumerate(records) if corner in r.corners]
        omegas = np.array([records[i].omega[c] for i, c in at])
        channels = sorted({n for i, _ in at for n in records[i].channels})
        response = unbalance_frf(vehicle, corner, omegas, rate, channels)
        for row, (i, c) in enumerate(at):
            frfs[i][:, c] = [response[row, channels.index(n)] for n in records[i].channels]
    return frfs


# ---- identification ----------------------------------------------------------------------------------------
def detection_threshold(samples: int, false_alarm: float = FALSE_ALARM) -> float:
    """T^2 that a balanced wheel exceeds with probability ``false_alarm`` when the covariance comes from ``samples``
    complex noise samples: T^2 / 2 is F(2, 2 m), whose tail is (1 + T^2 / (2 m))^-m."""
    return 2 * samples * (false_alarm ** (-1.0 / samples) - 1)


def _whitener(covariance: np.ndarray) -> np.ndarray:
    """W with W C W^H = I on C's range (directions C does not reach, e.g. two wheels at exactly one speed, dropped)."""
    values, vectors = np.linalg.eigh(covariance)
    keep = values > 1e-10 * values.max()
    return (vectors[:, keep] / np.sqrt(values[keep])).conj().T


def _weights(record: OrderRecord) -> np.ndarray:
    """The least-squares weights of a record's coefficients: the whitener of their covariance as estimated from
    the neighbouring frequencies set aside for it, each channel's own noise raised by ``WEIGHT_FLOOR`` (the road
    drives the channels through a few wheels, so that covariance is nearly singular, and its near-null directions,
    a front wheel's road seen again by the rear wheel a wheelbase later, are known only as well as a few
    frequencies tell)."""
    noise = record.weighting + WEIGHT_FLOOR * np.diag(np.diag(record.weighting).real)
    return _whitener(2.0 / record.duration * np.kron(noise, record.overlap))


def identify_unbalance(vehicle: Vehicle, measured: Record | Sequence[Record], holdout: Record | None = None,
                       settle: float = SETTLE) -> UnbalanceIdentification:
    """The unbalance of every wheel with an angle channel, by weighted least squares over the ``measured``
    records (one or several speeds), judged on ``holdout`` (see the module docstring)."""
    measured = [measured] if isinstance(measured, Record) else list(measured)
    records = [order_analysis(r, vehicle, settle) for r in measured]
    corners = records[0].corners
    if any(r.corners != corners for r in records):
        raise RecordError("the measured records must have the same wheels' angles")
    rate = measured[0].rate
    held = order_analysis(holdout, vehicle, settle) if holdout is not None else None
    frfs = record_frfs(vehicle, records + ([held] if held else []), rate)
    held_frf = frfs.pop() if held else None
    weights = [_weights(r) for r in records]
    design = np.vstack([w @ r.design(frf) for w, r, frf in zip(weights, records, frfs)])
    target = np.concatenate([w @ r.coefficients.reshape(-1) for w, r in zip(weights, records)])
    # the weighted coefficients' covariance, from the records' covariances as estimated (block diagonal)
    blocks = [w @ r.covariance() @ w.conj().T for w, r in zip(weights, records)]
    noise = np.zeros((target.size, target.size), complex)
    at = 0
    for block in blocks:
        noise[at:at + block.shape[0], at:at + block.shape[0]] = block
        at += block.shape[0]
    normal = np.linalg.inv(design.conj().T @ design)
    unbalance = normal @ design.conj().T @ target
    covariance = normal @ design.conj().T @ noise @ design @ normal
    residual = target - design @ unbalance
    leave = np.eye(target.size) - design @ normal @ design.conj().T  # residual = leave @ noise
    expected = float(np.trace(leave @ noise @ leave.conj().T).real)
    dof = 2 * (target.size - len(corners))
    chi2 = float(np.vdot(residual, residual).real) / expected * dof
    wheels = {}
    threshold = detection_threshold(min(r.noise_samples for r in records))
    for c, corner in enumerate(corners):
        variance = float(covariance[c, c].real)
        size = float(abs(unbalance[c]))
        std = float(np.sqrt(variance / 2))
        wheels[corner] = WheelEstimate(corner, size, float(np.degrees(np.angle(unbalance[c]))), std,
                                       float(np.degrees(std / size)) if size > 0 else 180.0,
                                       2 * size**2 / variance, threshold)
    result = UnbalanceIdentification(wheels, unbalance, covariance, records, frfs, chi2, dof,
                                     wheel_radius=vehicle.wheel_radius)
    if held is not None:
        weight = _weights(held)
        z = weight @ held.coefficients.reshape(-1)
        after = z - weight @ held.design(held_frf) @ unbalance
        result.holdout, result.holdout_frf = held, held_frf
        result.holdout_chi2 = (float(2 * np.vdot(z, z).real), float(2 * np.vdot(after, after).real))
    return result


def remove_orders(record: Record, identification: UnbalanceIdentification, vehicle: Vehicle) -> Record:
    """``record`` without the response to the named wheel's identified unbalance, Re{G U exp(i theta)} per channel
    with the model's G at that wheel's speed in the record, for a rig-style diagnosis of what the road drives. (A
    free fit of each channel to the wheel's harmonics would take the road's own content at that frequency with
    it, as much as the unbalance's response on the channels it barely reaches.)"""
    named = identification.named
    if named is None:
        return record
    theta = record[channel(named.corner, "wheel_angle")]
    names = [n for n in identification.records[0].channels if n in record]
    omega = wheel_speeds(record, [named.corner])
    frf = unbalance_frf(vehicle, named.corner, omega, record.rate, names)[0]
    u = identification.unbalance[identification.corners.index(named.corner)]
    channels = dict(record.channels)
    for name, g in zip(names, frf):
        channels[name] = channels[name] - np.real(g * u * np.exp(1j * theta))
    return Record(record.rate, channels, dict(record.units), dict(record.metadata), record.start_time)
