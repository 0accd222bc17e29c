"""Timing for the benchmark scripts (``from timing import best_of``; they run as ``python benchmarks/<name>.py``)."""

from __future__ import annotations

import time
from collections.abc import Callable


def best_of(function: Callable[[], object], repeats: int = 3, clock: Callable[[], float] = time.perf_counter) -> float:
    """The shortest of ``repeats`` timings of ``function()`` (s, on ``clock``): other work on the machine only ever
    adds time, so the shortest is the closest to the work itself."""
    times = []
    for _ in range(repeats):
        start = clock()
        function()
        times.append(clock() - start)
    return min(times)
