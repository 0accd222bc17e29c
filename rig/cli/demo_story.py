"""The whole product on built-in data (``rig demo``): a "real" car with a hidden cause, its road target, a drive
iterated on the baseline model that misses on the real car, the diagnosis of the real car's rig test, and a
drive iterated on the extended model that does better.

The story writes its data products as it goes (the target, the rig test, both iterations' drives, histories
and plots, the diagnosis and its report) into ``out_dir`` and returns what a presentation needs."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from controllers.rpc import DriveIteration, IterationSettings
from rig.causes import damper_asymmetry
from rig.diagnosis.rig_test.diagnose import Diagnosis, diagnose
from rig.diagnosis.rig_test.synthetic import rig_test_records, truth_vehicle
from rig.io.channels import channel
from rig.io.files import write_record
from rig.io.record import Record
from rig.report.diagnosis_report import write_diagnosis
from rig.report.plots import IterationPlots
from rig.road.roads import iso8608_road
from rig.sim.replay import ReplayResult, replay
from rig.sim.track import track_run
from rig.vehicle.vehicle_file import Vehicle, load_vehicle

STORY_CAUSE = damper_asymmetry.CAUSE.name  # hidden in the "real" car of the story
STORY_CHANNELS = [channel(c, q) for c in ("FL", "FR", "RL", "RR") for q in ("sprung_acc", "unsprung_acc")]


@dataclass
class StoryResult:
    """What the story found: the errors (%) of the drives played on the real car (the worst channel's, and every
    channel's RMS error in percent of the target's, as the iteration scores it), the diagnosis, and the records a
    review shows (the target, the real car on the extended and on the baseline model's drive, the rig test)."""

    baseline: Vehicle
    worst_error_before_pct: float   # drive iterated on the baseline model
    worst_error_after_pct: float    # drive iterated on the extended model
    diagnosis: Diagnosis
    target: Record
    outcome: ReplayResult           # the real car on the extended model's drive
    rig_test: Record
    before: ReplayResult | None = None  # the real car on the baseline model's drive
    errors_before: dict[str, float] = field(default_factory=dict)  # channel -> RMS error (%), baseline model's drive
    errors_after: dict[str, float] = field(default_factory=dict)   # channel -> RMS error (%), extended model's drive


def run_story(out_dir: str | Path, iterations: int = 5, say: Callable[[str], None] = print) -> StoryResult:
    """Run the story into ``out_dir``; ``say`` narrates each step."""
    out_dir = Path(out_dir)
    rng = np.random.default_rng(7)
    baseline = load_vehicle("proton_x")
    real = truth_vehicle(baseline, STORY_CAUSE, rng)
    say(f"1. the real car: proton_x off its data sheet by up to 3 % and with a hidden {STORY_CAUSE}")
    target = track_run(real, iso8608_road("C", 500.0, seed=11), 20.0, duration=20.0).record
    write_record(out_dir / "target.csv", target)
    say("2. its target: 20 s over an ISO 8608 class C road at 20 m/s, 8 accelerations")
    settings = IterationSettings(iterations=iterations, target_error_pct=1.0)

    def iterate(vehicle: Vehicle, folder: str) -> tuple[DriveIteration, np.ndarray]:
        job = DriveIteration(vehicle, target, STORY_CHANNELS, out_dir / folder, settings)
        plots = IterationPlots(out_dir / folder, f"{vehicle.name}: drive iteration", job.target, job.span, job.rate,
                               STORY_CHANNELS, settings.target_error_pct)
        return job, job.run(progress=False, callback=plots).drive

    first, drive = iterate(baseline, "iteration_baseline")
    errors_before = {n: m.rms_error_pct for n, m in first.score(drive, real).items()}
    before = max(errors_before.values())
    played_before = replay(real, first.drive_record(drive))
    say(f"3. a drive iterated on the baseline model, played on the real car: worst channel {before:.1f} % RMS error")
    measured, holdout = rig_test_records(real, rng, 20.0, 10.0)
    write_record(out_dir / "rig_test_measured.csv", measured)
    write_record(out_dir / "rig_test_holdout.csv", holdout)
    say("4. the real car's rig test (random drive with road events), diagnosed against the baseline model ...")
    result = diagnose(baseline, measured, holdout)
    write_diagnosis(result, out_dir / "diagnosis", "rig demo (its step 4)")
    say(f"   verdict: {result.verdict}; held-out TDDI {result.recalibrated_tddi:.4g} (recalibrated) -> "
        f"{result.extended_tddi:.4g} (extended)")
    shapes = "; ".join(f"{c} {', '.join(law.shapes)}" for c, law in result.force_laws.corners.items() if law.shapes)
    say(f"   the force laws measured from the data show: {shapes or 'straight laws'} (diagnosis/force_laws.png)")
    second, drive = iterate(result.extended_vehicle, "iteration_extended")
    errors_after = {n: m.rms_error_pct for n, m in second.score(drive, real).items()}
    after = max(errors_after.values())
    say(f"5. a drive iterated on the extended model, played on the real car: worst channel {after:.1f} % RMS error")
    return StoryResult(baseline, before, after, result, target, replay(real, second.drive_record(drive)), measured,
                       played_before, errors_before, errors_after)
