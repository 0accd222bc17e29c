"""``rig demo``: the whole product on built-in data (the story in rig/cli/demo_story.py), or with
``--quick`` a built-in broadband drive replayed on proton_x, its responses written and plotted."""

from __future__ import annotations

import argparse
import os
import time
from pathlib import Path

import numpy as np

from rig.cli.options import POSITIVE, add_rerun, command_line, out_folder, review


def add_parser(commands: argparse._SubParsersAction) -> None:
    demo = commands.add_parser("demo", help="the whole story on built-in data: iterate, miss on the real car, "
                                            "diagnose, extend, iterate again (a few minutes)")
    demo.add_argument("--out", type=out_folder, metavar="DIR", default="rig_demo_output",
                      help="output folder (default: %(default)s)")
    demo.add_argument("--quick", action="store_true",
                      help="only replay a built-in broadband drive on proton_x and plot it (seconds)")
    demo.add_argument("--duration", metavar="S", type=POSITIVE, default=20.0,
                      help="--quick drive length in s (default: %(default)s)")
    add_rerun(demo)
    demo.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    if args.quick:
        files = _quick(Path(args.out), args)
        print(f"wrote {', '.join(p.name for p in files)} in {Path(args.out).resolve()}")
    else:
        _story(args)
    return 0


def _quick(out_dir: Path, args: argparse.Namespace) -> list[Path]:
    """Replay the broadband drive on proton_x; the files written."""
    from rig.io.files import write_record
    from rig.report.plots import plot_psds, plot_responses, save_figure
    from rig.report.review_runs import present_replay
    from rig.sim.broadband import broadband_drive
    from rig.sim.replay import replay
    from rig.vehicle.vehicle_file import load_vehicle

    vehicle = load_vehicle("proton_x")
    drive = broadband_drive(vehicle.corners, args.duration)
    result = replay(vehicle, drive)
    files = [out_dir / "drive.csv", out_dir / "response.csv", out_dir / "responses.png", out_dir / "psd.png"]
    write_record(files[0], drive)
    write_record(files[1], result.record)
    title = f"{vehicle.name} on the four-poster: broadband drive replay"
    mid = args.duration / 2
    save_figure(plot_responses(result.record, f"{title} (3 s window)", window=(mid - 1.5, mid + 1.5)), files[2])
    save_figure(plot_psds(result.record, f"{title}: PSDs"), files[3])
    review(args, f"{args.duration:g} s of broadband drive replayed on {vehicle.name}",
           lambda rec: present_replay(rec, result, args.rerun_magnify))
    rms = {q: np.sqrt(np.mean(result.record.quantity(q, vehicle.corners) ** 2, axis=0))
           for q in ("sprung_acc", "unsprung_acc", "susp_travel")}
    summary = ", ".join(f"{q} RMS " + "/".join(f"{x:.3g}" for x in v) for q, v in rms.items())
    print(f"replayed {args.duration:.0f} s of broadband drive on {vehicle.name}: {summary} (FL/FR/RL/RR, SI)")
    return files


def _story(args: argparse.Namespace) -> None:
    from rig.cli.demo_story import run_story
    from rig.io.atomic import write_text_atomic

    said: list[str] = []

    def say(line: str) -> None:
        print(line, flush=True)
        said.append(line)

    load, start, cpu = os.getloadavg()[0], time.perf_counter(), time.process_time()
    story = run_story(args.out, say=say)
    wall, cpu = time.perf_counter() - start, time.process_time() - cpu
    headline = (f"played on the real car, the worst channel's RMS error went from {story.worst_error_before_pct:.1f} "
                f"% (drive iterated on the baseline model) to {story.worst_error_after_pct:.1f} % (extended model)")
    took = (f"took {wall:.0f} s, {cpu:.0f} s of CPU over all threads, on {os.cpu_count()} cores at a load of "
            f"{load:.1f} when it started")
    out = Path(args.out).resolve()
    write_text_atomic(out / "summary.md", "\n".join([
        "# rig demo", "", f"Run: `{command_line(args)}` ({took}).", "", f"**{headline}**", "", "What happened:", "",
        *[f"    {line}" for line in said], "", "What to look at:", "",
        "- `diagnosis/report.md`: what the diagnosis found in the real car's rig test, and why",
        "- `iteration_baseline/convergence.png`, `iteration_extended/convergence.png`: the two iterations",
        "- the same on your own records: `rig validate`, `rig diagnose`, `rig iterate` (README.md, docs/cli.md)", ""]))
    print(headline)
    print(took)
    print(f"summary: {out / 'summary.md'}; report: {out / 'diagnosis' / 'report.md'}")
    review(args, "iterate, miss on the real car, diagnose, extend, iterate again",
           lambda rec: _review_story(rec, story, args))


def _review_story(rec, story, args: argparse.Namespace) -> None:
    """The real car on the extended model's drive (``run/``, the rig moving) and on the baseline model's
    (``before/``, light) against its target (grey, on top), each channel's error before and after; then the
    diagnosis."""
    from rig.report.review import log_record
    from rig.report.review_diagnosis import log_diagnosis
    from rig.report.review_runs import log_run

    log_record(rec, story.target, "target", reference=True, label="target")
    if story.before is not None:
        played = story.before.record
        log_record(rec, played.select([n for n in story.errors_before if n in played]), "before", faint=True,
                   label="baseline model's drive:")
    log_run(rec, story.outcome.record, story.outcome.model, story.outcome.qpos, args.rerun_magnify)
    rec.results += ["| on the real car, RMS error (% of the target's) | drive iterated on the baseline model | "
                    "on the extended model |", "|---|---|---|",
                    *(f"| {n} | {e:.1f} % | {story.errors_after.get(n, float('nan')):.1f} % |"
                      for n, e in story.errors_before.items()), ""]
    log_diagnosis(rec, story.diagnosis)
    rec.headline = (f"played on the real car, the worst channel's RMS error went from "
                    f"{story.worst_error_before_pct:.1f} % (drive iterated on the baseline model) to "
                    f"{story.worst_error_after_pct:.1f} % (extended model); diagnosis: {rec.headline}")
