"""The measurement chain of a vehicle file: the sensor causes (rig/causes/, subsystem ``sensor``).

They describe the transducers, not the mechanics, so they are applied to the simulated channels after
the run, as the real chain applies them to the real motion.
"""

from __future__ import annotations

import numpy as np

from rig.causes import CAUSES


def apply_sensor_model(channels: dict[str, np.ndarray], extensions: dict, rate: float) -> dict[str, np.ndarray]:
    """Channels as the vehicle file's sensors would report them (new dict; others pass unchanged)."""
    sensors = [(CAUSES[name], value) for name, value in extensions.items() if CAUSES[name].subsystem == "sensor"]
    unknown = sorted({n for _, value in sensors for n in value} - set(channels))
    if unknown:
        raise ValueError(f"[{'/'.join(c.name for c, _ in sensors)}] name channels the run does not have: "
                         f"{', '.join(unknown)}")
    out = dict(channels)
    for cause, value in sorted(sensors, key=lambda s: s[0].name):
        out = cause.measure(out, value, rate)
    return out
