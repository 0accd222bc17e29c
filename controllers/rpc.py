"""RPC-style iterative drive-signal tuning with the virtual rig in the loop (Nurhadiyanto's thesis, section 4.1.1).

The procedure of MTS Remote Parameter Control / time waveform replication: identify the rig-plus-car
FRF with band-limited random drives, invert it per frequency line (rig/signal/inverse.py), then

    drive_0 = g H+ target,   drive_k+1 = drive_k + g H+ (target - response_k),

playing each drive on the rig; drive_0 may instead be any estimate (``initial``: Nurhadiyanto's inverse model,
a NARX, a file; controllers/drive_estimation.py). Two schemes:
- ``fixed``: the reference scheme of Nurhadiyanto's thesis: fixed H from the identification,
  fixed gain 0.5.
- ``adaptive`` (default): the FRF is re-estimated from every iteration's drive and response increments
  (secant information at the operating point: stops, lift-off and damper asymmetry change the effective
  FRF), and the gain is a trust region: full steps (g = 1) while the error falls; when it grows, the
  best drive is restored and the gain halved.
Drives are projected onto the post limits (stroke, velocity) inside every update and each hit is
reported; a run that diverges keeps its best drive. The FRF comes from an identification run on the virtual
rig, or from a measured drive/response record (``identification``) as a real rig's identification gives it.
History (metrics per iteration and channel) and the state needed to resume are written atomically after
every iteration.

``DriveIteration.run`` returns an ``IterationResult`` (scipy.optimize's ``OptimizeResult`` in spirit: best
drive, typed history, a status) and hands every iteration to an optional ``callback`` (plots, Rerun);
nothing here draws.
"""

from __future__ import annotations

import json
import os
from collections.abc import Callable
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np

from rig.constants import ANALYSIS_BAND
from rig.io.atomic import atomic_path, write_text_atomic
from rig.io.channels import channel
from rig.io.files import write_record
from rig.io.record import Record, RecordError
from rig.signal.filters import band_limited_noise, band_pass, fade_window
from rig.signal.frf import FrfEstimate, SpectralMatrices, estimate_frf, spectral_matrices
from rig.signal.inverse import EDGE, apply_frf, regularised_inverse
from rig.signal.metrics import channel_metrics
from rig.sim.drive_limits import LimitHit, check_drive
from rig.sim.replay import ReplayResult
from rig.sim.virtual_rig import VirtualRig
from rig.vehicle.vehicle_file import Vehicle

SCHEMES = ("adaptive", "fixed")
_PAD_MARGIN = 1.0  # s beyond half the inverse FIR's length before and after the target (see __init__)
_FADE = 1.0   # s: taper of the target's ends and of the drive's outer ends


@dataclass
class IterationSettings:
    scheme: str = "adaptive"
    iterations: int = 8
    gain: float | None = None               # fixed: 0.5; adaptive: the initial gain, 1.0
    target_error_pct: float = 3.0           # stop when every channel's RMS error is at most this
    band: tuple[float, float] = ANALYSIS_BAND  # Hz
    frequency_resolution: float = 0.125     # Hz, of the FRF: its inverse is an FIR of 1 / resolution s
    regularisation: float = 0.02            # Tikhonov alpha, relative to the largest singular value
    identification_rms: float = 0.003       # m, per post
    identification_duration: float = 120.0  # s
    seed: int = 0

    def __post_init__(self) -> None:
        if self.scheme not in SCHEMES:
            raise ValueError(f"scheme must be one of {', '.join(SCHEMES)}, got {self.scheme!r}")
        if self.gain is None:
            self.gain = 0.5 if self.scheme == "fixed" else 1.0
        self.band = tuple(self.band)


#: how a run ended: every channel within the target error; the error grew even with a small gain; no
#: progress while the drive sat on the post limits; no progress otherwise; the iteration count ran out
STATUSES = ("converged", "diverged", "limited", "stagnated", "out_of_iterations")


@dataclass
class IterationRecord:
    """One iteration: the metrics of the drive it played (one entry of history.json)."""

    iteration: int
    gain: float
    worst_rms_error_pct: float
    total_error_pct: float
    channels: dict[str, dict[str, float]]  # channel -> rms_error_pct, tddi, damage_ratio
    limit_hits: list[str]
    road_recovery_rms_error_pct: dict[str, dict[str, float]] | None = None  # track targets: corner -> band -> %

    def to_json(self) -> dict:
        document = asdict(self)
        if self.road_recovery_rms_error_pct is None:
            del document["road_recovery_rms_error_pct"]
        return document

    @classmethod
    def from_json(cls, document: dict) -> IterationRecord:
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
        return min(self.history, key=lambda h: h.total_error_pct)


class DriveIteration:
    """One drive-iteration job: a vehicle, a target record and its channels, and an output folder."""

    def __init__(self, vehicle: Vehicle, target: Record, channels: list[str], out_dir: str | os.PathLike | None,
                 settings: IterationSettings | None = None, nthread: int | None = None,
                 initial: Record | None = None, identification: Record | None = None):
        """``initial``: a first drive (``<corner>/drive`` channels, placed by its time stamps on the target's;
        default: the FRF inverse of the target); ``identification``: a measured record with the drives and
        ``channels`` whose FRF replaces the identification run on the virtual rig. ``out_dir`` may be None
        for a job that only gives its ``first_drive``."""
        self.settings = settings or IterationSettings()
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
        self.out_dir = None if out_dir is None else Path(out_dir)
        self.rig = VirtualRig(vehicle, self.rate, self.channels, nthread)
        self.corners = vehicle.corners
        self.time = (np.arange(self.target.shape[0]) - self.pad) / self.rate  # drive time: the target starts at 0
        self.nperseg = int(2 ** np.ceil(np.log2(self.rate / self.settings.frequency_resolution)))
        self.initial = None if initial is None else self._place(initial)
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
        history = state["history"]
        best_replay = None
        bar = _progress(self.settings.iterations, len(history), progress)
        try:
            while True:
                k = len(history)
                responses, plays = self.rig.play(state["drive"], float(self.time[0]))
                response = band_pass(responses[0], self.rate, self.settings.band)
                entry = self._entry(k, state, response, plays[0])
                history.append(entry)
                improved = entry.total_error_pct < state["best_total"]
                if improved:
                    state.update(best_total=entry.total_error_pct, best_drive=state["drive"], best_response=response)
                    best_replay = plays[0]
                drive = state["drive"]
                status, reason = self._stop_reason(history) or ("", "")
                self._update(state, response, improved)  # also on stopping: a resumed run continues from here
                state["status"], state["stop_reason"] = status, reason
                self._save(state)
                self._write_drive(state)
                if callback is not None:
                    callback(IterationStep(entry, list(history), drive, response))
                bar.set_postfix(worst=f"{entry.worst_rms_error_pct:.2f}%", gain=f"{entry.gain:.2f}", refresh=False)
                bar.update(1)
                if status:
                    break
        finally:
            bar.close()
        if best_replay is None:  # the best drive was played before a resume: play it once more
            best_replay = self.rig.play(state["best_drive"], float(self.time[0]))[1][0]
        return IterationResult(state["best_drive"], state["best_response"], history, state["status"],
                               state["stop_reason"], best_replay, estimate_frf(state["spectra"]))

    def first_drive(self) -> np.ndarray:
        """The drive the first iteration plays (samples x corners, m, with the lead-in and lead-out): the
        ``initial`` estimate, or the one-shot regularised FRF inverse of the target, gain times H+ target."""
        return self._start()["drive"]

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

    def _start(self) -> dict:
        s = self.settings
        state = {"spectra": _normalised(self._identified_spectra(), s.band), "gain": s.gain, "history": [],
                 "best_total": np.inf, "previous_drive": None, "previous_response": None, "status": "",
                 "stop_reason": ""}
        if self.initial is None:
            start = s.gain * apply_frf(self._inverse(state["spectra"]), self.target)
        else:
            start = self.initial
        state["drive"], state["limit_hits"] = self._project(start)
        state["best_drive"], state["best_response"] = state["drive"], np.zeros_like(self.target)
        return state

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

    def _update(self, state: dict, response: np.ndarray, improved: bool) -> None:
        """The next drive: the scheme's correction of the current (or, after a setback, the best) drive."""
        s = self.settings
        drive = state["drive"]
        if s.scheme == "adaptive":
            if state["previous_drive"] is not None:
                increment = spectral_matrices(drive - state["previous_drive"], response - state["previous_response"],
                                              self.rate, self.nperseg)
                state["spectra"] = state["spectra"] + _normalised(increment, s.band)
            state["previous_drive"], state["previous_response"] = drive, response
            if not improved:  # trust region: back to the best drive with half the step
                state["gain"] *= 0.5
                drive, response = state["best_drive"], state["best_response"]
                state["previous_drive"], state["previous_response"] = drive, response
            else:
                state["gain"] = min(s.gain, 2 * state["gain"])  # recover the step after a setback
        correction = apply_frf(self._inverse(state["spectra"]), self.weight * (self.target - response))
        state["drive"], state["limit_hits"] = self._project(drive + state["gain"] * correction)

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

    def _metrics(self, response: np.ndarray) -> dict[str, dict[str, float]]:
        """Per-channel metrics of a band-passed response against the edited target over the target's span;
        errors inside the end tapers count in proportion to the taper."""
        blended = self.weight * response + (1 - self.weight) * self.target
        return channel_metrics(self.target[self.span], blended[self.span], self.channels)

    def _entry(self, k: int, state: dict, response: np.ndarray, played: ReplayResult) -> IterationRecord:
        metrics = self._metrics(response)
        errors = [m["rms_error_pct"] for m in metrics.values()]
        recovery = None
        if all(channel(c, "road") in self.target_record for c in self.corners):
            recovery = self._road_recovery(played.record.quantity("actuator_disp", self.corners))
        return IterationRecord(k, float(state["gain"]), max(errors), float(np.sqrt(np.mean(np.square(errors)))),
                               metrics, [h.describe() for h in state["limit_hits"] + played.limit_hits], recovery)

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
        if latest.worst_rms_error_pct <= s.target_error_pct:
            return "converged", f"target reached: every channel within {s.target_error_pct:g} % RMS error"
        if len(history) >= s.iterations:
            return "out_of_iterations", f"iteration limit ({s.iterations}) reached"
        if s.scheme == "adaptive" and latest.gain < 1 / 64:
            return "diverged", "diverging: the error grows even with a small gain; best drive kept"
        if len(history) >= 4:
            best_before = min(h.total_error_pct for h in history[:-3])
            best_recent = min(h.total_error_pct for h in history[-3:])
            if best_recent > 0.99 * best_before:
                if all(h.limit_hits for h in history[-3:]):
                    return "limited", ("stagnated on the post limits: less than 1 % improvement in 3 iterations, "
                                       "each reaching a limit; best drive kept")
                return "stagnated", "stagnated: less than 1 % improvement in 3 iterations; best drive kept"
        return None

    def score(self, drive: np.ndarray, vehicle: Vehicle | None = None) -> dict[str, dict[str, float]]:
        """Per-channel metrics of ``drive`` played on this job's rig, or on another ``vehicle``'s (the real car)."""
        rig = self.rig if vehicle is None else VirtualRig(vehicle, self.rate, self.channels)
        return self._metrics(band_pass(rig.play(drive)[0][0], self.rate, self.settings.band))

    # ---- results -------------------------------------------------------------------------------------
    def drive_record(self, drive: np.ndarray) -> Record:
        """A drive as a record of ``<corner>/drive`` channels; time starts at -lead-in (the target starts at 0)."""
        metadata = {"vehicle": self.vehicle.name, "test": "rig", "signal": f"{self.settings.scheme} drive iteration"}
        return Record(self.rate, {channel(c, "drive"): drive[:, i] for i, c in enumerate(self.corners)},
                      metadata=metadata, start_time=-self.pad / self.rate)

    def _write_drive(self, state: dict) -> None:
        """The best drive so far, as CSV and RPC III, atomically."""
        record = self.drive_record(state["best_drive"])
        write_record(self.out_dir / "drive.csv", record)
        write_record(self.out_dir / "drive.drv", record)

    # ---- persistence ---------------------------------------------------------------------------------
    def _save(self, state: dict) -> None:
        self.out_dir.mkdir(parents=True, exist_ok=True)
        arrays = {k: v for k, v in state.items() if isinstance(v, np.ndarray)}
        spectra = state["spectra"]
        arrays.update(sxx=spectra.sxx, sxy=spectra.sxy, syy=spectra.syy, frequency=spectra.frequency)
        for key in ("previous_drive", "previous_response"):
            if state[key] is not None:
                arrays[key] = state[key]
        with atomic_path(self.out_dir / "state.npz") as tmp:
            np.savez(tmp, **arrays)
        document = {
            "vehicle": self.vehicle.name,
            "channels": self.channels,
            "settings": asdict(self.settings),
            "gain": state["gain"],
            "best_total_error_pct": state["best_total"],
            "status": state["status"],
            "stop_reason": state["stop_reason"],
            "iterations": [entry.to_json() for entry in state["history"]],
        }
        write_text_atomic(self.out_dir / "history.json", json.dumps(document, indent=1))

    def _load_state(self) -> dict | None:
        history_path, state_path = self.out_dir / "history.json", self.out_dir / "state.npz"
        if not history_path.is_file() or not state_path.is_file():
            return None
        document = json.loads(history_path.read_text())
        settings = asdict(self.settings)
        settings["band"] = list(settings["band"])
        saved = dict(document["settings"])
        for key in ("iterations", "target_error_pct"):  # these may change on resume
            saved.pop(key), settings.pop(key)
        if saved != settings or document["channels"] != self.channels or document["vehicle"] != self.vehicle.name:
            raise ValueError(f"{self.out_dir} holds a run with other settings, channels or vehicle; "
                             "resume it with the same ones or use another folder")
        arrays = np.load(state_path)
        state = {"history": [IterationRecord.from_json(entry) for entry in document["iterations"]],
                 "gain": document["gain"], "best_total": document["best_total_error_pct"],
                 "status": document.get("status", ""), "stop_reason": document["stop_reason"],
                 "spectra": SpectralMatrices(arrays["frequency"], arrays["sxx"], arrays["sxy"], arrays["syy"]),
                 "drive": arrays["drive"], "best_drive": arrays["best_drive"], "best_response": arrays["best_response"],
                 "previous_drive": arrays.get("previous_drive", None),
                 "previous_response": arrays.get("previous_response", None),
                 "limit_hits": []}
        return state


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


def _normalised(spectra: SpectralMatrices, band: tuple[float, float]) -> SpectralMatrices:
    """Spectra scaled to unit mean input power in the band: every record counts alike in the estimate."""
    inside = (spectra.frequency >= band[0]) & (spectra.frequency <= band[1])
    power = np.trace(spectra.sxx[inside], axis1=1, axis2=2).real.mean()
    return spectra.scaled(1.0 / power) if power > 0 else spectra


def _progress(total: int, done: int, enabled: bool):
    from tqdm import tqdm

    return tqdm(total=total, initial=done, desc="drive iteration", unit="it", disable=not enabled, leave=False)
