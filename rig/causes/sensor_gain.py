"""``sensor_gain``: a response channel's calibration factor is off (measured = factor x true); a negative factor is
a reversed polarity (an accelerometer mounted upside down, a channel wired the wrong way round).

    [sensor_gain]
    "FL/sprung_acc" = 1.06
    "RR/unsprung_acc" = -1.0
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
    signed = True
    typical = 0.1
    neutral = 1.0
    min_effect = MIN_ERROR
    meaning = "a channel's calibration factor is off"
    signature = "one channel's residual is proportional to the channel itself"
    separated_by = "a calibration of the channel against a reference (a static tilt through 1 g, a shaker)"

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
