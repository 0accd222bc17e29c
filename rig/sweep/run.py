"""Run a sweep in chunks: each finished chunk written atomically, a resumed run skipping finished chunks.

The design is cut into chunks of ``chunk_size`` points in order; an engine runs chunks and hands back each
finished one, which is written at once as ``DIR/chunks/chunk_NNNNN.npz`` (complete or absent: rig/io/atomic.py).
``DIR/sweep.json`` holds the design, the chunk size and the case's fingerprint, so that ``resume`` reuses
only chunks of the same sweep. The table is assembled from the chunk files and checked to hold every point
exactly once, whatever an engine retried. The chunks are the same for every engine, so every engine gives the
same table.

``LocalEngine`` runs the chunks one after another in this process, each a threaded rollout
(rig/sweep/evaluate.py); ``rig.sweep.ray_engine.RayEngine`` hands them to Ray tasks.
"""

from __future__ import annotations

import json
import os
from collections.abc import Callable, Iterator
from pathlib import Path

import numpy as np

from rig.io.atomic import atomic_path, write_text_atomic
from rig.sweep.design import Design, SweepError
from rig.sweep.evaluate import ChunkResult, SweepCase, evaluate_chunk
from rig.sweep.results import SweepResult, psd_band

#: (chunk index, design point indices, their key values)
Chunk = tuple[int, np.ndarray, np.ndarray]
ChunkFunction = Callable[[SweepCase, tuple[str, ...], np.ndarray, np.ndarray], ChunkResult]


class LocalEngine:
    """Chunks one after another in this process; ``function`` evaluates a chunk (default ``evaluate_chunk``)."""

    def __init__(self, function: ChunkFunction = evaluate_chunk):
        self.function = function

    def run(self, case: SweepCase, keys: tuple[str, ...], chunks: list[Chunk]) -> Iterator[tuple[int, ChunkResult]]:
        for index, points, values in chunks:
            yield index, self.function(case, keys, points, values)


def chunk_design(design: Design, chunk_size: int) -> list[Chunk]:
    """The design cut into chunks of ``chunk_size`` consecutive points."""
    if chunk_size < 1:
        raise SweepError(f"chunk size must be at least 1, got {chunk_size}")
    starts = range(0, design.n_points, chunk_size)
    return [(i, np.arange(s, min(s + chunk_size, design.n_points)), design.values[s:s + chunk_size])
            for i, s in enumerate(starts)]


def run_sweep(case: SweepCase, design: Design, out: str | os.PathLike, engine=None, chunk_size: int = 4,
              resume: bool = False, progress: Callable[[int], None] | None = None) -> SweepResult:
    """Run ``design`` on ``case`` with ``engine`` (default ``LocalEngine()``), chunks written under ``out``.

    ``resume`` reuses the finished chunks of the same sweep in ``out``; without it they are run again.
    ``progress(points)`` is called with the number of points finished (reused ones first).
    """
    out = Path(out)
    chunk_dir = out / "chunks"
    chunks = chunk_design(design, chunk_size)
    manifest = {"design": json.loads(design.to_json()), "chunk_size": chunk_size, "case": case.fingerprint()}
    manifest_path = out / "sweep.json"
    if resume and manifest_path.is_file() and json.loads(manifest_path.read_text()) != manifest:
        raise SweepError(f"{out} holds another sweep (design, chunk size or case differ): cannot resume it")
    if not resume or not manifest_path.is_file():
        for stale in chunk_dir.glob("chunk_*.npz"):
            stale.unlink()
        write_text_atomic(manifest_path, json.dumps(manifest))
    finished = {i for i, _, _ in chunks if _chunk_path(chunk_dir, i).is_file()}
    if progress:
        progress(sum(len(p) for i, p, _ in chunks if i in finished))
    todo = [c for c in chunks if c[0] not in finished]
    for index, result in (engine or LocalEngine()).run(case, design.keys, todo):
        if index in finished:  # an engine handing back a chunk twice: the first one stands
            continue
        _write_chunk(_chunk_path(chunk_dir, index), result)
        finished.add(index)
        if progress:
            progress(len(result.points))
    return assemble(design, chunk_dir, len(chunks), chunks_run=len(todo), chunks_reused=len(chunks) - len(todo))


def assemble(design: Design, chunk_dir: Path, n_chunks: int, chunks_run: int = 0,
             chunks_reused: int = 0) -> SweepResult:
    """The table from the chunk files; SweepError unless every design point is there exactly once."""
    missing = [i for i in range(n_chunks) if not _chunk_path(chunk_dir, i).is_file()]
    if missing:
        raise SweepError(f"chunk(s) {', '.join(map(str, missing))} did not finish; run again with resume")
    parts = [_read_chunk(_chunk_path(chunk_dir, i)) for i in range(n_chunks)]
    points = np.concatenate([p.points for p in parts])
    if not np.array_equal(np.sort(points), np.arange(design.n_points)):
        raise SweepError(f"{chunk_dir} does not hold every design point exactly once")
    names = parts[0].metric_names
    if any(p.metric_names != names for p in parts):
        raise SweepError(f"{chunk_dir}: chunks measured different metrics")
    order = np.argsort(points)
    metrics = np.concatenate([p.metrics for p in parts])[order]
    band = None
    if parts[0].psd is not None:
        band = psd_band(parts[0].psd_channels, parts[0].frequency, np.concatenate([p.psd for p in parts])[order])
    return SweepResult(design, names, metrics, band, chunks_run, chunks_reused)


def _chunk_path(chunk_dir: Path, index: int) -> Path:
    return chunk_dir / f"chunk_{index:05d}.npz"


def _write_chunk(path: Path, result: ChunkResult) -> None:
    arrays = {"points": result.points, "metric_names": np.array(result.metric_names), "metrics": result.metrics}
    if result.psd is not None:
        arrays.update(psd_channels=np.array(result.psd_channels), frequency=result.frequency, psd=result.psd)
    with atomic_path(path) as tmp, open(tmp, "wb") as file:
        np.savez(file, **arrays)


def _read_chunk(path: Path) -> ChunkResult:
    with np.load(path) as data:
        if "psd" not in data:
            return ChunkResult(data["points"], tuple(map(str, data["metric_names"])), data["metrics"])
        return ChunkResult(data["points"], tuple(map(str, data["metric_names"])), data["metrics"],
                           tuple(map(str, data["psd_channels"])), data["frequency"], data["psd"])
