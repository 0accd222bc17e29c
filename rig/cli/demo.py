"""``rig demo``: replay a built-in broadband drive on proton_x, write the responses and a plot."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from rig.causes import damper_asymmetry
from rig.io.channels import channel
from rig.io.files import write_record
from rig.io.record import Record
from rig.report.plots import plot_psds, plot_responses
from rig.signal.filters import band_limited_noise
from rig.sim.replay import replay
from rig.vehicle.vehicle_file import load_vehicle

DEMO_RATE = 512.0      # Hz
DEMO_BAND = (0.5, 30)  # Hz
DEMO_RMS = 0.003       # m per post


def demo_drive(vehicle_corners: tuple[str, ...], duration: float = 20.0, seed: int = 2) -> Record:
    """The built-in broadband drive: band-limited random post commands, faded in and out."""
    values = band_limited_noise(duration, DEMO_RATE, DEMO_BAND, DEMO_RMS, len(vehicle_corners), seed)
    channels = {channel(c, "drive"): values[:, i] for i, c in enumerate(vehicle_corners)}
    return Record(DEMO_RATE, channels, metadata={"test": "rig", "signal": "band-limited random 0.5-30 Hz"})


def run_demo(out_dir: str | Path, vehicle_name: str = "proton_x", duration: float = 20.0,
             rerun: str | Path | None = None, rerun_spawn: bool = False) -> dict[str, Path]:
    """Run the demo; returns the files written in ``out_dir``. ``rerun`` (.rrd path) / ``rerun_spawn`` also
    log the run to Rerun (rig/report/review.py)."""
    out_dir = Path(out_dir)
    vehicle = load_vehicle(vehicle_name)
    drive = demo_drive(vehicle.corners, duration)
    result = replay(vehicle, drive)
    files = {"drive": out_dir / "drive.csv", "response": out_dir / "response.csv",
             "plot": out_dir / "responses.png", "psd": out_dir / "psd.png"}
    write_record(files["drive"], drive)
    write_record(files["response"], result.record)
    title = f"{vehicle.name} on the four-poster: broadband drive replay"
    mid = duration / 2
    plot_responses(result.record, files["plot"], f"{title} (3 s window)", window=(mid - 1.5, mid + 1.5))
    plot_psds(result.record, files["psd"], f"{title}: PSDs")
    if rerun is not None or rerun_spawn:
        from rig.report.review import default_blueprint, log_replay, recording

        with recording(rerun, rerun_spawn, default_blueprint(vehicle.corners)) as stream:
            log_replay(stream, result)
    rms = {q: np.sqrt(np.mean(result.record.quantity(q, vehicle.corners) ** 2, axis=0))
           for q in ("sprung_acc", "unsprung_acc", "susp_travel")}
    files_summary = ", ".join(f"{q} RMS " + "/".join(f"{x:.3g}" for x in v) for q, v in rms.items())
    print(f"replayed {duration:.0f} s of broadband drive on {vehicle.name}: {files_summary} (FL/FR/RL/RR, SI)")
    return files


STORY_CAUSE = damper_asymmetry.CAUSE.name  # hidden in the "real" car of the story
STORY_CHANNELS = [channel(c, q) for c in ("FL", "FR", "RL", "RR") for q in ("sprung_acc", "unsprung_acc")]


def run_story(out_dir: str | Path, rerun: str | Path | None = None, rerun_spawn: bool = False,
              iterations: int = 5, say=print) -> dict[str, float]:
    """The whole product on built-in data: a "real" car with a hidden cause, its road target, a drive
    iterated on the baseline model that misses on the real car, the diagnosis of the real car's rig data,
    and a drive iterated on the extended model that does better. Returns the before/after errors (%)."""
    from controllers.rpc import DriveIteration, IterationSettings
    from rig.diagnosis.diagnose import diagnose
    from rig.diagnosis.synthetic import rig_test_records, truth_vehicle
    from rig.report.diagnosis_report import write_diagnosis
    from rig.report.plots import IterationPlots
    from rig.road.roads import iso8608_road
    from rig.sim.track import track_run

    out_dir = Path(out_dir)
    rng = np.random.default_rng(7)
    baseline = load_vehicle("proton_x")
    real = truth_vehicle(baseline, STORY_CAUSE, rng)
    say(f"1. the real car: proton_x off its data sheet by up to 3 % and with a hidden {STORY_CAUSE}")
    target = track_run(real, iso8608_road("C", 500.0, seed=11), 20.0, duration=20.0).record
    write_record(out_dir / "target.csv", target)
    say("2. its target: 20 s over an ISO 8608 class C road at 20 m/s, 8 accelerations")
    settings = IterationSettings(iterations=iterations, target_error_pct=1.0)

    def iterate(vehicle, folder: str) -> tuple[DriveIteration, np.ndarray]:
        job = DriveIteration(vehicle, target, STORY_CHANNELS, out_dir / folder, settings)
        plots = IterationPlots(out_dir / folder, f"{vehicle.name}: drive iteration", job.target, job.span, job.rate,
                               STORY_CHANNELS)
        return job, job.run(progress=False, callback=plots).drive

    first, drive = iterate(baseline, "iteration_baseline")
    before = first.score(drive, real)
    worst_before = max(m["rms_error_pct"] for m in before.values())
    say(f"3. a drive iterated on the baseline model, played on the real car: worst channel {worst_before:.1f} % RMS error")
    measured, holdout = rig_test_records(real, rng, 20.0, 10.0)
    write_record(out_dir / "rig_test_measured.csv", measured)
    write_record(out_dir / "rig_test_holdout.csv", holdout)
    say("4. the real car's rig test (random drive with road events), diagnosed against the baseline model ...")
    result = diagnose(baseline, measured, holdout)
    write_diagnosis(result, out_dir / "diagnosis")
    say(f"   verdict: {result.verdict}; held-out TDDI {result.recalibrated_tddi:.4g} (recalibrated) -> "
        f"{result.extended_tddi:.4g} (extended)")
    shapes = "; ".join(f"{c} {', '.join(law.shapes)}" for c, law in result.force_laws.corners.items() if law.shapes)
    say(f"   the force laws measured from the data show: {shapes or 'straight laws'} (diagnosis/force_laws.png)")
    second, drive = iterate(result.extended_vehicle, "iteration_extended")
    after = second.score(drive, real)
    worst_after = max(m["rms_error_pct"] for m in after.values())
    say(f"5. a drive iterated on the extended model, played on the real car: worst channel {worst_after:.1f} % RMS error")
    if rerun is not None or rerun_spawn:
        from rig.report.review import default_blueprint, log_record, log_replay, recording
        from rig.sim.replay import replay

        # the outcome on the real car (run/, with the rig moving) against its target (grey), and the rig test
        with recording(rerun, rerun_spawn, default_blueprint(baseline.corners)) as stream:
            log_record(stream, target, prefix="target", reference=True)
            log_replay(stream, replay(real, second.drive_record(drive)))
            log_record(stream, measured, prefix="rig_test")
    return {"worst_error_before_pct": worst_before, "worst_error_after_pct": worst_after}
