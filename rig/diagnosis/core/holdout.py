"""Which parts of a rig test a diagnosis fits and which it scores: chosen on content, not on position.

A record often holds rest (the posts still before and after a drive, e.g. the replay of an iterated drive with
seconds of rest at its end). Rest says nothing about a model, and a hold-out made mostly of rest would judge a
model on noise. So the excitation is measured first: the post displacement's RMS in a sliding window, against
the record's typical level. Rest at either end (at least ``MIN_REST_S``) is dropped, and the active span is
cut so that the held-out part holds ``share`` of its active time (rest inside the record not counted): both
parts carry excitation. The
held-out part is simulated from ``SETTLE_S`` before the cut (the model starts from rest, the real car was
moving), scoring only after it. With an explicit hold-out record, the two records are kept as they are, rest at
their ends aside.

Written here: no library finds rest in a rig test.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from rig.io.record import Record

REST_LEVEL = 0.1   # a window is at rest while its RMS post motion is below this share of the record's typical level
WINDOW_S = 0.5     # s: the sliding window of the excitation
MIN_REST_S = 1.0   # s: rest at an end shorter than this is kept
SETTLE_S = 3.0     # s: simulated before the held-out part so that the model's start transient dies away
HOLDOUT_SHARE = 1 / 3


@dataclass(frozen=True)
class Part:
    """A part of a record (s from its start): [start, end), simulated from ``simulated_from``."""

    start: float
    end: float
    simulated_from: float

    @property
    def seconds(self) -> float:
        return self.end - self.start


@dataclass
class Split:
    """The parts a diagnosis fits and scores, and the rest it dropped (s)."""

    fit: Part
    holdout: Part
    explicit: bool                                    # the hold-out is a record of its own
    dropped: list[tuple[str, float, float]] = field(default_factory=list)  # (which record, start, end) of rest

    def lines(self) -> list[str]:
        """What was used and dropped, in words."""
        held = ("the hold-out record" if self.explicit else
                f"{self.holdout.start:.1f}-{self.holdout.end:.1f} s of the measured record")
        lines = [f"fitted on {self.fit.start:.1f}-{self.fit.end:.1f} s of the measured record, scored on {held}"
                 + (f" (simulated from {self.holdout.simulated_from:.1f} s so that the model settles)"
                    if self.holdout.simulated_from < self.holdout.start else "")]
        lines += [f"rest dropped from the {which}: {start:.1f}-{end:.1f} s" for which, start, end in self.dropped]
        return lines

    def to_json(self) -> dict:
        return {"fit_s": [self.fit.start, self.fit.end], "holdout_s": [self.holdout.start, self.holdout.end],
                "explicit": self.explicit, "rest_dropped_s": [[w, a, b] for w, a, b in self.dropped]}


def excitation(record: Record) -> np.ndarray:
    """Per sample, the RMS post displacement (else the drive, else the road) over the corners in a sliding window
    about it (m); ones where the record has none of them."""
    quantity = next((q for q in ("actuator_disp", "drive", "road") if record.corners_with(q)), None)
    if quantity is None:
        return np.ones(record.n_samples)
    motion = record.quantity(quantity, record.corners_with(quantity))
    motion = motion - np.median(motion, axis=0)
    window = max(1, int(WINDOW_S * record.rate))
    power = np.convolve(np.mean(motion**2, axis=1), np.ones(window) / window, mode="same")
    return np.sqrt(power)


def moving(record: Record) -> np.ndarray:
    """Per sample, whether the posts move (the excitation above REST_LEVEL of the record's typical level)."""
    level = excitation(record)
    return level > REST_LEVEL * np.quantile(level, 0.75)


def active_span(record: Record) -> tuple[int, int]:
    """First and last+1 sample of the record without the rest at its ends (rest shorter than MIN_REST_S kept)."""
    moving_at = np.flatnonzero(moving(record))
    if moving_at.size == 0:
        return 0, record.n_samples
    shortest = int(MIN_REST_S * record.rate)
    start = moving_at[0] if moving_at[0] >= shortest else 0
    end = moving_at[-1] + 1 if record.n_samples - moving_at[-1] - 1 >= shortest else record.n_samples
    return int(start), int(end)


def choose_split(measured: Record, holdout: Record | None = None, share: float = HOLDOUT_SHARE) -> Split:
    """The fit and held-out parts (see the module docstring)."""
    rate = measured.rate
    start, end = active_span(measured)
    dropped = _rest("measured record", measured, start, end)
    if holdout is not None:
        h_start, h_end = active_span(holdout)
        dropped += _rest("hold-out record", holdout, h_start, h_end)
        return Split(Part(start / rate, end / rate, start / rate),
                     Part(h_start / holdout.rate, h_end / holdout.rate, h_start / holdout.rate), True, dropped)
    active = np.cumsum(moving(measured)[start:end])
    cut = start + int(np.searchsorted(active, (1 - share) * active[-1]))
    settle_from = max(start, cut - int(SETTLE_S * rate))
    return Split(Part(start / rate, cut / rate, start / rate), Part(cut / rate, end / rate, settle_from / rate),
                 False, dropped)


def _rest(which: str, record: Record, start: int, end: int) -> list[tuple[str, float, float]]:
    rate = record.rate
    return ([(which, 0.0, start / rate)] if start > 0 else []) + \
        ([(which, end / rate, record.n_samples / rate)] if end < record.n_samples else [])


def split_holdout(record: Record, share: float = HOLDOUT_SHARE) -> tuple[Record, Record]:
    """The fit part of a record and its held-out part (chosen on content), as records of their own."""
    split = choose_split(record, share=share)
    fit, _ = part_of(record, split.fit)
    held, _ = part_of(record, Part(split.holdout.start, split.holdout.end, split.holdout.start))
    return fit, held


def part_of(record: Record, part: Part) -> tuple[Record, int]:
    """The samples of ``record`` from ``part.simulated_from`` to its end, the posts and drives starting from zero
    like the model's, and how many samples settle the model before the part begins."""
    first, begin, last = (int(round(t * record.rate)) for t in (part.simulated_from, part.start, part.end))
    cut = slice(first, last)
    channels = {n: v[cut] - (v[cut][0] if n.endswith(("/drive", "/actuator_disp")) else 0.0)
                for n, v in record.channels.items()}
    return Record(record.rate, channels, dict(record.units), dict(record.metadata)), begin - first
