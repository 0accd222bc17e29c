"""What a drive iteration matches: the time history (RMS error), its peaks, or its fatigue damage.

A severe target is often out of reach as a time history (a tyre that must leave its post, a post at its
limits); a durability test then asks for the peaks or the damage the target holds. The user chooses:

- ``rms``: every channel's RMS error (% of the target's RMS), as Nurhadiyanto's §4.1.1 iterates;
- ``peak``: every channel's peak error (rig/signal/metrics.py ``peak_error_pct``). The update is the time
  history's: weighting the error towards the target's peaks (1 + (target / max |target|)^8) was measured to slow
  the peaks' convergence on proton_x_nonlinear (worst peak error after six plays 5.6 % against 0.85 %): the
  peaks lie where the car is least linear (bump stops), and more step there overshoots;
- ``damage``: every channel's rainflow pseudo-damage ratio (exponent 6, Forsén 1999), its error
  100 (max(r, 1 / r) - 1) %, so 25 % is the 0.8-1.25 band. Where part of the target is out of reach
  (controllers/reachability.py) and the rest of the record is within the default RMS tolerance, the update aims
  at the target scaled per channel by a factor that each play multiplies by r^(-1/6) (damage grows with the
  sixth power of the cycles' ranges), within 1 / MAX_SCALE to MAX_SCALE: the rest is driven harder, so that the
  damage matches. Where all of it is in reach, the time history converges and its damage with it; rescaling
  then would only disturb the first plays, whose damage says more about the waveform's error than about the
  amplitude.

Each criterion has its own default tolerance (``DEFAULT_TOLERANCE``, %).
"""

from __future__ import annotations

import numpy as np

from rig.signal.metrics import DAMAGE_EXPONENT

MATCHES = ("rms", "peak", "damage")
DEFAULT_TOLERANCE = {"rms": 3.0, "peak": 5.0, "damage": 25.0}
MAX_SCALE = 1.25
_KEYS = {"rms": "rms_error_pct", "peak": "peak_error_pct"}


def damage_error_pct(ratio: float) -> float:
    """A damage ratio's distance from one, in %: 100 (max(r, 1 / r) - 1); infinite for a ratio of zero."""
    return float(100 * (max(ratio, 1 / ratio) - 1)) if ratio > 0 else float("inf")


def channel_errors(metrics: dict[str, dict[str, float]], match: str) -> dict[str, float]:
    """Each channel's error (%) under the criterion ``match``."""
    if match == "damage":
        return {name: damage_error_pct(m.damage_ratio) for name, m in metrics.items()}
    return {name: float(getattr(m, _KEYS[match])) for name, m in metrics.items()}


def rescaled(scale: np.ndarray, metrics: dict[str, dict[str, float]], match: str, out_of_reach: bool) -> np.ndarray:
    """The next per-channel scale of the target the update aims at: unchanged but for damage matching with part
    of the target out of reach."""
    if match != "damage" or not out_of_reach:
        return scale
    ratios = np.array([max(m.damage_ratio, 1e-12) for m in metrics.values()])
    return np.clip(scale * ratios ** (-1 / DAMAGE_EXPONENT), 1 / MAX_SCALE, MAX_SCALE)
