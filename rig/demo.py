"""``rig demo``: replay a built-in broadband drive on proton_x, write the responses and a plot."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from rig.channels import channel
from rig.plots import plot_psds, plot_responses
from rig.record import Record
from rig.record_files import write_record
from rig.replay import replay
from rig.signals import band_limited_noise
from rig.vehicle import load_vehicle

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
    log the run to Rerun (rig/review.py)."""
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
        from rig.review import default_blueprint, log_replay, recording

        with recording(rerun, rerun_spawn, default_blueprint(vehicle.corners)) as stream:
            log_replay(stream, result)
    rms = {q: np.sqrt(np.mean(result.record.quantity(q, vehicle.corners) ** 2, axis=0))
           for q in ("sprung_acc", "unsprung_acc", "susp_travel")}
    files_summary = ", ".join(f"{q} RMS " + "/".join(f"{x:.3g}" for x in v) for q, v in rms.items())
    print(f"replayed {duration:.0f} s of broadband drive on {vehicle.name}: {files_summary} (FL/FR/RL/RR, SI)")
    return files
