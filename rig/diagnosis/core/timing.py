"""Where a diagnosis spends its time: the wall time of each step and of the fits inside it.

A ``StageClock`` times the diagnosis's steps one after another (integrity and split, force laws, recalibration,
first round, selection, verdict, the intervals of the reported fits) and, inside a step, each fit (a candidate's
screening, a joint fit, a refinement), which may run beside each other on several threads: the parts of a step can add
up to more than the step.
Each step and part is told to the diagnosis's ``progress`` callback as it starts.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass


@dataclass(frozen=True)
class StageTime:
    """The wall time (s) of one step of a diagnosis, or of one part of a step (``within`` names the step)."""

    stage: str
    seconds: float
    within: str | None = None


class StageClock:
    """Times the steps of a diagnosis and the parts inside them (module docstring); ``times`` holds them in the order
    they ended."""

    def __init__(self, progress: Callable[[str], None] | None = None):
        self.progress = progress or (lambda step: None)
        self.times: list[StageTime] = []
        self._lock = threading.Lock()
        self._step: str | None = None

    @contextmanager
    def step(self, name: str) -> Iterator[None]:
        """Time one step of the diagnosis (steps do not overlap)."""
        self._step = name
        with self._timed(name, None):
            yield
        self._step = None

    @contextmanager
    def part(self, name: str) -> Iterator[None]:
        """Time one part of the current step (parts may run beside each other); ``progress`` is told its name."""
        self.progress(name)
        with self._timed(name, self._step):
            yield

    @contextmanager
    def _timed(self, name: str, within: str | None) -> Iterator[None]:
        start = time.perf_counter()
        try:
            yield
        finally:
            seconds = time.perf_counter() - start
            with self._lock:
                self.times.append(StageTime(name, seconds, within))
