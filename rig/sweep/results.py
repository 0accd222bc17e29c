"""A finished sweep as a table, and what is computed from it: the Pareto front, the PSD scatter band."""

from __future__ import annotations

import csv
import os
from dataclasses import dataclass

import numpy as np

from rig.io.atomic import atomic_path
from rig.io.channels import QUANTITY_UNITS, split_channel
from rig.sweep.design import SPEED, Design
from rig.vehicle.vehicle_file import key_unit

#: percentiles of the scatter band
BAND_PERCENTILES = (5.0, 50.0, 95.0)
#: units of the ride metrics and the speed
UNITS = {"a_w": "m/s^2", "tyre_load_rms": "-", "travel_rms": "m", "power_w": "W", SPEED: "m/s"}


def column_unit(name: str) -> str:
    """The unit of a results column: a metric's, a vehicle-file key's, or a channel's RMS (``FL/susp_travel rms``)."""
    if name in UNITS:
        return UNITS[name]
    if name.endswith(" rms"):
        return QUANTITY_UNITS.get(split_channel(name.removesuffix(" rms"))[1], "")
    return key_unit(name)


@dataclass(frozen=True)
class PsdBand:
    """Per channel, the 5th, 50th and 95th percentile over the points of its PSD (SI^2/Hz) at each frequency."""

    channels: tuple[str, ...]
    frequency: np.ndarray  # Hz
    low: np.ndarray        # (channels, frequencies)
    median: np.ndarray
    high: np.ndarray


@dataclass(frozen=True)
class SweepResult:
    """One row per design point: the key values and the metrics (``metrics[i, j]`` of ``metric_names[j]``)."""

    design: Design
    metric_names: tuple[str, ...]
    metrics: np.ndarray
    psd_band: PsdBand | None = None
    chunks_run: int = 0      # chunks simulated by this call
    chunks_reused: int = 0   # chunks found finished (--resume)

    def column(self, name: str) -> np.ndarray:
        if name in self.design.keys:
            return self.design.values[:, self.design.keys.index(name)]
        return self.metrics[:, self.metric_names.index(name)]

    @property
    def columns(self) -> list[str]:
        return ["point", *self.design.keys, *self.metric_names]

    def rows(self) -> np.ndarray:
        """(points, columns) in the order of ``columns``."""
        n = self.design.n_points
        return np.column_stack([np.arange(n), self.design.values, self.metrics])


def pareto_mask(first: np.ndarray, second: np.ndarray) -> np.ndarray:
    """True for the points no other point beats in both (smaller is better in each, e.g. a_w and tyre load)."""
    first, second = np.asarray(first, float), np.asarray(second, float)
    better_eq = (first[None, :] <= first[:, None]) & (second[None, :] <= second[:, None])
    strictly = (first[None, :] < first[:, None]) | (second[None, :] < second[:, None])
    return ~np.any(better_eq & strictly, axis=1)


def psd_band(channels: tuple[str, ...], frequency: np.ndarray, psd: np.ndarray) -> PsdBand:
    """The scatter band of PSDs (points, channels, frequencies) over the points."""
    low, median, high = np.percentile(psd, BAND_PERCENTILES, axis=0)
    return PsdBand(channels, frequency, low, median, high)


def band_coverage(band: PsdBand, measured: dict[str, tuple[np.ndarray, np.ndarray]]) -> dict[str, float]:
    """Per channel of ``measured`` (name -> frequency in Hz, PSD) in the band: the share of the band's frequencies
    at which the measured PSD (interpolated onto them) lies inside the simulated 5-95 % band."""
    shares = {}
    for name, (frequency, psd) in measured.items():
        c = band.channels.index(name)
        level = np.interp(band.frequency, frequency, psd)
        shares[name] = float(np.mean((level >= band.low[c]) & (level <= band.high[c])))
    return shares


def write_table(result: SweepResult, path: str | os.PathLike) -> None:
    """``results.csv``: a header of column names with their units (``front.damping [N s/m]``, as record CSVs
    have them), then one row per point; floats as Python writes them (exact)."""
    with atomic_path(path) as tmp, open(tmp, "w", newline="", encoding="utf-8") as file:
        writer = csv.writer(file)
        writer.writerow([name if name == "point" else f"{name} [{column_unit(name)}]" for name in result.columns])
        for i, row in enumerate(result.rows()):
            writer.writerow([i, *(repr(float(v)) for v in row[1:])])


def write_parquet(result: SweepResult, path: str | os.PathLike) -> bool:
    """The same table as Parquet when pyarrow is installed; False (nothing written) without it."""
    try:
        import pyarrow as pa
        import pyarrow.parquet as pq
    except ImportError:
        return False
    rows = result.rows()
    table = pa.table({name: (rows[:, j].astype(np.int64) if j == 0 else rows[:, j])
                      for j, name in enumerate(result.columns)})
    with atomic_path(path) as tmp:
        pq.write_table(table, tmp)
    return True
