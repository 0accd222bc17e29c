"""A throwaway record file format, one module and nothing else (tests/test_registries.py registers it): NumPy's
``.npz`` archive, a float array per channel, its unit and the rate beside it."""

import json

import numpy as np

from rig.io.atomic import atomic_path
from rig.io.formats import RecordFormat
from rig.io.record import Record, RecordError


def read_npz(path, resample=False, channel_map=None):
    with np.load(path) as archive:
        if "rate" not in archive or "units" not in archive:
            raise RecordError(f"{path}: an .npz record needs 'rate' and 'units'")
        units = json.loads(str(archive["units"]))
        channels = {name: archive[name].astype(float) for name in units}
        return Record(rate=float(archive["rate"]), channels=channels, units=units)


def write_npz(path, record, units=None):
    with atomic_path(path, suffix=".npz") as tmp:
        np.savez(tmp, rate=record.rate, units=json.dumps(record.units), **record.channels)


FORMAT = RecordFormat(suffixes=(".npz",), read=read_npz, write=write_npz, label="NumPy .npz")
