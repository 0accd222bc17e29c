"""Make the example files the documentation's commands run on (deterministic: the same files every time).

- ``run_042.mf4``: a rig test as a DAQ exports it: ASAM MDF4 at 256 Hz, 30 s, the DAQ's own channel names,
  displacements in mm, accelerations in g, loads in kN, the body accelerometers mounted upside down, and two
  channels the rig does not need. The car is proton_x off its data sheet by up to 3 % with a hidden bump stop,
  driven by broadband drives with road events, 2 % noise on every measured channel
  (rig/diagnosis/rig_test/synthetic.py).
- ``daq.toml``: the channel map that puts those names onto the channel contract.
- ``unbalanced.toml``: proton_x with an unbalanced front right wheel (8 g·m, 40 degrees past its mark).
- ``bench.csv``: a lab quarter-car bench's test (lab_quarter off its data sheet by up to 3 %), 20 s at 500 Hz: the base
  plate moved by band-limited noise, a random force between body and wheel, the plates' encoders (0.02 mm counts) and
  the force with 1 % noise, as the contract CSV writes them.

Run from the repository: ``python examples/make_examples.py``.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from asammdf import MDF, Signal

from rig.diagnosis.rig_test.synthetic import rig_test_records, truth_vehicle
from rig.io.files import write_record
from rig.io.record import Record
from rig.io.units import STANDARD_GRAVITY
from rig.signal.filters import band_limited_noise
from rig.sim.replay import replay
from rig.vehicle.assets import vehicle_dir
from rig.vehicle.vehicle_file import load_vehicle

HERE = Path(__file__).resolve().parent
RATE, DURATION = 256.0, 30.0
DAQ = {"FL": "LF", "FR": "RF", "RL": "LR", "RR": "RR"}  # the DAQ's corner names
#: contract quantity -> (DAQ name pattern, unit, factor from SI, map entry's extra keys)
CHANNELS = {
    "drive": ("PostCmd_{}", "mm", 1e3, ""),
    "actuator_disp": ("PostDisp_{}", "mm", 1e3, ""),
    "sprung_acc": ("ACC_{}_BODY", "g", -1 / STANDARD_GRAVITY, ', unit = "g", scale = -1.0'),  # upside down
    "unsprung_acc": ("ACC_{}_WHEEL", "g", 1 / STANDARD_GRAVITY, ""),
    "susp_travel": ("Travel_{}", "mm", 1e3, ""),
    "tyre_force": ("WFT_Fz_{}", "kN", 1e-3, ""),
}


def rig_test() -> None:
    rng = np.random.default_rng(42)
    truth = truth_vehicle(load_vehicle("proton_x"), "bump_stop", rng)
    record, _ = rig_test_records(truth, rng, DURATION, 5.0, RATE)  # the second record goes unused
    signals = [Signal((record[f"{corner}/{quantity}"] * factor).astype(np.float32), record.time,
                      name=pattern.format(daq), unit=unit)
               for corner, daq in DAQ.items() for quantity, (pattern, unit, factor, _) in CHANNELS.items()]
    signals += [Signal(np.zeros(record.n_samples, np.float32), record.time, name="CAN_VehSpeed", unit="km/h"),
                Signal(np.full(record.n_samples, 82.5, np.float32), record.time, name="Oil_Temp", unit="degC")]
    mdf = MDF(version="4.10")
    mdf.append(signals, comment="four-poster run 042: proton_x, broadband drives with road events")
    mdf.save(HERE / "run_042.mf4", overwrite=True)
    mdf.close()
    lines = ["# The DAQ's names onto the channel contract (docs/contracts.md); units from the file unless given",
             "[channels]"]
    for corner, daq in DAQ.items():
        for quantity, (pattern, _, _, extra) in CHANNELS.items():
            target = f'{{ name = "{corner}/{quantity}"{extra} }}' if extra else f'"{corner}/{quantity}"'
            lines.append(f'"{pattern.format(daq)}" = {target}')
    (HERE / "daq.toml").write_text("\n".join(lines) + "\n")


def unbalanced() -> None:
    text = (vehicle_dir() / "proton_x.toml").read_text(encoding="utf-8")
    text = "# proton_x with an unbalanced front right wheel: 8 g·m, 40 degrees past its mark\n" + text.replace(
        'name = "proton_x"', 'name = "proton_x_unbalanced"')
    text += "\n[wheel_unbalance]\ncorner = \"FR\"\nunbalance_kgm = 0.008      # kg m\nangle_deg = 40.0          # deg\n"
    (HERE / "unbalanced.toml").write_text(text, encoding="utf-8")


def bench() -> None:
    rng = np.random.default_rng(3)
    truth = truth_vehicle(load_vehicle("lab_quarter"), "none", rng)
    rate, duration, encoder = 500.0, 20.0, 0.02e-3
    base = band_limited_noise(duration, rate, (0.5, 12.0), 1.5e-3, 1, seed=3)[:, 0]
    force = band_limited_noise(duration, rate, (0.5, 15.0), 0.8, 1, seed=4)[:, 0]
    played = replay(truth, Record(rate, {"FL/actuator_disp": base, "FL/active_force": force}))
    channels = {name: np.round(played.record[name] / encoder) * encoder
                for name in ("FL/actuator_disp", "FL/sprung_disp", "FL/unsprung_disp")}
    channels["FL/active_force"] = force + 0.01 * np.std(force) * rng.standard_normal(force.size)
    write_record(HERE / "bench.csv", Record(rate, channels, metadata={
        "vehicle": "lab_quarter", "test": "rig", "source": "examples/make_examples.py: lab_quarter off its data "
                                                           "sheet by up to 3 %, encoders of 0.02 mm"}))


if __name__ == "__main__":
    rig_test()
    unbalanced()
    bench()
