"""Unbalance identification (the transputer paper): identified against true m e and angle over a range of speeds.

Records of the independent simulator written for the tests (tests/independent_track.py: the truth car's linear
parameters off by up to 3 %, Gaussian ISO 8608 roads, rolling radii a few tenths of a percent apart, 2 % noise),
one unbalanced wheel, 60 s at each speed. Each speed is identified on its own (rig/diagnosis/track/unbalance.py), and
all speeds of a road class together (least squares over the speeds, as the transputer paper does). Prints per case the
identified over the true m e, the angle error, the standard deviations and the wall time; with ``--plot`` draws
the README figure (assets/figures/unbalance_identification.png).
Run: python benchmarks/unbalance.py [--plot PATH] [--classes A B C] [--seed 1]
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

from independent_track import Drive, Unbalance, independent_track_records, random_radii

from rig.diagnosis.track.unbalance import identify_unbalance
from rig.vehicle.vehicle_file import load_vehicle

SPEEDS = (15.0, 20.0, 25.0, 30.0, 35.0)
TRUTH = Unbalance("FR", 0.008, 40.0)
DURATION = 60.0


def run(road_class: str, seed: int, vehicle) -> list[dict]:
    rng = np.random.default_rng(seed)
    radii = random_radii(vehicle, rng)
    drives = [Drive(road_class, speed, DURATION, radii, {c: rng.uniform(0, 2 * np.pi) for c in vehicle.corners})
              for speed in SPEEDS]
    started = time.perf_counter()
    records, _ = independent_track_records(vehicle, TRUTH, drives, seed)
    simulated = time.perf_counter() - started
    rows = []
    for speed, chosen in [(s, [r]) for s, r in zip(SPEEDS, records)] + [(None, records)]:
        started = time.perf_counter()
        found = identify_unbalance(vehicle, chosen)
        wheel = found.wheels[TRUTH.corner]
        rows.append({"class": road_class, "case": f"{speed:g} m/s" if speed else "all speeds", "speed": speed,
                     "verdict": found.verdict, "named": found.named.corner if found.named else "-",
                     "ratio": wheel.unbalance_kgm / TRUTH.kgm, "std_ratio": wheel.std_kgm / TRUTH.kgm,
                     "angle_error": (wheel.angle_deg - TRUTH.angle_deg + 180) % 360 - 180, "std_deg": wheel.std_deg,
                     "others": max(w.unbalance_kgm for c, w in found.wheels.items() if c != TRUTH.corner),
                     "seconds": time.perf_counter() - started})
    print(f"  class {road_class}: {len(records)} records of {DURATION:g} s simulated in {simulated:.1f} s")
    return rows


def plot(rows: list[dict], path: Path) -> None:
    from rig.report.plots import plt, save_figure

    fig, (size_ax, angle_ax) = plt.subplots(1, 2, figsize=(11, 4))
    classes = sorted({r["class"] for r in rows})
    for i, road_class in enumerate(classes):
        single = [r for r in rows if r["class"] == road_class and r["speed"] is not None]
        joint = next(r for r in rows if r["class"] == road_class and r["speed"] is None)
        speed = np.array([r["speed"] for r in single]) + (i - (len(classes) - 1) / 2) * 0.5
        size_ax.errorbar(speed, [r["ratio"] * TRUTH.kgm * 1e3 for r in single],
                         yerr=[2 * r["std_ratio"] * TRUTH.kgm * 1e3 for r in single], fmt="o", color=f"C{i}",
                         label=f"class {road_class}, each speed; all: {joint['ratio'] * TRUTH.kgm * 1e3:.2f} g·m")
        angle_ax.errorbar(speed, [r["angle_error"] for r in single], yerr=[2 * r["std_deg"] for r in single],
                          fmt="o", color=f"C{i}", label=f"class {road_class}")
    size_ax.axhline(TRUTH.kgm * 1e3, color="k", lw=1, label=f"true: {TRUTH.kgm * 1e3:g} g·m at {TRUTH.corner}")
    size_ax.set_ylabel("identified m e [g·m]  (±2σ)")
    angle_ax.axhline(0.0, color="k", lw=1)
    angle_ax.set_ylabel("angle error [°]  (±2σ)")
    for ax in (size_ax, angle_ax):
        ax.set_xlabel("speed [m/s]")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    fig.suptitle(f"unbalance identified from {DURATION:g} s of driving per speed (independent simulator, road unknown, "
                 f"2 % noise)", fontsize=10)
    path.parent.mkdir(parents=True, exist_ok=True)
    save_figure(fig, path)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--classes", nargs="+", default=["A", "B", "C"])
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--vehicle", default="proton_x")
    parser.add_argument("--plot", type=Path,
                        help="write the figure here (README: assets/figures/unbalance_identification.png)")
    args = parser.parse_args()
    vehicle = load_vehicle(args.vehicle)
    print(f"{vehicle.name}, {TRUTH.kgm * 1e3:g} g m at {TRUTH.corner}, {TRUTH.angle_deg:g} deg from the mark")
    rows = []
    for road_class in args.classes:
        rows += run(road_class, args.seed, vehicle)
    print(f"{'class':5s} {'case':10s} {'verdict':15s} {'wheel':5s} {'identified/true':>15s} {'std/true':>8s} "
          f"{'angle err':>9s} {'std deg':>7s} {'max other g m':>13s} {'s':>5s}")
    for r in rows:
        print(f"{r['class']:5s} {r['case']:10s} {r['verdict']:15s} {r['named']:5s} {r['ratio']:15.4f} "
              f"{r['std_ratio']:8.4f} {r['angle_error']:9.2f} {r['std_deg']:7.2f} {r['others'] * 1e3:13.3f} "
              f"{r['seconds']:5.1f}")
    if args.plot:
        plot(rows, args.plot)
        print(f"wrote {args.plot}")


if __name__ == "__main__":
    main()
