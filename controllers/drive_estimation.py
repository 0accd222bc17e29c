"""Drive estimation from a measured response (Nurhadiyanto's thesis, chapters 5-6): a first
drive for iteration, straight from the target's accelerations.

- ``inverse-model``: Nurhadiyanto's linear quarter-car inverse, Eq 5.1 per corner from the vehicle file, carried
  back through the servo model (controllers/inverse_model.py);
- ``frf``: the one-shot regularised FRF inverse that drive iteration starts from (controllers/rpc.py), with
  H1 from a measured drive/response record (``train``) or from an identification run of the virtual rig;
- ``narx``: Nurhadiyanto's NARX network, one per corner, fitted on ``train`` or on an identification run of the
  virtual rig (controllers/narx.py), its structure chosen on a validation split by free-run error. Where both
  records measure the suspension travel (``susp_travel``), the networks take it as measured. The estimate says
  where the target's amplitudes exceed the training's (controllers/training_coverage.py): there the NARX
  extrapolates. Without ``train``, the identification run's drive is designed from the target to cover its
  amplitudes (``training_drive``), and where the target still goes beyond it, the NARX is iterated on its own
  error: its estimate is played on the virtual rig, the play joins the training data and the network is fitted
  again (``REFINEMENTS`` times): it learns the car where the target takes it.

- ``neuro``: the neuro form, Eq 5.1 through the servo whose suspension force is the neuro-model paper's network,
  learned from ``train`` (or an identification run of the virtual rig designed to cover the target;
  controllers/neuro_inverse.py);
- ``auto``: the method chosen by its check on the part of the training record it was not fitted on, its drive error
  and its residual's whiteness, the car's structure first where the target leaves the training
  (controllers/inverse_choice.py).

Given a training record (or the identification run), each estimate carries its check on the held-out part
(``checks``: drive error and residual tests per corner; for ``auto``, every method's), and ``summary()`` says all of
it for a file.

Where the target measures the tyre forces, every method's drive is bridged over the stretches a tyre was off its
post (controllers/lift_off_bridge.py): there the responses bound the post from above only.

Each returns a ``DriveEstimate``: the drive as a record of ``<corner>/drive`` channels on the target's time
base, and a line saying how it was made; ``at_rest()`` fades it in and out at its ends, as a drive file must
(``rig replay`` refuses a drive that does not start at rest; drive iteration fades its drives the same way).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field, replace

import numpy as np

from controllers.inverse_model import inverse_model_drive
from controllers.lift_off_bridge import airborne, bridged, off_post
from controllers.inverse_choice import HeldOut, choose, held_out, split
from controllers.narx import CANDIDATES, NarxFit, NarxStructure, fit_narx, fit_structure
from controllers.neuro_inverse import fit_neuro_inverse
from controllers.rpc import DriveIteration, IterationSettings
from controllers.training_coverage import Coverage, coverage, training_drive
from rig.constants import ANALYSIS_BAND
from rig.io.checks import require_band
from rig.io.channels import channel
from rig.io.record import Record, RecordError
from rig.signal.filters import fade_window
from rig.signal.metrics import drive_error_pct
from rig.sim.virtual_rig import VirtualRig
from rig.vehicle.vehicle_file import Vehicle

METHODS = ("inverse-model", "frf", "narx", "neuro", "auto")
CHOSEN = ("inverse-model", "frf", "narx", "neuro")  # what ``auto`` chooses from
RESPONSES = ("sprung_acc", "unsprung_acc")

#: the virtual rig's identification run for a NARX without ``train``: a drive designed from the target to cover
#: its amplitudes (controllers/training_coverage.py), 60 s, and the refits on the NARX's own plays where the
#: target still goes beyond it
IDENTIFICATION_DURATION = 60.0  # s
REFINEMENTS = 1
FADE = 1.0  # s: a drive file's ends fade to rest over this time (as drive iteration's do)
MIN_TARGET_DURATION = 4 * FADE  # s: the fades take at most half of a target
MIN_FRF_SECONDS = 32.0  # s: the FRF's H1 needs four segments of 8 s


@dataclass
class DriveEstimate:
    """An estimated drive: ``<corner>/drive`` channels (m) on the target's time base, and how it was made."""

    method: str
    drive: Record
    detail: str
    band: tuple[float, float] = ANALYSIS_BAND  # Hz: the band the drive was estimated in
    narx: NarxFit | None = None  # the fitted NARX and its validation errors (method ``narx``)
    coverage: Coverage | None = None  # where the target exceeds the training (methods that learn from one)
    checks: list[HeldOut] = field(default_factory=list)  # on the training's held-out part (inverse_choice.py)
    choice: str | None = None  # why ``auto`` chose the method

    def summary(self) -> dict:
        """What a file says of the estimate: the method, how it was made, its checks and the training's coverage."""
        return {"method": self.method, "detail": self.detail, "band_hz": list(self.band), "choice": self.choice,
                "coverage": None if self.coverage is None else self.coverage.describe(),
                "checks": {c.method: c.to_json() for c in self.checks}}

    @property
    def values(self) -> np.ndarray:
        """Samples x corners, m."""
        return np.column_stack(list(self.drive.channels.values()))

    def at_rest(self) -> Record:
        """The drive faded in and out over FADE s at its ends: a drive file that starts and ends at rest."""
        fade = fade_window(self.drive.n_samples, int(round(FADE * self.drive.rate)))
        return Record(self.drive.rate, {name: values * fade for name, values in self.drive.channels.items()},
                      dict(self.drive.units), dict(self.drive.metadata), self.drive.start_time)


def estimate_drive(vehicle: Vehicle, target: Record, method: str, train: Record | None = None,
                   channels: list[str] | None = None, candidates: tuple[NarxStructure, ...] = CANDIDATES,
                   progress: Callable[[str], None] | None = None) -> DriveEstimate:
    """Estimate the post drives that reproduce ``target`` on ``vehicle``'s rig with ``method`` (METHODS), in the
    analysis band the target supports.

    ``channels``: the target channels the FRF inverse reproduces (default: every body and wheel acceleration);
    ``train``: a measured record with drives and responses at the target's rate (``frf``: its H1; ``narx``:
    its training data); ``candidates``: the NARX structures to choose from.
    """
    if method not in METHODS:
        raise ValueError(f"method must be one of {', '.join(METHODS)}, got {method!r}")
    if target.duration < MIN_TARGET_DURATION:
        raise RecordError(f"the target is {target.duration:.3g} s; a drive estimate needs at least "
                          f"{MIN_TARGET_DURATION:g} s (its ends fade in and out over {FADE:g} s)")
    band = require_band(target, "the target", "drive estimation")
    corners = vehicle.corners
    for quantity in RESPONSES:
        target.quantity(quantity, corners)  # names the missing corners
    if train is not None and abs(train.rate - target.rate) > 1e-9 * target.rate:
        raise RecordError(f"the training record is sampled at {train.rate:g} Hz, the target at {target.rate:g} Hz")
    measured = all(channel(c, "susp_travel") in record for record in (target, train) if record is not None
                   for c in corners)
    checks, choice, narx = [], None, None
    if method in ("neuro", "auto") and train is None:
        train = rig_record(vehicle, training_drive(vehicle, target, IDENTIFICATION_DURATION, band), target.rate,
                           "identification run of the virtual rig, designed to cover the target", measured)
    if method == "auto":
        checked = [_check(m, vehicle, train, band, candidates, measured, channels, progress) for m in CHOSEN
                   if _checkable(m, train)]
        checks = [check for check, _ in checked]
        narx = next((fit for _, fit in checked if fit is not None), None)
        chosen, choice = choose(checks, coverage(train, target, corners, band, measured).covered)
        method = chosen.method
    values, fit, cover, detail, load = _estimated(method, vehicle, target, train, band, candidates, measured,
                                                  channels, progress, narx)
    if train is not None and not checks and _checkable(method, train):
        checks = [_check(method, vehicle, train, band, candidates, measured, channels, progress, fit)[0]]
    off = airborne(target, corners)
    estimated = off is None and load is not None
    off = off_post(load, target.rate) if estimated else off
    if off is not None and off.any():  # a tyre off its post: the responses bound the post from above only
        values = bridged(values, off, target.rate)
        detail += (f"; bridged over the {off.any(axis=1).sum() / target.rate:.2g} s a tyre was off its post"
                   + (" (by the tyre load the learned suspension force gives)" if estimated else ""))
    drive = Record(target.rate, {channel(c, "drive"): values[:, i] for i, c in enumerate(corners)},
                   metadata={"vehicle": vehicle.name, "test": "rig", "signal": f"{method} drive estimate"},
                   start_time=target.start_time)
    return DriveEstimate(method, drive, detail, band, fit, cover, checks, choice)


def _estimated(method: str, vehicle: Vehicle, target: Record, train: Record | None, band: tuple[float, float],
               candidates: tuple[NarxStructure, ...], measured: bool, channels: list[str] | None,
               progress: Callable[[str], None] | None, narx: NarxFit | None):
    """One method's drive for the target, its NARX fit, the training's coverage of the target, how it was made and
    the tyre loads it estimates (the neuro form's; else None)."""
    corners = vehicle.corners
    if method == "inverse-model":
        return inverse_model_drive(vehicle, target, band), None, None, \
            "Nurhadiyanto's Eq 5.1 per corner, through the servo model", None
    if method == "frf":
        channels = channels or [channel(c, q) for c in corners for q in RESPONSES]
        job = DriveIteration(vehicle, target, channels, None, IterationSettings(band=band), identification=train)
        source = "the training record" if train is not None else "an identification run of the virtual rig"
        return job.first_drive()[job.span], None, None, f"one-shot regularised FRF inverse, H1 from {source}", None
    if method == "neuro":
        inverse = fit_neuro_inverse(vehicle, train, band, measured)
        return inverse.drive(target), None, coverage(train, target, corners, band, measured), \
            f"neuro form: {inverse.describe()}", inverse.tyre_load(target)
    if narx is not None:  # fitted while it was checked
        return narx.model.simulate(target), narx, coverage(train, target, corners, band, measured), \
            f"NARX ({narx.structure.describe()}) from the training record, free run", None
    return (*_narx_drive(vehicle, target, train, candidates, band, progress), None)


def _checkable(method: str, train: Record) -> bool:
    """Whether the part of ``train`` a check fits on is long enough for ``method`` (the FRF's four segments)."""
    return method != "frf" or split(train)[0].duration >= MIN_FRF_SECONDS


def _check(method: str, vehicle: Vehicle, train: Record, band: tuple[float, float],
           candidates: tuple[NarxStructure, ...], measured: bool, channels: list[str] | None,
           progress: Callable[[str], None] | None, fitted: NarxFit | None = None) -> tuple[HeldOut, NarxFit | None]:
    """``method`` checked on the held-out part of ``train`` (controllers/inverse_choice.py), and the NARX fitted on
    the way (its own validation split is the same: its validation drive is the check)."""
    corners = vehicle.corners
    if method == "narx":
        narx = fitted or fit_narx(train, corners, tuple(replace(s, measured_travel=measured and s.integrated)
                                                        for s in candidates), band=band, progress=progress)
        return held_out(method, None, train, corners, band, narx.model.parameters.size, narx.validation_drive), narx

    def estimate(fit_part: Record, whole: Record) -> np.ndarray:
        return _estimated(method, vehicle, whole, fit_part, band, candidates, measured, channels, progress, None)[0]

    return held_out(method, estimate, train, corners, band), None


def _narx_drive(vehicle: Vehicle, target: Record, train: Record | None, candidates: tuple[NarxStructure, ...],
                band: tuple[float, float], progress: Callable[[str], None] | None):
    """The NARX's free-run drive for the target, its fit, the training's coverage of the target and the method's
    description."""
    corners = vehicle.corners
    measured = all(channel(c, "susp_travel") in record for record in (target, train) if record is not None
                   for c in corners)
    on_rig = train is None
    if on_rig:
        train = rig_record(vehicle, training_drive(vehicle, target, IDENTIFICATION_DURATION, band), target.rate,
                           "identification run of the virtual rig, designed to cover the target", measured)
    candidates = tuple(replace(s, measured_travel=measured and s.integrated) for s in candidates)
    fit = fit_narx(train, corners, candidates, band=band, progress=progress)
    cover = coverage(train, target, corners, band, measured)
    refits = 0
    while on_rig and not cover.covered and refits < REFINEMENTS:  # iterated on its own error where it extrapolates
        estimate = fit.model.simulate(target) * fade_window(target.n_samples, int(FADE * target.rate))[:, None]
        train = joined(train, rig_record(vehicle, estimate, target.rate, "the NARX's estimate on the virtual rig",
                                         measured))
        fit = NarxFit(fit_structure(train, corners, fit.structure, band), fit.validation_error_pct)
        cover, refits = coverage(train, target, corners, band, measured), refits + 1
    source = "the training record" if not on_rig else "a designed run of the virtual rig" + (
        f" and {refits} play(s) of its own estimate" if refits else "")
    return fit.model.simulate(target), fit, cover, f"NARX ({fit.structure.describe()}) from {source}, free run"


def rig_record(vehicle: Vehicle, drive: np.ndarray, rate: float, signal: str, travel: bool = False) -> Record:
    """A run of the virtual rig: the drives (samples x corners, m), the body and wheel accelerations and, with
    ``travel``, the suspension travel."""
    quantities = RESPONSES + (("susp_travel",) if travel else ())
    names = [channel(c, q) for c in vehicle.corners for q in quantities]
    response = VirtualRig(vehicle, rate, names).play(drive)[0][0]
    channels = {channel(c, "drive"): drive[:, i] for i, c in enumerate(vehicle.corners)}
    channels.update({name: response[:, i] for i, name in enumerate(names)})
    return Record(rate, channels, metadata={"vehicle": vehicle.name, "test": "rig", "signal": signal})


def joined(first: Record, second: Record) -> Record:
    """Two records of the same channels one after the other (both at rest where they meet)."""
    return Record(first.rate, {n: np.concatenate([v, second[n]]) for n, v in first.channels.items()},
                  dict(first.units), dict(first.metadata))


def drive_errors(true: Record, estimate: DriveEstimate) -> dict[str, float]:
    """Nurhadiyanto's drive error per corner (%): RMS of estimate minus true drive over the true drive's RMS, in
    the band the drive was estimated in, over the samples both records hold."""
    corners = true.corners_with("drive")
    start = int(round((estimate.drive.start_time - true.start_time) * true.rate))
    estimated = estimate.drive.quantity("drive", corners)
    truth = true.quantity("drive", corners)
    lo, hi = max(start, 0), min(start + estimated.shape[0], truth.shape[0])
    errors = drive_error_pct(truth[lo:hi], estimated[lo - start:hi - start], true.rate, estimate.band)
    return dict(zip(corners, map(float, errors)))
