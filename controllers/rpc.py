"""RPC-style iterative drive-signal tuning with the virtual rig in the loop (Nurhadiyanto's thesis, section 4.1.1).

The procedure of MTS Remote Parameter Control / time waveform replication: identify the rig-plus-car
FRF with band-limited random drives, invert it per frequency line (rig/signal/inverse.py), then

    drive_0 = g H+ target,   drive_k+1 = drive_k + g H+ (target - response_k),

playing each drive on the rig; drive_0 may instead be any estimate (``initial``: Nurhadiyanto's inverse model,
a NARX, a file; controllers/drive_estimation.py). Two schemes:
- ``fixed``: the reference scheme of Nurhadiyanto's thesis: fixed H from the identification,
  fixed gain 0.5.
- ``adaptive`` (default), for severe, nonlinear targets as commercial controllers (MTS RPC, Simcenter TWR) do:
  the FRF is updated from every iteration's drive and response increments (secant information at the operating
  point: stops and damper asymmetry change the effective FRF), robust to lift-off (controllers/frf_update.py);
  the gains are per channel and per octave band (controllers/band_gains.py): full steps (g = 1) while a band's
  error falls, halved where it grows; when the whole error grows, the best drive is restored. The error the
  update corrects leaves out the samples where the drive has no hold on a channel: while its corner's tyre is
  off the post (controllers/reachability.py).
A target with actuator forces between body and wheel (``<corner>/active_force``: a lab bench, an active car)
has them played beside every iteration's drive, as measured: they are an input, not something to reproduce.
The iteration matches the time history, its peaks or its damage (``match``, controllers/matching.py). Drives
are projected onto the post limits (stroke, velocity) inside every update and each hit is reported; a run that
diverges keeps its best drive. Where the model's own limits (lift-off, stroke, velocity, force) make the target
unreachable, the run stops as ``limited``, says which limit, how much the target asks beyond it and for how
long, and the error reached on the rest of the record. The FRF comes from an identification run on the virtual
rig, or from a measured drive/response record (``identification``) as a real rig's identification gives it.
History (metrics per iteration and channel) and the state needed to resume are written atomically after
every iteration.

``DriveIteration.run`` returns an ``IterationResult`` (scipy.optimize's ``OptimizeResult`` in spirit: best
drive, typed history, a status) and hands every iteration to an optional ``callback`` (plots, Rerun);
nothing here draws.
"""

from __future__ import annotations

import dataclasses
import json
import os
from collections.abc import Callable
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np

from controllers import IterationError
from controllers.band_gains import BandGains, band_errors
from controllers.frf_update import normalised, updated_spectra, usable_window
from controllers.matching import DEFAULT_TOLERANCE, MATCHES, channel_errors, rescaled
from controllers.reachability import (Unreachable, airborne, at_force_rating, lift_off_demands, limit_demands,
                                      per_channel, rest_error, widened)
from rig.constants import ANALYSIS_BAND, MIN_BAND_RATIO, analysis_band
from rig.io.atomic import atomic_path, write_text_atomic
from rig.io.channels import channel
from rig.io.files import write_record
from rig.io.record import Record, RecordError
from rig.signal.filters import band_limited_noise, band_pass, fade_window
from rig.signal.frf import FrfEstimate, SpectralMatrices, estimate_frf, spectral_matrices
from rig.signal.inverse import EDGE, apply_frf, regularised_inverse
from rig.signal.metrics import ChannelMetrics, channel_metrics
from rig.sim.drive_limits import LimitHit, check_drive, on_limits
from rig.sim.replay import ReplayResult, active_forces
from rig.sim.virtual_rig import VirtualRig
from rig.vehicle.vehicle_file import Vehicle

SCHEMES = ("adaptive", "fixed")
AIRBORNE, AT_LIMIT = 1, 2  # why the drive has no hold on a corner (``_without_hold``)
_PAD_MARGIN = 1.0  # s beyond half the inverse FIR's length before and after the target (see __init__)
_FADE = 1.0   # s: taper of the target's ends and of the drive's outer ends
_MIN_TARGET = 4 * _FADE  # s: the tapers take at most half of a target


@dataclass
class IterationSettings:
    scheme: str = "adaptive"
    iterations: int = 8
    gain: float | None = None               # fixed: 0.5; adaptive: the initial gain, 1.0
    target_error_pct: float | None = None   # stop when every channel's error is at most this (%; ``match``'s default)
    match: str = "rms"                      # what is matched: rms, peak or damage (controllers/matching.py)
    band: tuple[float, float] = ANALYSIS_BAND  # Hz
    frequency_resolution: float = 0.125     # Hz, of the FRF: its inverse is an FIR of 1 / resolution s
    regularisation: float = 0.02            # Tikhonov alpha, relative to the largest singular value
    identification_rms: float = 0.003       # m, per post
    identification_duration: float = 120.0  # s
    seed: int = 0

    def __post_init__(self) -> None:
        if self.scheme not in SCHEMES:
            raise IterationError(f"scheme must be one of {', '.join(SCHEMES)}, got {self.scheme!r}")
        if self.iterations < 1:
            raise IterationError(f"iterations must be at least 1, got {self.iterations}")
        if self.match not in MATCHES:
            raise IterationError(f"match must be one of {', '.join(MATCHES)}, got {self.match!r}")
        if self.target_error_pct is None:
            self.target_error_pct = DEFAULT_TOLERANCE[self.match]
        if not self.target_error_pct >= 0:
            raise IterationError(f"target error must be a non-negative percentage, got {self.target_error_pct}")
        if self.gain is None:
            self.gain = 0.5 if self.scheme == "fixed" else 1.0
        self.band = tuple(self.band)


#: how a run ended: every channel within the target error; the error grew even with a small gain; the model's
#: limits (lift-off, post stroke, velocity, force) hold the rest of the error; no progress otherwise; the iteration
#: count ran out
STATUSES = ("converged", "diverged", "limited", "stagnated", "out_of_iterations")


@dataclass
class IterationRecord:
    """One iteration: the metrics of the drive it played (one entry of history.json)."""

    iteration: int
    gain: float
    worst_rms_error_pct: float
    total_error_pct: float
    channels: dict[str, ChannelMetrics]  # channel -> rms_error_pct, tddi, peak_error_pct, damage_ratio
    limit_hits: list[str]
    road_recovery_rms_error_pct: dict[str, dict[str, float]] | None = None  # track targets: corner -> band -> %
    score: float | None = None  # total error under the match criterion (%): the best drive has the lowest
    rest_rms_error_pct: dict[str, float] | None = None  # channel -> RMS error (%) where the model can follow
    rest_share: float | None = None  # share of the target's samples counted in rest_rms_error_pct
    unreachable: list[Unreachable] = field(default_factory=list)  # the target's demands beyond the model

    @property
    def ranking(self) -> float:
        return self.total_error_pct if self.score is None else self.score

    def to_json(self) -> dict:
        document = asdict(self)
        for key in ("road_recovery_rms_error_pct", "score", "rest_rms_error_pct", "rest_share"):
            if document[key] is None:
                del document[key]
        return document

    @classmethod
    def from_json(cls, document: dict) -> IterationRecord:
        document = dict(document)
        document["unreachable"] = [Unreachable(**u) for u in document.get("unreachable", [])]
        document["channels"] = {name: ChannelMetrics.from_json(m) for name, m in document["channels"].items()}
        return cls(**document)


@dataclass
class IterationStep:
    """What ``callback`` sees after each iteration: its record, the history so far, the drive it played
    (samples x corners, m) and its response band-passed like the target (samples x channels, SI)."""

    record: IterationRecord
    history: list[IterationRecord]
    drive: np.ndarray
    response: np.ndarray


@dataclass
class IterationResult:
    """A finished (or stopped) drive iteration."""

    drive: np.ndarray                 # best drive, samples x corners (m), with the lead-in and lead-out
    response: np.ndarray              # its response, samples x channels, band-passed like the target
    history: list[IterationRecord]
    status: str                       # one of STATUSES
    stop_reason: str                  # the same in words
    replay: ReplayResult              # the best drive on the rig: every channel, unfiltered, and joint positions
    frf: FrfEstimate                  # the FRF estimate the run ended with

    @property
    def best(self) -> IterationRecord:
        return min(self.history, key=lambda h: h.ranking)

    @property
    def unreachable(self) -> list[Unreachable]:
        """What the target asks beyond the model, as the best drive met it."""
        return self.best.unreachable


@dataclass
class IterationState:
    """What an iteration carries from one play to the next: the FRF's spectral matrices and the band gains, the drive
    to play next (with the limits its projection hit), the best drive so far by the trust region's objective (the
    drive a setback goes back to) and by the match criterion (the run's result), the last play (the FRF update's
    secant), the band errors the gains adapt on, the damage matching's target scale, the history and how the run
    ended. ``arrays`` and ``restored`` are its saved form (state.npz beside history.json): what a resumed run
    restores."""

    spectra: SpectralMatrices
    gains: BandGains
    drive: np.ndarray                   # samples x corners, m: the next play
    best_drive: np.ndarray
    best_response: np.ndarray
    best_events: np.ndarray             # samples x corners: where the best drive had no hold (``_without_hold``)
    kept_drive: np.ndarray
    kept_response: np.ndarray
    previous_events: np.ndarray
    scale: np.ndarray                   # per channel: the target's scale under damage matching (1 otherwise)
    history: list[IterationRecord] = field(default_factory=list)
    limit_hits: list[LimitHit] = field(default_factory=list)  # the next drive's projection onto the post limits
    best_total: float = np.inf
    kept_score: float = np.inf
    previous_drive: np.ndarray | None = None
    previous_response: np.ndarray | None = None
    band_errors: np.ndarray | None = None
    status: str = ""
    stop_reason: str = ""

    SAVED = ("drive", "best_drive", "best_response", "best_events", "kept_drive", "kept_response", "previous_events",
             "scale", "previous_drive", "previous_response", "band_errors")  # the arrays state.npz holds

    def arrays(self) -> dict[str, np.ndarray]:
        """The arrays of state.npz: the saved ones that are set, the spectral matrices and the band gains."""
        arrays = {name: getattr(self, name) for name in self.SAVED if getattr(self, name) is not None}
        s = self.spectra
        return arrays | {"sxx": s.sxx, "sxy": s.sxy, "syy": s.syy, "frequency": s.frequency,
                         "gains": self.gains.values}

    @classmethod
    def restored(cls, arrays, document: dict, gains: BandGains, at_rest: np.ndarray, channels: int
                 ) -> IterationState:
        """The state state.npz (``arrays``) and history.json (``document``) saved; ``gains``: uniform ones to restore
        the saved values into, ``at_rest``: no event anywhere (what runs saved before events were kept get)."""
        gains.values = arrays["gains"] if "gains" in arrays else np.full_like(gains.values, document["gain"])
        return cls(SpectralMatrices(arrays["frequency"], arrays["sxx"], arrays["sxy"], arrays["syy"]), gains,
                   arrays["drive"], arrays["best_drive"], arrays["best_response"],
                   arrays.get("best_events", at_rest), arrays.get("kept_drive", arrays["best_drive"]),
                   arrays.get("kept_response", arrays["best_response"]), arrays.get("previous_events", at_rest),
                   arrays.get("scale", np.ones(channels)),
                   [IterationRecord.from_json(entry) for entry in document["iterations"]], [],
                   document["best_total_error_pct"], document.get("kept_score", document["best_total_error_pct"]),
                   arrays.get("previous_drive", None), arrays.get("previous_response", None),
                   arrays.get("band_errors", None), document.get("status", ""), document["stop_reason"])


class DriveIteration:
    """One drive-iteration job: a vehicle, a target record and its channels, and an output folder."""

    def __init__(self, vehicle: Vehicle, target: Record, channels: list[str], out_dir: str | os.PathLike | None,
                 settings: IterationSettings | None = None, nthread: int | None = None,
                 initial: Record | None = None, identification: Record | None = None):
        """``initial``: a first drive (``<corner>/drive`` channels, placed by its time stamps on the target's;
        default: the FRF inverse of the target); ``identification``: a measured record with the drives and
        ``channels`` whose FRF replaces the identification run on the virtual rig. ``out_dir`` may be None
        for a job that only gives its ``first_drive``."""
        settings = settings or IterationSettings()
        if target.duration < _MIN_TARGET:
            raise IterationError(f"the target is {target.duration:.3g} s; iteration needs at least {_MIN_TARGET:g} s "
                                 f"(its ends are tapered over {_FADE:g} s each)")
        supported = analysis_band(target.rate, target.duration) or (np.inf, 0.0)
        band = (max(settings.band[0], supported[0]), min(settings.band[1], supported[1]))
        if band[1] < MIN_BAND_RATIO * band[0]:
            raise IterationError(f"the target ({target.duration:.3g} s at {target.rate:g} Hz) supports "
                                 f"{supported[0]:.3g}-{supported[1]:.3g} Hz: too little of {settings.band[0]:g}-"
                                 f"{settings.band[1]:g} Hz to iterate in")
        self.settings = dataclasses.replace(settings, band=band)
        self.vehicle = vehicle
        self.channels = list(channels)
        self.target_record = target
        self.rate = target.rate
        # like RPC's target editing: the iteration works on the band it can reproduce (Nurhadiyanto: 0.6-50 Hz),
        # with the ends tapered to rest and a lead-in and lead-out at rest, longer than half the inverse FIR
        # (1 / frequency resolution): a record cut off mid-motion cannot be reproduced from rest, and the
        # band-pass then treats target and response alike (both at rest beyond the ends)
        self.pad = int(round((0.5 / self.settings.frequency_resolution + _PAD_MARGIN) * target.rate))
        self.span = slice(self.pad, self.pad + target.n_samples)  # the target's own samples
        fade = int(_FADE * target.rate)
        # errors inside the end tapers count in proportion to the taper: there the car must settle from the
        # target's motion (e.g. damper jacking) to rest, which the target does not show
        self.weight = np.pad(fade_window(target.n_samples, fade), self.pad)[:, None]
        self.target = self._edit(np.column_stack([target[name] for name in self.channels]))
        self.fade = fade_window(self.target.shape[0], fade)[:, None]
        self.target_rms = np.sqrt(np.mean(self.target[self.span] ** 2, axis=0))
        # a lift-off counts as out of reach where the target falls faster than the airborne wheel by more than the
        # RMS tolerance (of the channel's target RMS)
        rms_tolerance = self.settings.target_error_pct if self.settings.match == "rms" else DEFAULT_TOLERANCE["rms"]
        self._margin = rms_tolerance / 100 * self.target_rms
        self.out_dir = None if out_dir is None else Path(out_dir)
        self.rig = VirtualRig(vehicle, self.rate, self.channels, nthread)
        self.corners = vehicle.corners
        self.time = (np.arange(self.target.shape[0]) - self.pad) / self.rate  # drive time: the target starts at 0
        self.nperseg = int(2 ** np.ceil(np.log2(self.rate / self.settings.frequency_resolution)))
        self.initial = None if initial is None else self._place(initial)
        self.forces = self._placed_forces(target)
        self.identification = identification
        if identification is not None:
            check_identification(identification, self.corners, self.channels, self.rate, self.nperseg)

    # ---- public -------------------------------------------------------------------------------------
    def run(self, resume: bool = False, progress: bool = True,
            callback: Callable[[IterationStep], None] | None = None) -> IterationResult:
        """Iterate until the stop rule; with ``resume``, continue from the state in ``out_dir``.

        ``callback(step)`` sees every iteration (``IterationStep``), e.g. to plot or log it; ``progress``
        shows a progress bar.
        """
        state = self._load_state() if resume else None
        if state is None:
            state = self._start()
        history = state.history
        kept_replay = None
        bar = _progress(self.settings.iterations, len(history), progress)
        try:
            while True:
                responses, plays = self.rig.play(state.drive, float(self.time[0]), self.forces)
                response = band_pass(responses[0], self.rate, self.settings.band)
                events = self._without_hold(state.drive, plays[0])
                entry = self._entry(len(history), state, response, plays[0], events)
                history.append(entry)
                improved = self._objective(entry) < state.best_total
                if improved:  # the trust region's reference: the drive a setback goes back to
                    state.best_total, state.best_drive = self._objective(entry), state.drive
                    state.best_response, state.best_events = response, events
                if entry.ranking < state.kept_score:  # the run's result: the best under the match criterion
                    state.kept_score, state.kept_drive, state.kept_response = entry.ranking, state.drive, response
                    kept_replay = plays[0]
                drive = state.drive
                state.status, state.stop_reason = self._stop_reason(history) or ("", "")
                self._update(state, response, events, improved, entry)  # also on stopping: a resumed run goes on
                self._save(state)
                self._write_drive(state)
                if callback is not None:
                    callback(IterationStep(entry, list(history), drive, response))
                bar.set_postfix(worst=f"{entry.worst_rms_error_pct:.2f}%", gain=f"{entry.gain:.2f}", refresh=False)
                bar.update(1)
                if state.status:
                    break
        finally:
            bar.close()
        if kept_replay is None:  # the best drive was played before a resume: play it once more
            kept_replay = self.rig.play(state.kept_drive, float(self.time[0]), self.forces)[1][0]
        return IterationResult(state.kept_drive, state.kept_response, history, state.status, state.stop_reason,
                               kept_replay, estimate_frf(state.spectra))

    def first_drive(self) -> np.ndarray:
        """The drive the first iteration plays (samples x corners, m, with the lead-in and lead-out): the
        ``initial`` estimate, or the one-shot regularised FRF inverse of the target, gain times H+ target."""
        return self._start().drive

    # ---- steps ----------------------------------------------------------------------------------------
    def _identified_spectra(self) -> SpectralMatrices:
        """Spectral matrices of drives to the iterated channels: from the ``identification`` record, or from
        band-limited random drives played on the virtual rig."""
        if self.identification is not None:
            drive = self.identification.quantity("drive", self.corners)
            response = np.column_stack([self.identification[name] for name in self.channels])
            return spectral_matrices(drive, response, self.rate, self.nperseg)
        s = self.settings
        # excite beyond the band: the inverse's edges reach EDGE octaves outside it
        margin = 2.0 ** (EDGE + 0.25)
        excited = (s.band[0] / margin, min(s.band[1] * margin, 0.45 * self.rate))
        identification = band_limited_noise(s.identification_duration, self.rate, excited, s.identification_rms,
                                            len(self.corners), s.seed)
        response, _ = self.rig.play(identification)  # unfiltered: the FRF estimate is band-limited itself
        return spectral_matrices(identification, response[0], self.rate, self.nperseg)

    def _start(self) -> IterationState:
        s = self.settings
        spectra = normalised(self._identified_spectra(), s.band)
        start = s.gain * apply_frf(self._inverse(spectra), self.target) if self.initial is None else self.initial
        drive, hits = self._project(start)
        at_rest = np.zeros((self.time.size, len(self.corners)), np.int8)
        nothing = np.zeros_like(self.target)
        return IterationState(spectra, BandGains.uniform(s.band, len(self.channels), s.gain), drive, drive, nothing,
                              at_rest, drive, nothing, at_rest, np.ones(len(self.channels)), limit_hits=hits)

    def _place(self, initial: Record) -> np.ndarray:
        """An initial drive record on this job's drive time base (zero where it has no samples)."""
        if abs(initial.rate - self.rate) > 1e-9 * self.rate:
            raise RecordError(f"the initial drive is sampled at {initial.rate:g} Hz, the target at {self.rate:g} Hz")
        values = initial.quantity("drive", self.corners)
        first = int(round((initial.start_time - self.target_record.start_time) * self.rate)) + self.pad
        drive = np.zeros((self.time.size, len(self.corners)))
        lo, hi = max(first, 0), min(first + values.shape[0], drive.shape[0])
        if hi <= lo:
            raise RecordError(f"the initial drive ({initial.start_time:g}-{initial.start_time + initial.duration:g} s) "
                              f"does not overlap the target ({self.target_record.start_time:g} s on)")
        drive[lo:hi] = values[lo - first:hi - first]
        return drive

    def _placed_forces(self, target: Record) -> np.ndarray | None:
        """The target's actuator forces (``<corner>/active_force``, N, from their first sample) on the drive time base,
        its ends tapered as the target's are and at rest in the lead-in and lead-out; None when it has none. A
        measured input the car felt beside its posts: every iteration plays it, the drive makes up the rest (the
        identification runs without it: the FRF is the drive's)."""
        forces = active_forces(target, self.corners)
        if forces is None:
            return None
        return np.pad(forces * self.weight[self.span], ((self.pad, self.pad), (0, 0)))

    def _update(self, state: IterationState, response: np.ndarray, events: np.ndarray, improved: bool,
                entry: IterationRecord) -> None:
        """The next drive: the scheme's correction of the current (or, after a setback, the best) drive."""
        s = self.settings
        drive, gains = state.drive, state.gains
        if improved:
            state.scale = rescaled(state.scale, entry.channels, s.match, self._held_by_limits(entry))
        error = self._error(state, response, events)
        if s.scheme == "adaptive":
            if state.previous_drive is not None:
                window = usable_window(events, state.previous_events, self.rate)
                state.spectra, _ = updated_spectra(state.spectra, drive - state.previous_drive,
                                                   response - state.previous_response, window, self.rate, self.nperseg,
                                                   s.band)
            state.previous_drive, state.previous_response, state.previous_events = drive, response, events
            now = band_errors(error, self.rate, gains.edges)
            if improved:
                if state.band_errors is not None:
                    gains.adapt(now, state.band_errors)
                state.band_errors = now
            else:  # back to the best drive, with half the step where the error grew
                gains.halve(now, state.band_errors)
                drive, response, events = state.best_drive, state.best_response, state.best_events
                state.previous_drive, state.previous_response, state.previous_events = drive, response, events
                error = self._error(state, response, events)
        inverse = self._inverse(state.spectra) * gains.on_lines(state.spectra.frequency)[:, None, :]
        state.drive, state.limit_hits = self._project(drive + apply_frf(inverse, error))

    @staticmethod
    def _held_by_limits(entry: IterationRecord) -> bool:
        """Whether the model's limits hold the error: something out of reach, and the rest of the record within
        the default RMS tolerance (earlier, the error says more about the waveform than about the limits)."""
        return bool(entry.unreachable) and max(entry.rest_rms_error_pct.values()) <= DEFAULT_TOLERANCE["rms"]

    def _objective(self, entry: IterationRecord) -> float:
        """What the trust region compares plays by: the total RMS error, smooth in the drive where a peak is not;
        for damage matching the damage error, as the target the update aims at is rescaled each play."""
        return entry.ranking if self.settings.match == "damage" else entry.total_error_pct

    def _error(self, state: IterationState, response: np.ndarray, events: np.ndarray) -> np.ndarray:
        """The error the update corrects: the target (scaled for damage matching) minus the response, weighted by
        the end tapers; in the adaptive scheme, zero where a channel's corner was off its post (the drive has no hold
        there)."""
        error = self.weight * (state.scale * self.target - response)
        if self.settings.scheme == "adaptive":
            error = error * ~per_channel(widened(events != 0, self.rate), self.corners, self.channels)
        return error

    def _edit(self, signals: np.ndarray) -> np.ndarray:
        """Taper the ends, pad with rest, band-pass: a target record as the iteration sees it.

        Tapered before filtering, so the filter never sees a record cut off mid-motion (whose edge the
        steep low corner would ring on for seconds), and exactly as each response is filtered."""
        tapered = np.pad(signals * self.weight[self.span], ((self.pad, self.pad), (0, 0)))
        return band_pass(tapered, self.rate, self.settings.band)

    def _inverse(self, spectra: SpectralMatrices) -> np.ndarray:
        frf = estimate_frf(spectra)
        return regularised_inverse(frf.h1, frf.coherence, frf.frequency, self.settings.band,
                                   self.settings.regularisation, output_scale=self.target_rms)

    def _project(self, drive: np.ndarray) -> tuple[np.ndarray, list[LimitHit]]:
        """Taper the ends, then clip to the post stroke and velocity (reported, never silent)."""
        drive = drive * self.fade
        return check_drive(drive, self.rate, self.vehicle.rig, self.corners, self.time, clip=True)

    def _metrics(self, response: np.ndarray) -> dict[str, ChannelMetrics]:
        """Per-channel metrics of a band-passed response against the edited target over the target's span;
        errors inside the end tapers count in proportion to the taper."""
        blended = self.weight * response + (1 - self.weight) * self.target
        return channel_metrics(self.target[self.span], blended[self.span], self.channels)

    def _without_hold(self, drive: np.ndarray, played: ReplayResult) -> np.ndarray:
        """Samples x corners where the drive has no hold on a corner (0: it has): AIRBORNE where the tyre is off its
        post, AT_LIMIT where the drive sits on the post's stroke or velocity limit or the post at its force rating."""
        at_limit = on_limits(drive, self.rate, self.vehicle.rig) | at_force_rating(played.record, self.corners,
                                                                                   self.vehicle.rig)
        events = np.where(airborne(played.record, self.corners), AIRBORNE, np.where(at_limit, AT_LIMIT, 0))
        return events.astype(np.int8)

    def _entry(self, k: int, state: IterationState, response: np.ndarray, played: ReplayResult,
               events: np.ndarray) -> IterationRecord:
        metrics = self._metrics(response)
        errors = [m.rms_error_pct for m in metrics.values()]
        matched = list(channel_errors(metrics, self.settings.match).values())
        recovery = None
        if all(channel(c, "road") in self.target_record for c in self.corners):
            recovery = self._road_recovery(played.record.quantity("actuator_disp", self.corners))
        span = self.span
        blended = self.weight * response + (1 - self.weight) * self.target
        hits = state.limit_hits + played.limit_hits
        unreachable = lift_off_demands(self.target[span], blended[span], events[span] == AIRBORNE, self.channels,
                                       self.corners, self.rate, self._margin) + limit_demands(
            state.limit_hits, played.limit_hits, self.rate)
        rest, share = rest_error(self.target[span], blended[span],
                                 per_channel(widened(events != 0, self.rate), self.corners, self.channels)[span])
        return IterationRecord(k, state.gains.mean, max(errors), float(np.sqrt(np.mean(np.square(errors)))),
                               metrics, [h.describe() for h in hits], recovery,
                               float(np.sqrt(np.mean(np.square(matched)))),
                               {name: rest[j] for j, name in enumerate(self.channels)}, share, unreachable)

    def _road_recovery(self, achieved: np.ndarray) -> dict[str, dict[str, float]]:
        """Achieved post motion against the road under each wheel (track targets): RMS error in % of the
        road's, below and above 2 Hz, both edited like the target (band, end tapers). Below 2 Hz the
        accelerations say little about displacement (they scale with f^2), so the drive is loosest there."""
        road = self._edit(self.target_record.quantity("road", self.corners))
        posts = band_pass(achieved, self.rate, self.settings.band)
        low, high = self.settings.band
        result: dict[str, dict[str, float]] = {c: {} for c in self.corners}
        for label, part in ((f"{low:g}-2 Hz", (low, 2.0)), (f"2-{high:g} Hz", (2.0, high))):
            difference = (self.weight * band_pass(posts - road, self.rate, part))[self.span]
            reference = (self.weight * band_pass(road, self.rate, part))[self.span]
            for i, c in enumerate(self.corners):
                result[c][label] = float(100 * np.sqrt(np.mean(difference[:, i] ** 2) / np.mean(reference[:, i] ** 2)))
        return result

    def _stop_reason(self, history: list[IterationRecord]) -> tuple[str, str] | None:
        """(status, reason in words) when the run should stop, else None."""
        s = self.settings
        latest = history[-1]
        worst = max(channel_errors(latest.channels, s.match).values())
        if worst <= s.target_error_pct:
            return "converged", f"target reached: every channel within {_tolerance(s)}"
        rest_worst = max(latest.rest_rms_error_pct.values())
        if latest.unreachable and s.match == "rms" and rest_worst <= s.target_error_pct:
            return "limited", f"limited by the model: {self._limits(latest)}; best drive kept"
        if len(history) >= s.iterations:
            return "out_of_iterations", f"iteration limit ({s.iterations}) reached" + (
                f"; {self._limits(min(history, key=lambda h: h.ranking))}" if latest.unreachable else "")
        if s.scheme == "adaptive" and latest.gain < 1 / 64:
            return "diverged", "diverging: the error grows even with a small gain; best drive kept"
        if len(history) >= 4:
            best_before = min(h.ranking for h in history[:-3])
            best_recent = min(h.ranking for h in history[-3:])
            if best_recent > 0.99 * best_before:
                if all(h.limit_hits or h.unreachable for h in history[-3:]):
                    best = min(history, key=lambda h: h.ranking)
                    return "limited", ("stagnated on the model's limits: less than 1 % improvement in 3 iterations; "
                                       f"{self._limits(best)}; best drive kept")
                return "stagnated", "stagnated: less than 1 % improvement in 3 iterations; best drive kept"
        return None

    @staticmethod
    def _limits(entry: IterationRecord) -> str:
        """The model's limits an iteration met (each demand in full: ``IterationRecord.unreachable``), and the error
        reached on the rest of the record."""
        corners: dict[str, list[str]] = {}
        for u in entry.unreachable:
            corners.setdefault(u.kind, [])
            if u.corner not in corners[u.kind]:
                corners[u.kind].append(u.corner)
        worst = max(entry.rest_rms_error_pct, key=entry.rest_rms_error_pct.get)
        return (", ".join(f"{kind} at {', '.join(names)}" for kind, names in corners.items())
                + f"; on the rest of the record ({100 * entry.rest_share:.1f} % of it) worst channel "
                f"{entry.rest_rms_error_pct[worst]:.2f} % RMS error ({worst})")

    def score(self, drive: np.ndarray, vehicle: Vehicle | None = None) -> dict[str, ChannelMetrics]:
        """Per-channel metrics of ``drive`` played on this job's rig, or on another ``vehicle``'s (the real car)."""
        rig = self.rig if vehicle is None else VirtualRig(vehicle, self.rate, self.channels)
        return self._metrics(band_pass(rig.play(drive, forces=self.forces)[0][0], self.rate, self.settings.band))

    # ---- results -------------------------------------------------------------------------------------
    def drive_record(self, drive: np.ndarray) -> Record:
        """A drive as a record of ``<corner>/drive`` channels, with the ``<corner>/active_force`` channels every play
        applies where the target has them; time starts at -lead-in (the target starts at 0)."""
        metadata = {"vehicle": self.vehicle.name, "test": "rig", "signal": f"{self.settings.scheme} drive iteration"}
        channels = {channel(c, "drive"): drive[:, i] for i, c in enumerate(self.corners)}
        if self.forces is not None:
            channels |= {channel(c, "active_force"): self.forces[:, i] for i, c in enumerate(self.corners)}
        return Record(self.rate, channels, metadata=metadata, start_time=-self.pad / self.rate)

    def _write_drive(self, state: IterationState) -> None:
        """The best drive so far, as CSV and RPC III, atomically."""
        record = self.drive_record(state.kept_drive)
        write_record(self.out_dir / "drive.csv", record)
        write_record(self.out_dir / "drive.drv", record)

    # ---- persistence ---------------------------------------------------------------------------------
    def _save(self, state: IterationState) -> None:
        self.out_dir.mkdir(parents=True, exist_ok=True)
        with atomic_path(self.out_dir / "state.npz") as tmp:
            np.savez(tmp, **state.arrays())
        document = {
            "vehicle": self.vehicle.name,
            "channels": self.channels,
            "settings": asdict(self.settings),
            "gain": state.gains.mean,
            "best_total_error_pct": state.best_total,
            "kept_score": state.kept_score,
            "status": state.status,
            "stop_reason": state.stop_reason,
            "iterations": [entry.to_json() for entry in state.history],
        }
        write_text_atomic(self.out_dir / "history.json", json.dumps(document, indent=1))

    def _load_state(self) -> IterationState | None:
        history_path, state_path = self.out_dir / "history.json", self.out_dir / "state.npz"
        if not history_path.is_file() or not state_path.is_file():
            return None
        document = json.loads(history_path.read_text())
        settings = asdict(self.settings)
        settings["band"] = list(settings["band"])
        saved = dict(document["settings"])
        saved.setdefault("match", "rms")  # saved before the choice existed
        for key in ("iterations", "target_error_pct"):  # these may change on resume
            saved.pop(key), settings.pop(key)
        if saved != settings or document["channels"] != self.channels or document["vehicle"] != self.vehicle.name:
            raise IterationError(f"{self.out_dir} holds a run with other settings, channels or vehicle; "
                                 "resume it with the same ones or use another folder")
        gains = BandGains.uniform(self.settings.band, len(self.channels), self.settings.gain)
        at_rest = np.zeros((self.time.size, len(self.corners)), np.int8)
        return IterationState.restored(np.load(state_path), document, gains, at_rest, len(self.channels))


def check_identification(record: Record, corners: tuple[str, ...], channels: list[str], rate: float,
                         nperseg: int) -> None:
    """Refuse an identification record that cannot give the FRF: no drive or response channels, another sample
    rate than the target's, or too short for the FRF's frequency resolution."""
    record.quantity("drive", corners)  # names the corners without a drive channel
    missing = [name for name in channels if name not in record]
    if missing:
        raise RecordError(f"the identification record has no channel {', '.join(missing)}")
    if abs(record.rate - rate) > 1e-9 * rate:
        raise RecordError(f"the identification record is sampled at {record.rate:g} Hz, the target at {rate:g} Hz")
    if record.n_samples < 4 * nperseg:
        raise RecordError(f"the identification record is {record.duration:g} s long; the FRF needs at least "
                          f"{4 * nperseg / rate:g} s (4 segments of {nperseg / rate:g} s)")


def _tolerance(settings: IterationSettings) -> str:
    """The stop criterion in words."""
    t = settings.target_error_pct
    if settings.match == "damage":
        return f"a damage ratio of {1 / (1 + t / 100):.3g}-{1 + t / 100:.3g}"
    return f"{t:g} % {'peak' if settings.match == 'peak' else 'RMS'} error"


def _progress(total: int, done: int, enabled: bool):
    from tqdm import tqdm

    return tqdm(total=total, initial=done, desc="drive iteration", unit="it", disable=not enabled, leave=False)
