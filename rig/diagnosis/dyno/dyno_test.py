"""A damper dynamometer test as data: the records' rod displacement, force and temperature, checked, with the
rod's velocity and the force's rate derived (docs/contracts.md: dyno records).

Channels: ``damper/displacement`` (m, extension positive), ``damper/force`` (N, positive resisting extension)
and, optionally, ``damper/temperature`` (degC). Each record (a sine or triangle test at one speed, or a sequence
of them) is differentiated on its own (rig/signal/differentiate.py): the velocity from the displacement, and the
force's rate (for a damper in series with a stiffness) from the force, each with the window its own spectrum
sets (a force through a compliance turns faster than the displacement at a triangle's reversals); the
displacement's lines count as the rod's motion only where the force follows them (a transducer's electrical pickup
does not move the rod). A displacement
whose file gives no unit is read in m only where that is plausible for a damper on a dynamometer (a stroke under
``MAX_STROKE`` and a speed under ``MAX_SPEED``); anything else (a displacement in mm, say) is refused, naming the
channel.

A damper absorbs work: with the contract's signs its force times its velocity is positive on average. Records where
it is clearly negative (the force's correlation with the velocity below -REVERSED_CORRELATION) have one channel's
polarity reversed: the force is taken reversed and the test says so (``reversed_force``), naming both channels,
since the records cannot tell which of the two is wired the wrong way round (a static push on the rod, read on both,
would).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from rig.io.record import Record, RecordError
from rig.signal.differentiate import rate_of

DISPLACEMENT = "damper/displacement"
FORCE = "damper/force"
TEMPERATURE = "damper/temperature"
MAX_STROKE = 1.0   # m, peak to peak: no damper dynamometer strokes further
MAX_SPEED = 10.0   # m/s: high-speed dynamometers reach a few m/s
MIN_SAMPLES = 32
REVERSED_CORRELATION = 0.2  # a damper's force against its velocity correlates by 0.5-0.95 (friction and gas less)


class DynoError(RecordError):
    """A dynamometer record that cannot be used; the message names the record and the channel."""


@dataclass(frozen=True)
class DynoRun:
    """One record of a dyno test (SI: s, m, m/s, N, N/s, degC); ``window``: the differentiator's (samples)."""

    name: str
    rate: float
    time: np.ndarray
    displacement: np.ndarray
    velocity: np.ndarray
    force: np.ndarray
    force_rate: np.ndarray
    temperature: np.ndarray | None
    window: int

    @property
    def stroke(self) -> float:
        """Peak-to-peak displacement (m)."""
        return float(np.ptp(self.displacement))

    @property
    def peak_velocity(self) -> float:
        return float(np.max(np.abs(self.velocity)))


@dataclass(frozen=True)
class DynoTest:
    """The runs of a dyno test and what was assumed in reading them (``notes``)."""

    runs: tuple[DynoRun, ...]
    notes: tuple[str, ...] = ()
    reversed_force: bool = False  # the records' force and displacement had opposite polarity: the force was reversed

    def joined(self, quantity: str) -> np.ndarray | None:
        """One quantity of every run, end to end; None for temperature unless every run has it."""
        parts = [getattr(run, quantity) for run in self.runs]
        return None if any(p is None for p in parts) else np.concatenate(parts)

    @property
    def has_temperature(self) -> bool:
        return all(run.temperature is not None for run in self.runs)


def dyno_test(records: list[tuple[str, Record]]) -> DynoTest:
    """The dyno test of ``(name, record)`` pairs, each checked: displacement and force present, a displacement
    without a unit plausible in m, enough samples and some motion. Refusals are DynoError, in one line."""
    if not records:
        raise DynoError("a dyno test needs at least one record")
    runs, notes = [], []
    for name, record in records:
        run, note = _run(name, record)
        runs.append(run)
        notes.extend(note)
    with_temperature = [run.name for run in runs if run.temperature is not None]
    if with_temperature and len(with_temperature) < len(runs):
        notes.append(f"only {', '.join(with_temperature)} carry {TEMPERATURE}: the temperature is not used")
    correlation = _work_correlation(runs)
    if correlation < -REVERSED_CORRELATION:
        runs = [dataclasses.replace(run, force=-run.force, force_rate=-run.force_rate) for run in runs]
        notes.append(f"'{FORCE}' and '{DISPLACEMENT}' have opposite polarity: the force does work on the damper "
                     f"(its correlation with the velocity is {correlation:.2f}), so it was taken reversed; the records "
                     f"cannot tell which channel is wired the wrong way round (a static push on the rod, read on both, "
                     f"would): mend it, or give the channel map's entry scale = -1")
    return DynoTest(tuple(runs), tuple(notes), correlation < -REVERSED_CORRELATION)


def _work_correlation(runs: list[DynoRun]) -> float:
    """The correlation of the force (about its mean: a gas preload does no work over a cycle) with the velocity, over
    every run: positive where the damper absorbs work, as a damper does."""
    force = np.concatenate([run.force - np.mean(run.force) for run in runs])
    velocity = np.concatenate([run.velocity for run in runs])
    return float(force @ velocity / np.sqrt((force @ force) * (velocity @ velocity)))


def _run(name: str, record: Record) -> tuple[DynoRun, list[str]]:
    missing = [c for c in (DISPLACEMENT, FORCE) if c not in record]
    if missing:
        raise DynoError(f"{name}: no {' or '.join(repr(c) for c in missing)} channel (it has: "
                        f"{', '.join(record.names) or 'none'}); a dyno record needs time, {DISPLACEMENT} and "
                        f"{FORCE} (name the file's channels with --map)")
    if record.n_samples < MIN_SAMPLES:
        raise DynoError(f"{name}: {record.n_samples} samples; a dyno record needs at least {MIN_SAMPLES}")
    displacement, force = record[DISPLACEMENT], record[FORCE]
    if np.ptp(force) == 0.0:
        raise DynoError(f"{name}: channel '{FORCE}' does not change (a load cell not connected?)")
    velocity = rate_of(displacement, record.rate, witness=force)  # the rod's motion is what the force follows
    notes = _check_displacement(name, record, displacement, velocity.values)
    force_rate = rate_of(force, record.rate).values
    temperature = record.channels.get(TEMPERATURE)
    run = DynoRun(name, record.rate, record.time, displacement, velocity.values, force, force_rate, temperature,
                  velocity.window)
    return run, notes


def _check_displacement(name: str, record: Record, displacement: np.ndarray, velocity: np.ndarray) -> list[str]:
    """Refuse a displacement that does not move, or that has no unit and is implausible in m; say what was
    assumed where it has no unit and is plausible."""
    unit = record.units.get(DISPLACEMENT, "")
    stroke, speed = float(np.ptp(displacement)), float(np.max(np.abs(velocity)))
    if unit not in ("", "m"):
        raise DynoError(f"{name}: channel '{DISPLACEMENT}' is in {unit}, not a length")
    if stroke == 0.0:
        raise DynoError(f"{name}: channel '{DISPLACEMENT}' does not move")
    if unit:
        return []
    if stroke > MAX_STROKE or speed > MAX_SPEED:
        raise DynoError(f"{name}: channel '{DISPLACEMENT}' has no unit, and read in m it strokes {stroke:.4g} m at "
                        f"up to {speed:.4g} m/s: not a damper on a dynamometer (under {MAX_STROKE:g} m, "
                        f"{MAX_SPEED:g} m/s); give its unit in the channel map (e.g. unit = \"mm\")")
    return [f"{name}: '{DISPLACEMENT}' has no unit; read in m (stroke {stroke * 1e3:.1f} mm, up to "
            f"{speed:.3g} m/s)"]
