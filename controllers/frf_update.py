"""The FRF updated from the iterations' own drives and responses, robust to lift-off.

The adaptive scheme adds the spectral matrices of each play's increments (drive and response minus the
previous play's) to the identification's: secant information at the operating point, where stops and damper
asymmetry change the effective FRF. A tyre off its post breaks that relation (the post no longer moves the
wheel), and so does a drive clipped to the post's limits; the increments are used only where every tyre stayed
on its post and every post within its limits in both plays: the stretches around such events
(``LIFT_OFF_GUARD`` on each side) are faded out of both, and a play pair with too little left gives no update.
What remains counts per frequency line by its own multiple coherence (the share of the response increment the
drive increment explains linearly; with no more Welch segments than drives it would be one by construction,
and every line counts fully), and the update's step is halved until the FRF changes by at most
``MAX_CHANGE`` (median over the band's lines and channels, relative) in one iteration.
"""

from __future__ import annotations

import numpy as np
from scipy.ndimage import binary_dilation

from rig.signal.frf import SpectralMatrices, estimate_frf, spectral_matrices

LIFT_OFF_GUARD = 0.1  # s around an event: the wheel's landing transient (the wheel hop rings for about this)
MIN_USABLE = 0.5      # share of the samples that must be usable for an update
MAX_CHANGE = 0.25     # most relative change of the FRF per iteration (median over lines and channels)
_FADE = 0.05          # s: the fade of each usable stretch's ends


def normalised(spectra: SpectralMatrices, band: tuple[float, float]) -> SpectralMatrices:
    """Spectra scaled to unit mean input power in the band: every record counts alike in the estimate."""
    inside = (spectra.frequency >= band[0]) & (spectra.frequency <= band[1])
    power = np.trace(spectra.sxx[inside], axis1=1, axis2=2).real.mean()
    return spectra.scaled(1.0 / power) if power > 0 else spectra


def usable_window(events_now: np.ndarray, events_before: np.ndarray, rate: float) -> np.ndarray:
    """Weight per sample (0-1): zero within LIFT_OFF_GUARD of any corner's event (non-zero in samples x corners:
    a tyre off its post, a post on its limits) in either play, rising to one over _FADE s beyond."""
    off = np.any(events_now != 0, axis=1) | np.any(events_before != 0, axis=1)
    fade = max(1, int(round(_FADE * rate)))
    if off.any():
        off = binary_dilation(off, np.ones(2 * (int(round(LIFT_OFF_GUARD * rate)) + fade) + 1, bool))
    kernel = np.hanning(2 * fade + 1)
    return np.convolve((~off).astype(float), kernel / kernel.sum(), "same")


def updated_spectra(spectra: SpectralMatrices, drive_step: np.ndarray, response_step: np.ndarray,
                    window: np.ndarray, rate: float, nperseg: int, band: tuple[float, float]
                    ) -> tuple[SpectralMatrices, float]:
    """The spectra with a play pair's increments added (see the module's docstring), and the share of the full
    step taken (0: no update)."""
    if window.mean() < MIN_USABLE:
        return spectra, 0.0
    increment = normalised(spectral_matrices(drive_step * window[:, None], response_step * window[:, None],
                                             rate, nperseg), band)
    coherence = _coherence(increment, drive_step.shape[0], nperseg)
    weighted = SpectralMatrices(increment.frequency, increment.sxx * coherence[:, None, None],
                                increment.sxy * coherence[:, None, None], increment.syy * coherence[:, None])
    inside = (spectra.frequency >= band[0]) & (spectra.frequency <= band[1])
    before = estimate_frf(spectra).h1[inside]
    share = 1.0
    while share >= 1 / 16:
        candidate = spectra + weighted.scaled(share)
        after = estimate_frf(candidate).h1[inside]
        if np.median(np.abs(after - before) / np.maximum(np.abs(before), 1e-300)) <= MAX_CHANGE:
            return candidate, share
        share /= 2
    return spectra, 0.0


def _coherence(increment: SpectralMatrices, samples: int, nperseg: int) -> np.ndarray:
    """Mean multiple coherence of the outputs per line; ones where too few segments make it meaningless."""
    segments = (samples - nperseg) // (nperseg // 2) + 1
    if segments <= increment.sxx.shape[1]:
        return np.ones(increment.frequency.size)
    return estimate_frf(increment).coherence.mean(axis=1)
