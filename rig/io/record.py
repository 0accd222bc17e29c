"""Test records: uniformly sampled, named channels in SI units, with metadata (contract: docs/contracts.md)."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from rig.errors import RigError
from rig.io.channels import CORNERS, QUANTITY_UNITS, channel, sort_corners, split_channel


class RecordError(RigError):
    """A record (or a file holding one) that breaks the record contract; the message names the place."""


@dataclass
class Record:
    """Named channels sampled at ``rate`` Hz from ``start_time`` s.

    ``channels`` maps contract names (``FL/sprung_acc``) to 1-D float arrays in SI units; ``units`` gives
    each channel's SI unit; ``metadata`` holds the ``# key: value`` lines of a CSV (``vehicle``, ``test``...).
    """

    rate: float
    channels: dict[str, np.ndarray]
    units: dict[str, str] = field(default_factory=dict)
    metadata: dict[str, str] = field(default_factory=dict)
    start_time: float = 0.0

    def __post_init__(self) -> None:
        if not np.isfinite(self.rate) or self.rate <= 0:
            raise RecordError(f"sample rate must be a positive number of Hz, got {self.rate}")
        lengths = set()
        for name, values in list(self.channels.items()):
            values = np.asarray(values, dtype=float)
            if values.ndim != 1:
                raise RecordError(f"channel '{name}' must be one-dimensional, got shape {values.shape}")
            bad = np.flatnonzero(~np.isfinite(values))
            if bad.size:
                raise RecordError(f"channel '{name}' has a non-finite value ({values[bad[0]]}) at sample {bad[0]}")
            self.channels[name] = values
            lengths.add(values.size)
            if name not in self.units:
                self.units[name] = QUANTITY_UNITS.get(split_channel(name)[1], "")
        if len(lengths) > 1:
            raise RecordError(f"channels have different lengths: {sorted(lengths)}")

    @property
    def names(self) -> list[str]:
        return list(self.channels)

    @property
    def n_samples(self) -> int:
        return next(iter(self.channels.values())).size if self.channels else 0

    @property
    def duration(self) -> float:
        """Length of the record in s (number of samples over the rate)."""
        return self.n_samples / self.rate

    @property
    def time(self) -> np.ndarray:
        """Sample times in s."""
        return self.start_time + np.arange(self.n_samples) / self.rate

    def __getitem__(self, name: str) -> np.ndarray:
        try:
            return self.channels[name]
        except KeyError:
            raise KeyError(f"record has no channel '{name}' (it has: {', '.join(self.names)})") from None

    def __contains__(self, name: str) -> bool:
        return name in self.channels

    def corners_with(self, quantity: str) -> list[str]:
        """Corners (of any layout), in contract order, that have a ``<corner>/<quantity>`` channel."""
        return sort_corners(c for c, q in map(split_channel, self.channels) if q == quantity)

    def quantity(self, quantity: str, corners: tuple[str, ...] | list[str] = CORNERS) -> np.ndarray:
        """Samples × corners matrix of one quantity; a missing corner is an error that names it."""
        missing = [c for c in corners if channel(c, quantity) not in self.channels]
        if missing:
            raise RecordError(
                f"record has no '{quantity}' channel for corner(s) {', '.join(missing)} "
                f"(expected {', '.join(channel(c, quantity) for c in missing)})"
            )
        return np.column_stack([self.channels[channel(c, quantity)] for c in corners])

    def select(self, names: list[str]) -> Record:
        """A record with only the named channels (same rate and metadata)."""
        return Record(self.rate, {n: self[n] for n in names}, {n: self.units[n] for n in names},
                      dict(self.metadata), self.start_time)
