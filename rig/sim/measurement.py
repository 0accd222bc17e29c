"""The measurement chain of a vehicle file: the causes keyed by channel (rig/causes/: the sensor causes and
``input_gain``).

They describe the transducers, not the mechanics, so they are applied to the simulated channels after the run, as the
real chain applies them to the real motion (``apply_sensor_model``), and taken off a record's input channels before
the record drives a run (``true_inputs``: a post's displacement channel that records another factor of the motion).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from rig.causes import CAUSES
from rig.io.record import Record


def apply_sensor_model(channels: dict[str, np.ndarray], extensions: dict, rate: float) -> dict[str, np.ndarray]:
    """Channels as the vehicle file's sensors would report them (new dict; others pass unchanged)."""
    sensors = [(CAUSES[name], value) for name, value in extensions.items() if CAUSES[name].keyed_by_channel]
    unknown = sorted({n for _, value in sensors for n in value} - set(channels))
    if unknown:
        raise ValueError(f"[{'/'.join(c.name for c, _ in sensors)}] name channels the run does not have: "
                         f"{', '.join(unknown)}")
    out = dict(channels)
    for cause, value in sorted(sensors, key=lambda s: s[0].name):
        out = cause.measure(out, value, rate)
    return out


def true_inputs(record: Record, extensions: dict) -> Record:
    """``record`` with its input channels as the posts and actuators really moved, by the vehicle file's causes
    keyed by channel (the record itself where none applies)."""
    channels = record.channels
    for name, value in sorted(extensions.items()):
        if CAUSES[name].keyed_by_channel:
            channels = CAUSES[name].inputs(channels, value)
    if channels is record.channels:
        return record
    return dataclasses.replace(record, channels=channels)
