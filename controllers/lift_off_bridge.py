"""A drive estimate bridged over the stretches where the target's tyres were off their posts.

While a tyre is off its post, the body and wheel say only that the post is below where it would touch the wheel: Eq
5.1 gives exactly that touching position there, and the NARX, fitted where the tyre pushes, about the same; the post
itself goes on down (a bump's far side, a hole). Where the target measures the tyre force (wheel-pan load cells;
else where an estimate of it is at hand: the neuro form's, from the wheel's equilibrium), the stretches where it is
off (``airborne``: the force, averaged over ``SMOOTH`` s, below ``OFF_SHARE`` of its mean, gaps shorter than
``SMOOTH`` closed, widened by half the average's width) are re-estimated as the flattest drive (least squared second
difference over the stretch and ``CONTEXT`` s each side, the estimate kept outside it) that stays below the estimate
inside it: ``scipy.optimize.lsq_linear`` with the estimate as upper bound.

Measured on the large-event case of tests/drive_estimation_case.py (two NARX estimates; the rear left off its post
for 0.05 s twice): worst corner 11.5 % and 9.3 % unbridged, 3.8-7.6 % and 2.8-5.9 % bridged, for thresholds of 2-10
% and averages over 6-18 ms (7.4 % and 4.6 % at the defaults).
"""

from __future__ import annotations

import numpy as np
from scipy.ndimage import binary_closing, binary_dilation, label, uniform_filter1d
from scipy.optimize import lsq_linear

from rig.io.channels import channel
from rig.io.record import Record

SMOOTH = 0.01     # s
OFF_SHARE = 0.05  # of the tyre force's mean
CONTEXT = 0.03    # s of the estimate on each side the bridge joins smoothly


def airborne(target: Record, corners: tuple[str, ...]) -> np.ndarray | None:
    """Samples x corners where the target's tyre is off its post, or None without measured tyre forces."""
    names = [channel(c, "tyre_force") for c in corners]
    if not all(name in target for name in names):
        return None
    return off_post(np.column_stack([target[name] for name in names]), target.rate)


def off_post(force: np.ndarray, rate: float) -> np.ndarray:
    """Samples x corners where a tyre force (measured, or estimated where none is: controllers/neuro_inverse.py)
    says the tyre is off its post (module docstring)."""
    width = max(1, int(round(SMOOTH * rate)))
    off = uniform_filter1d(force, width, axis=0) < OFF_SHARE * force.mean(axis=0)
    off = binary_closing(off, np.ones((width, 1), bool))
    # the average blurs each end by half its width: widened back, the bridge starts where the tyre still pushed
    return binary_dilation(off, np.ones((2 * (width // 2) + 1, 1), bool)) if width > 1 else off


def bridged(drive: np.ndarray, off: np.ndarray, rate: float) -> np.ndarray:
    """``drive`` (samples x corners, m) with each stretch of ``off`` replaced by the flattest drive below it."""
    out = drive.copy()
    context = max(2, int(round(CONTEXT * rate)))
    for i in range(drive.shape[1]):
        stretches, count = label(off[:, i])
        for k in range(1, count + 1):
            inside = np.flatnonzero(stretches == k)
            window = np.arange(max(inside[0] - context, 0), min(inside[-1] + context + 1, drive.shape[0]))
            free = np.isin(window, inside)
            curvature = np.diff(np.eye(window.size), 2, axis=0)
            fixed = -curvature[:, ~free] @ drive[window[~free], i]
            solution = lsq_linear(curvature[:, free], fixed, bounds=(-np.inf, drive[window[free], i] + 1e-12))
            out[window[free], i] = solution.x
    return out
