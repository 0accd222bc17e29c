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

Written here: the grouping is bookkeeping over the channel names, no library does it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rig.causes import ChannelCause
from rig.io.channels import split_channel

AGREEMENT = 0.25        # channels share a value when they depart from neutral within this share of each other
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
