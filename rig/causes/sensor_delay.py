"""``sensor_delay``: a channel (group) is time-shifted; the measured channel lags the truth by ``s``.

    [sensor_delay]
    "RR/unsprung_acc" = 0.004

The shift is fractional (rig/signal/alignment.py).
"""

from __future__ import annotations

import numpy as np

from rig.causes._base import ChannelCause, with_extension
from rig.io.channels import channel
from rig.signal.alignment import channel_delays, delayed

MIN_DELAY = 0.001   # s worth naming


class _SensorDelay(ChannelCause):
    name = "sensor_delay"
    unit = "s"
    bounds = (-0.5, 0.5)
    typical = 0.005
    neutral = 0.0
    min_effect = MIN_DELAY
    meaning = "a channel (group) is time-shifted"
    signature = "one channel's residual is its own derivative: a phase growing with frequency"

    def measure(self, channels, value, rate):
        return {**channels, **{name: delayed(channels[name], delay * rate) for name, delay in value.items()}}

    def channel_values(self, measured, simulated, rate):
        return channel_delays(measured, simulated, rate)

    def response(self, value, frequency):
        return np.exp(-2j * np.pi * np.asarray(frequency) * value)

    def hidden(self, truth, rng):
        corner = rng.choice(truth.corners)
        delay = rng.uniform(0.003, 0.008)
        return with_extension(truth, self.name, {channel(corner, q): delay for q in ("sprung_acc", "unsprung_acc")})


CAUSE = _SensorDelay()
