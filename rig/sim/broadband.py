"""A broadband post drive: band-limited random commands per corner, faded in and out (the demo's drive, and a
ready excitation for replays, identification and tests)."""

from __future__ import annotations

from rig.io.channels import channel
from rig.io.record import Record
from rig.signal.filters import band_limited_noise

BROADBAND_RATE = 512.0      # Hz
BROADBAND_BAND = (0.5, 30)  # Hz
BROADBAND_RMS = 0.003       # m per post


def broadband_drive(corners: tuple[str, ...] | list[str], duration: float = 20.0, seed: int = 2) -> Record:
    """Band-limited random drives (0.5-30 Hz, 3 mm RMS per post) at 512 Hz for ``corners``, ``duration`` s."""
    values = band_limited_noise(duration, BROADBAND_RATE, BROADBAND_BAND, BROADBAND_RMS, len(corners), seed)
    channels = {channel(c, "drive"): values[:, i] for i, c in enumerate(corners)}
    return Record(BROADBAND_RATE, channels, metadata={"test": "rig", "signal": "band-limited random 0.5-30 Hz"})
