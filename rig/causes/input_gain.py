"""``input_gain``: an input channel's calibration factor is off, or its polarity is reversed: the record says
``factor`` times what the post did (recorded = factor x true; a negative factor: the channel's sign is reversed).

    [input_gain]
    "FL/actuator_disp" = -1.0   # the front-left post's displacement channel is wired the wrong way round

The car feels the true motion, so a record that drives the model is first brought back to it (``inputs``: true =
recorded / factor), while a run's own ``actuator_disp`` is reported as the channel records it (``measure``). A
polarity is found from the records before any fit (rig/diagnosis/rig_test/input_chain.py: the measured responses
regressed on
each input's own response), not as a gain bounded above zero. A fault of the actuator force between body and wheel
is ``force_constant_error``'s; a delay of an input against the responses is the responses' ``sensor_delay`` seen
from the other side (the records cannot tell the two apart).
"""

from __future__ import annotations

import numpy as np

from rig.causes._base import Cause, FitParameter, ParameterSpec, refusal, refuse_factor, with_extension
from rig.io.channels import channel, split_channel

QUANTITIES = ("actuator_disp",)  # the input channels whose calibration this cause holds
MIN_ERROR = 0.1   # a factor this far from 1 (relative) is worth fitting: the data sheet's errors move the chain's gains
TYPICAL = 0.05    # relative size of a factor's error, for fitting


class _InputGain(Cause):
    name = "input_gain"
    subsystem = "car"  # it changes what the car feels: fitted by simulation, as the car causes are
    keyed_by_channel = True
    input_quantities = QUANTITIES
    meaning = "an input channel's calibration factor is off or its polarity reversed (a post's displacement)"
    signature = "every response to one post is scaled by one factor (negative: reversed), those to the others are not"
    separated_by = "a static step of the post by a known height, read on its channel (or a dial gauge on its pan)"

    def parse(self, section, where, axles):
        if not isinstance(section, dict) or not section:
            raise ValueError(f"{where}: [{self.name}] must hold \"<corner>/actuator_disp\" = factor")
        for name, factor in section.items():
            if split_channel(name)[1] not in QUANTITIES:
                raise ValueError(f"{where}: [{self.name}] '{name}' is not an input channel ({', '.join(QUANTITIES)})")
            refuse_factor(factor, f"{where}: [{self.name}] '{name}'")
        return {name: float(factor) for name, factor in section.items()}

    def to_table(self, value):
        return dict(value)

    def parameters(self):
        return [ParameterSpec('"<corner>/actuator_disp"', "-", -5.0, 5.0,
                              "recorded over true; |factor| 0.2..5, negative: polarity reversed")]

    def implausible(self, vehicle):
        return refusal(lambda: self.parse(vehicle.extensions[self.name], vehicle.source, ()))

    def inputs(self, channels, value):
        return {**channels, **{name: channels[name] / factor for name, factor in value.items() if name in channels}}

    def measure(self, channels, value, rate):
        return {**channels, **{name: factor * channels[name] for name, factor in value.items() if name in channels}}

    def fit_parameters(self, vehicle, hints=None):
        """A factor for each post whose gain the input chain found off by MIN_ERROR or more, started there and
        bounded on its side of zero (hints ``input_gains``: channel -> gain)."""
        gains = (hints or {}).get("input_gains", {})
        return [signed_factor(name, gain, self.setter(name)) for name, gain in gains.items()
                if split_channel(name)[1] in QUANTITIES and abs(gain - 1) >= MIN_ERROR]

    def setter(self, name):
        def apply(vehicle, factor):
            return with_extension(vehicle, self.name, {**vehicle.extensions.get(self.name, {}), name: float(factor)})
        return apply

    def hidden(self, truth, rng):
        corner = rng.choice(truth.corners)
        factor = -1.0 if rng.random() < 0.5 else float(rng.choice([-1, 1]) * rng.uniform(0.2, 0.35) + 1)
        return with_extension(truth, self.name, {channel(corner, "actuator_disp"): factor})


def signed_factor(name: str, start: float, apply, typical: float = TYPICAL) -> FitParameter:
    """A fitted factor started at ``start`` and bounded on its side of zero (|factor| 0.2..5): a polarity found from
    the records stays found."""
    low, high = (0.2, 5.0) if start > 0 else (-5.0, -0.2)
    return FitParameter(name, float(np.clip(start, low, high)), low, high, apply, typical=typical * abs(start))


CAUSE = _InputGain()
