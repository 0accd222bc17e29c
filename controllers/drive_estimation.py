"""Drive estimation from a measured response (Nurhadiyanto's thesis, chapters 5-6): a first
drive for iteration, straight from the target's accelerations.

- ``inverse-model``: Nurhadiyanto's linear quarter-car inverse, Eq 5.1 per corner from the vehicle file, carried
  back through the servo model (controllers/inverse_model.py);
- ``frf``: the one-shot regularised FRF inverse that drive iteration starts from (controllers/rpc.py), with
  H1 from a measured drive/response record (``train``) or from an identification run of the virtual rig;
- ``narx``: Nurhadiyanto's NARX network, one per corner, fitted on ``train`` or on an identification run of the
  virtual rig (controllers/narx.py), its structure chosen on a validation split by free-run error.

Each returns a ``DriveEstimate``: the drive as a record of ``<corner>/drive`` channels on the target's time
base, and a line saying how it was made; ``at_rest()`` fades it in and out at its ends, as a drive file must
(``rig replay`` refuses a drive that does not start at rest; drive iteration fades its drives the same way).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from controllers.inverse_model import inverse_model_drive
from controllers.narx import CANDIDATES, NarxFit, NarxStructure, check_training_record, fit_narx
from controllers.rpc import DriveIteration, IterationSettings
from rig.constants import ANALYSIS_BAND
from rig.io.channels import channel
from rig.io.record import Record, RecordError
from rig.signal.filters import band_limited_noise, fade_window
from rig.signal.metrics import drive_error_pct
from rig.sim.virtual_rig import VirtualRig
from rig.vehicle.vehicle_file import Vehicle

METHODS = ("inverse-model", "frf", "narx")
RESPONSES = ("sprung_acc", "unsprung_acc")

#: the virtual rig's identification run for a NARX without ``train``: pink noise (PSD ~ 1/f, as road
#: displacement falls with frequency), 60 s
IDENTIFICATION_DURATION = 60.0  # s
IDENTIFICATION_RMS = 0.004      # m per post
IDENTIFICATION_BAND = (0.3, 40.0)  # Hz
FADE = 1.0  # s: a drive file's ends fade to rest over this time (as drive iteration's do)


@dataclass
class DriveEstimate:
    """An estimated drive: ``<corner>/drive`` channels (m) on the target's time base, and how it was made."""

    method: str
    drive: Record
    detail: str
    narx: NarxFit | None = None  # the fitted NARX and its validation errors (method ``narx``)

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
    """Estimate the post drives that reproduce ``target`` on ``vehicle``'s rig with ``method`` (METHODS).

    ``channels``: the target channels the FRF inverse reproduces (default: every body and wheel acceleration);
    ``train``: a measured record with drives and responses at the target's rate (``frf``: its H1; ``narx``:
    its training data); ``candidates``: the NARX structures to choose from.
    """
    if method not in METHODS:
        raise ValueError(f"method must be one of {', '.join(METHODS)}, got {method!r}")
    corners = vehicle.corners
    for quantity in RESPONSES:
        target.quantity(quantity, corners)  # names the missing corners
    if train is not None and abs(train.rate - target.rate) > 1e-9 * target.rate:
        raise RecordError(f"the training record is sampled at {train.rate:g} Hz, the target at {target.rate:g} Hz")
    if method == "inverse-model":
        values, fit = inverse_model_drive(vehicle, target), None
        detail = "Nurhadiyanto's Eq 5.1 per corner, through the servo model"
    elif method == "frf":
        channels = channels or [channel(c, q) for c in corners for q in RESPONSES]
        job = DriveIteration(vehicle, target, channels, None, IterationSettings(), identification=train)
        values = job.first_drive()[job.span]
        source = "the training record" if train is not None else "an identification run of the virtual rig"
        detail, fit = f"one-shot regularised FRF inverse, H1 from {source}", None
    else:
        if train is None:
            train = identification_record(vehicle, target.rate)
        check_training_record(train, corners, max(s.order for s in candidates))
        fit = fit_narx(train, corners, candidates, progress=progress)
        values = fit.model.simulate(target)
        detail = f"NARX ({fit.structure.describe()}), free run"
    drive = Record(target.rate, {channel(c, "drive"): values[:, i] for i, c in enumerate(corners)},
                   metadata={"vehicle": vehicle.name, "test": "rig", "signal": f"{method} drive estimate"},
                   start_time=target.start_time)
    return DriveEstimate(method, drive, detail, fit)


def identification_record(vehicle: Vehicle, rate: float, seed: int = 0) -> Record:
    """An identification run of the virtual rig: pink-noise drives and the body and wheel accelerations."""
    drive = band_limited_noise(IDENTIFICATION_DURATION, rate, IDENTIFICATION_BAND, IDENTIFICATION_RMS,
                               len(vehicle.corners), seed, slope=1.0)
    names = [channel(c, q) for c in vehicle.corners for q in RESPONSES]
    response = VirtualRig(vehicle, rate, names).play(drive)[0][0]
    channels = {channel(c, "drive"): drive[:, i] for i, c in enumerate(vehicle.corners)}
    channels.update({name: response[:, i] for i, name in enumerate(names)})
    return Record(rate, channels, metadata={"vehicle": vehicle.name, "test": "rig",
                                            "signal": "pink-noise identification run of the virtual rig"})


def drive_errors(true: Record, estimate: DriveEstimate, band: tuple[float, float] = ANALYSIS_BAND) -> dict[str, float]:
    """Nurhadiyanto's drive error per corner (%): RMS of estimate minus true drive over the true drive's RMS, in
    the drive band, over the samples both records hold."""
    corners = true.corners_with("drive")
    start = int(round((estimate.drive.start_time - true.start_time) * true.rate))
    estimated = estimate.drive.quantity("drive", corners)
    truth = true.quantity("drive", corners)
    lo, hi = max(start, 0), min(start + estimated.shape[0], truth.shape[0])
    errors = drive_error_pct(truth[lo:hi], estimated[lo - start:hi - start], true.rate, band)
    return dict(zip(corners, map(float, errors)))
