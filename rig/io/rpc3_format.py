"""MTS RPC III time-history files (``.rsp`` response, ``.drv`` drive, ``.tim``) through ``rpc3-file``.

Channel names are the file's ``DESC.CHAN_n`` strings; values are converted to SI from ``UNITS.CHAN_n``.
Record metadata travels in ``META.<key>`` header parameters.
"""

from __future__ import annotations

import os
import warnings
from pathlib import Path

import numpy as np
import rpc3
import rpc3.rpc3 as _rpc3_module

from rig.io.atomic import atomic_path
from rig.io.channel_map import UNWRAPPED, ChannelMap, plan_channels, plan_metadata
from rig.io.channels import split_channel
from rig.io.formats import RecordFormat
from rig.io.record import Record, RecordError
from rig.io.units import si_to

_rpc3_module.progressbar = False  # the library draws a tqdm bar on every read and write otherwise

_TIME_TYPES = {".drv": "DRIVE", ".rsp": "RESPONSE", ".tim": "RESPONSE", ".rpc": "RESPONSE"}
_META_PREFIX = "META."


def read_rpc3(path: str | os.PathLike, channel_map: ChannelMap | None = None) -> Record:
    """Read an RPC III file into a Record in SI units (unit names from the header), through ``channel_map``."""
    path = Path(path)
    try:
        with warnings.catch_warnings():
            # rpc3-file warns when the last data group is padded, which is normal for recorded files
            warnings.filterwarnings("ignore", message="Partially filled last group")
            channels, params = rpc3.read(str(path))
    except (OSError, ValueError) as err:
        raise RecordError(f"{path}: not a readable RPC III file ({err})") from None
    if not channels:
        raise RecordError(f"{path}: RPC III file has no channels")
    rates = {round(1.0 / ch.dt, 9) for ch in channels}
    if len(rates) != 1:
        raise RecordError(f"{path}: channels have different sample rates {sorted(rates)} Hz")
    by_name, units, places = {}, {}, {}
    for number, ch in enumerate(channels, start=1):
        name = ch.name.strip() or f"channel_{number}"
        if name in by_name:
            raise RecordError(f"{path}: duplicate channel '{name}' (DESC.CHAN_{number})")
        by_name[name], units[name], places[name] = ch, ch.unit, f"UNITS.CHAN_{number}"
    plan = plan_channels(path, units, channel_map, places)
    values = {c.name: c.apply(by_name[c.source].data) for c in plan.conversions}
    metadata = {k[len(_META_PREFIX):]: str(v) for k, v in params.items() if k.startswith(_META_PREFIX)}
    metadata.update(plan_metadata(plan, channel_map))
    return Record(rates.pop(), values, {c.name: c.unit for c in plan.conversions}, metadata,
                  start_time=float(channels[0].x0))


def write_rpc3(path: str | os.PathLike, record: Record, units: dict[str, str] | None = None,
               floating_point: bool = False) -> None:
    """Write ``record`` as RPC III, atomically.

    The default is the classic 16-bit integer format with a per-channel scale (resolution: peak/32752);
    ``floating_point`` writes 32-bit floats. ``.drv`` files are marked ``TIME_TYPE=DRIVE``. A wheel's angle is
    written modulo a turn, in [-pi, pi) (unwrapped, 16 bits would keep a minute's angle to a fifth of a radian);
    ``read_rpc3`` unwraps it.
    """
    path = Path(path)
    units = units or {}
    channels = []
    for name in record.names:
        if len(name) > 32:
            raise RecordError(f"channel name '{name}' is longer than the 32 characters RPC III allows")
        unit = units.get(name, record.units[name])
        values = record[name]
        if split_channel(name)[1] in UNWRAPPED:
            values = np.mod(values + np.pi, 2 * np.pi) - np.pi
        data = values * si_to(unit, record.units[name])
        channels.append(rpc3.Channel(name=name, unit=unit, dt=1.0 / record.rate, data=data, x0=record.start_time))
    extra = {"TIME_TYPE": _TIME_TYPES.get(path.suffix.lower(), "RESPONSE")}
    extra.update({f"{_META_PREFIX}{k}"[:32]: str(v)[:96] for k, v in record.metadata.items()})
    with atomic_path(path, suffix=".rsp") as tmp:
        rpc3.write(str(tmp), channels, datatype=float if floating_point else int, overwrite=True,
                   extra_params=extra)


def _read(path: Path, resample: bool, channel_map: ChannelMap | None) -> Record:
    return read_rpc3(path, channel_map)  # uniformly sampled by construction: nothing to resample


FORMAT = RecordFormat((".rsp", ".drv", ".tim", ".rpc", ".rpc3"), _read, "RPC III .rsp/.drv/.tim", write=write_rpc3,
                      order=20)
