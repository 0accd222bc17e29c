"""``sensor_gain``: a channel's calibration factor is off (measured = factor x true).

    [sensor_gain]
    "FL/sprung_acc" = 1.06
"""

from __future__ import annotations

import numpy as np

from rig.causes._base import ChannelCause, with_extension
from rig.io.channels import channel
from rig.signal.alignment import channel_gains

MIN_ERROR = 0.03  # relative calibration error worth naming


class _SensorGain(ChannelCause):
    name = "sensor_gain"
    unit = "-"
    bounds = (0.2, 5.0)
    typical = 0.1
    neutral = 1.0
    min_effect = MIN_ERROR
    meaning = "a channel's calibration factor is off"
    signature = "one channel's residual is proportional to the channel itself"

    def measure(self, channels, value, rate):
        return {**channels, **{name: factor * channels[name] for name, factor in value.items()}}

    def channel_values(self, measured, simulated, rate):
        return channel_gains(measured, simulated)

    def response(self, value, frequency):
        return np.full(np.shape(frequency), value, complex)

    def hidden(self, truth, rng):
        name = channel(rng.choice(truth.corners), rng.choice(["sprung_acc", "unsprung_acc"]))
        return with_extension(truth, self.name, {name: float(rng.choice([-1, 1]) * rng.uniform(0.08, 0.15) + 1)})


CAUSE = _SensorGain()
