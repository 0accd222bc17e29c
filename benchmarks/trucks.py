"""Replay speed of the trucks against the car, measured in the same run.

Prints, for a 60 s random drive (0.5-30 Hz, 3 mm RMS per post) at 256 Hz (the Belgian-block record's rate) on one
thread, the replay time of proton_x (the reference), of truck_6x4 with its rigid frame and with its flexible frame,
and of tractor_4x2, and each truck's time over the car's, with the models' sizes (degrees of freedom, actuators);
and the real-time factors.
Run: python benchmarks/trucks.py
"""

from __future__ import annotations

import dataclasses
import time

from rig.io.record import Record
from rig.signal.filters import band_limited_noise
from rig.sim.replay import replay
from rig.vehicle.mjcf import build_model
from rig.vehicle.vehicle_file import load_vehicle

DURATION = 60.0
RATE = 256.0
REPEATS = 3


def best_of(function, repeats=REPEATS) -> float:
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        function()
        times.append(time.perf_counter() - start)
    return min(times)


def main() -> None:
    truck = load_vehicle("truck_6x4")
    vehicles = {"proton_x": load_vehicle("proton_x"), "truck_6x4 rigid frame": dataclasses.replace(truck, frame=None),
                "truck_6x4": truck, "tractor_4x2": load_vehicle("tractor_4x2")}
    reference = None
    print(f"{DURATION:g} s random drive at {RATE:g} Hz, one thread, best of {REPEATS}")
    for name, vehicle in vehicles.items():
        values = band_limited_noise(DURATION, RATE, (0.5, 30.0), 0.003, len(vehicle.corners), 7)
        drive = Record(RATE, {f"{c}/drive": values[:, i] for i, c in enumerate(vehicle.corners)})
        seconds = best_of(lambda v=vehicle, d=drive: replay(v, d, nthread=1, clip=True))
        model = build_model(vehicle, RATE).model
        reference = reference or seconds
        print(f"{name:24s} {seconds:6.3f} s  {seconds / reference:5.2f} x proton_x  "
              f"real time x{DURATION / seconds:5.1f}  (nv {model.nv}, nu {model.nu}, na {model.na})")


if __name__ == "__main__":
    main()
