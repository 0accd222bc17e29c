"""The machine's cores left to the rig's rollouts: MuJoCo's profiler clock off while they run, BLAS on one thread
through a diagnosis.

- MuJoCo times the stages of its pipeline (``mjData.timer``) through its ``mjcb_time`` callback, and its Python
  bindings put a monotonic clock there when they load (``set_mjcb_time(None)`` puts it back). An RK4 step then reads
  the clock about a hundred times (each timed stage's start and end, in each of its four evaluations): 15-17 % of a
  car's step on ideal posts (``python benchmarks/replay.py``, its last line), states bit for bit the same. Nothing in
  the rig reads those timers. ``clock_off`` clears the callback while a rollout runs, as MuJoCo's C API documents it
  (no callback: no profiling), by writing the library's ``mjcb_time`` pointer through ctypes, since the bindings'
  setter cannot clear it; rollouts run on several threads at once, so the first to start clears it and the last to
  end puts back what was there. A thread of the same process stepping MuJoCo meanwhile steps as before; its timers
  may then read wrong, never its physics. Where the library cannot be found, nothing changes.
- OpenBLAS's threads wait for the next call by spinning, and on two cores that time is taken from the rollouts'
  threads: ``one_blas_thread`` holds BLAS to one thread (threadpoolctl) for a diagnosis, whose matrices are small.
Written by hand (``one_blas_thread`` excepted): no library switches MuJoCo's profiler off.
"""

from __future__ import annotations

import ctypes
import functools
import threading
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import TypeVar

import mujoco
from threadpoolctl import threadpool_limits

F = TypeVar("F", bound=Callable)


@functools.cache
def _time_callback() -> ctypes.c_void_p | None:
    """MuJoCo's ``mjcb_time`` pointer in the library the bindings loaded; None where it is not found."""
    folder = Path(mujoco.__file__).parent
    for library in sorted(folder.glob("*mujoco*.so*")) + sorted(folder.glob("*mujoco*.dylib")) + sorted(
            folder.glob("mujoco*.dll")):
        try:
            return ctypes.c_void_p.in_dll(ctypes.CDLL(str(library)), "mjcb_time")
        except (OSError, ValueError):
            continue
    return None


class _ClockHolder:
    """How many rollouts run with the clock off, and the callback to put back when the last one ends."""

    def __init__(self):
        self.lock, self.running, self.saved = threading.Lock(), 0, None


_holder = _ClockHolder()


@contextmanager
def clock_off() -> Iterator[None]:
    """MuJoCo's profiler clock off for the block (module docstring)."""
    callback = _time_callback()
    if callback is None:
        yield
        return
    with _holder.lock:
        if _holder.running == 0:
            _holder.saved, callback.value = callback.value, None
        _holder.running += 1
    try:
        yield
    finally:
        with _holder.lock:
            _holder.running -= 1
            if _holder.running == 0:
                callback.value = _holder.saved


def one_blas_thread(function: F) -> F:
    """``function`` run with BLAS held to one thread (module docstring)."""

    @functools.wraps(function)
    def held(*args, **kwargs):
        with threadpool_limits(limits=1, user_api="blas"):
            return function(*args, **kwargs)

    return held  # type: ignore[return-value]
