"""Sensor causes judged as sensors: channels grouped as a DAQ groups them, parameters counted by group, and the
plausibility of where a fault sits.

A DAQ shifts or scales channels by module: the channels wired to one module share its clock (a delay) or its
range setting (a gain). Without the DAQ's wiring the natural modules are the whole system and each corner's
sensors. So a sensor cause's per-channel values are grouped: every channel alike is one group (one parameter);
otherwise, per corner, the channels that depart alike share one value (one parameter), and a channel that departs
alone is a group of its own. That is the count of parameters the cause pays for.

A fault confined to one physical quantity at every corner (the four body accelerometers delayed, and nothing
else) is not how a DAQ fails: the accelerometers of four corners sit on different modules, and what delays them
all alike is more likely the car, whose body responds late where a compliance is in series with the damper.
``confined_quantity`` names such a pattern; the diagnosis then prefers a car cause whose phase signature matches.

A channel's value (fitted on the fit data) counts only where the fault's own signature (``ChannelCause.response``: a
flat gain, a delay's phase line) describes how the held-out channel departs from the model's, per frequency, as well
as no fault does or better (its misfit over the misfit of no fault at most SIGNATURE_LEFT, ``described``), and only on
a model that names another cause. The truth car's wheels, each up to 3 % off its axle's unsprung mass and tyre rate,
bend the wheel accelerometers near wheel hop, where their power is: the time domain fits that as gains (1.043, 0.963
and 1.030 beside a Duffing spring), which over the band describe the channels hardly better than no fault, if at all
(the misfit ratio, mean over a cause's channels, 0.98-1.13 in the benchmarks' cases). A real gain describes its
channel better even where another cause's remainder shares it (a 10 % gain beside a smooth bump stop the bump stop
does not wholly explain: 0.94). Before any cause is named a structural cause's misfit bends every channel alike, and
the first round keeps each departing channel.

Written here: the grouping is bookkeeping over the channel names, no library does it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rig.causes import ChannelCause
from rig.diagnosis.rig_test.evidence import phase_curves, signature_misfit
from rig.io.channels import split_channel

AGREEMENT = 0.25        # channels share a value when they depart from neutral within this share of each other
SIGNATURE_LEFT = 1.0    # a channel's value counts where the fault's signature leaves at most this share of it
ALL_CHANNELS = "all channels"


@dataclass(frozen=True)
class ChannelGroups:
    """A sensor cause's channels in groups that share one value: label -> (channels, value)."""

    groups: dict[str, tuple[tuple[str, ...], float]]

    @property
    def n_params(self) -> int:
        return len(self.groups)

    def per_channel(self) -> dict[str, float]:
        """The value of every channel in a group (the vehicle file's section)."""
        return {name: value for names, value in self.groups.values() for name in names}

    def describe(self) -> str:
        return "; ".join(f"{label}: {', '.join(names)}" if len(names) > 1 else label
                         for label, (names, _) in self.groups.items())


def group_channels(cause: ChannelCause, values: dict[str, float]) -> ChannelGroups:
    """``values`` (every compared channel's value) grouped as a DAQ would group them (module docstring); channels
    whose value does not depart from neutral by the cause's ``min_effect`` are left out."""
    departing = {n: v for n, v in values.items() if abs(v - cause.neutral) >= cause.min_effect}
    if not departing:
        return ChannelGroups({})
    if len(departing) == len(values) and _alike(cause, list(values.values())):
        return ChannelGroups({ALL_CHANNELS: (tuple(values), float(np.mean(list(values.values()))))})
    groups: dict[str, tuple[tuple[str, ...], float]] = {}
    for corner in dict.fromkeys(split_channel(n)[0] for n in departing):
        names = [n for n in departing if split_channel(n)[0] == corner]
        if len(names) > 1 and _alike(cause, [departing[n] for n in names]):
            groups[corner] = (tuple(names), float(np.mean([departing[n] for n in names])))
        else:
            groups.update({n: ((n,), departing[n]) for n in names})
    return ChannelGroups(groups)


def described(cause: ChannelCause, values: dict[str, float], measured: np.ndarray, simulated: np.ndarray,
              rate: float, band: tuple[float, float]) -> dict[str, float]:
    """``values`` (channel -> value, in the columns' order of ``measured`` and ``simulated``, samples x channels) with
    each departing channel whose departure the fault's signature does not describe set to neutral (module
    docstring)."""
    names = list(values)
    departing = [i for i, n in enumerate(names) if abs(values[n] - cause.neutral) >= cause.min_effect]
    if not departing:
        return dict(values)
    curves = phase_curves(measured[:, departing], simulated[:, departing], [names[i] for i in departing], rate, band)
    kept = dict(values)
    for name, curve in curves.items():
        left = signature_misfit(curve, cause.response(values[name], curve.frequency))
        if left > SIGNATURE_LEFT * signature_misfit(curve, np.ones(curve.frequency.shape, complex)):
            kept[name] = cause.neutral
    return kept


def _alike(cause: ChannelCause, values: list[float]) -> bool:
    departures = np.array(values) - cause.neutral
    if np.any(np.sign(departures) != np.sign(departures[0])):
        return False
    spread = np.max(departures) - np.min(departures)
    return bool(spread <= max(AGREEMENT * np.max(np.abs(departures)), 0.5 * cause.min_effect))


def confined_quantity(channels: list[str] | tuple[str, ...], corners: tuple[str, ...]) -> str | None:
    """The physical quantity when the faulty ``channels`` are that one quantity at every corner and nothing else
    (implausible for a DAQ: module docstring); None otherwise."""
    quantities = {split_channel(n)[1] for n in channels}
    if len(quantities) != 1 or len(corners) < 2:
        return None
    quantity = next(iter(quantities))
    return quantity if {split_channel(n)[0] for n in channels} == set(corners) else None
