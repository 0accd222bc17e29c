"""Chunks of a sweep as Ray tasks, on this machine or a cluster (optional extra ``[scale]``: ``ray>=2.9``).

Each task evaluates one chunk, still batched in C (``threads`` rollout threads, and as many CPUs reserved);
the case goes to the object store once. Finished chunks come back to this process as they finish, which
writes them (rig/sweep/run.py), so workers need no shared file system. A task whose worker dies (killed, out
of memory, node lost) is run again by Ray (``max_retries``); a task that raises is not: its error is raised here.
Workers import this package: on a cluster, install it on every node.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import replace

from rig.sweep.design import SweepError
from rig.sweep.evaluate import ChunkResult, SweepCase, evaluate_chunk
from rig.sweep.run import Chunk, ChunkFunction

INSTALL_HINT = "install it with: pip install 'virtual-four-poster[scale]' (or pip install 'ray>=2.9')"


def import_ray():
    """The ray module, or SweepError saying how to install it."""
    try:
        import ray
    except ImportError:
        raise SweepError(f"the Ray engine needs Ray, which is not installed; {INSTALL_HINT}") from None
    return ray


class RayEngine:
    """Chunks as Ray tasks. ``address``: an existing cluster ('auto' or 'ray://host:10001'); None starts a local
    Ray with ``num_cpus`` (default: all), shut down when the sweep ends. A Ray already started is used as is."""

    def __init__(self, address: str | None = None, num_cpus: int | None = None, threads: int = 1,
                 max_retries: int = 3, function: ChunkFunction = evaluate_chunk):
        self.ray = import_ray()
        self.address, self.num_cpus, self.threads = address, num_cpus, threads
        self.max_retries, self.function = max_retries, function

    def run(self, case: SweepCase, keys: tuple[str, ...], chunks: list[Chunk]) -> Iterator[tuple[int, ChunkResult]]:
        ray = self.ray
        started = not ray.is_initialized()
        if started:
            if self.address:
                ray.init(address=self.address, log_to_driver=False)
            else:
                ray.init(num_cpus=self.num_cpus, include_dashboard=False, log_to_driver=False)
        try:
            if ray.cluster_resources().get("CPU", 0) < self.threads:
                raise SweepError(f"each Ray task asks for {self.threads} CPUs (threads) but the cluster has "
                                 f"{ray.cluster_resources().get('CPU', 0):g}")
            task = ray.remote(num_cpus=self.threads, max_retries=self.max_retries)(_run_chunk)
            case_ref = ray.put(replace(case, nthread=self.threads))
            pending = {task.remote(self.function, case_ref, keys, points, values): index
                       for index, points, values in chunks}
            while pending:
                done, _ = ray.wait(list(pending), num_returns=1)
                for ref in done:
                    index = pending.pop(ref)
                    try:
                        result = ray.get(ref)
                    except ray.exceptions.RayTaskError as err:  # the chunk raised: its own error, in one line
                        raise (err.cause if isinstance(err.cause, Exception) else err) from None
                    except ray.exceptions.RayError as err:  # workers or nodes lost beyond the retries
                        raise SweepError(f"chunk {index} failed {self.max_retries + 1} times "
                                         f"({type(err).__name__}); the finished chunks are saved: run again "
                                         "with resume") from None
                    yield index, result
        finally:
            if started:
                ray.shutdown()


def _run_chunk(function: ChunkFunction, case: SweepCase, keys, points, values) -> ChunkResult:
    return function(case, keys, points, values)

