"""``rig dyno`` end to end: LabVIEW-style exports of a generated dyno programme read through a channel map, the law
chosen and written into a vehicle file, damper.json's contract keys, the plots; and one-line refusals."""

import json

import numpy as np
import pytest
from dyno_cases import dyno_records

from rig.cli import main
from rig.diagnosis.dyno.damper_law import UNITS
from rig.vehicle.vehicle_file import load_vehicle

LAW = {"c_low_rebound": 6000.0, "c_high_rebound": 1500.0, "knee_rebound": 0.25, "c_low_compression": 3000.0,
       "c_high_compression": 800.0, "knee_compression": 0.2, "preload": 150.0, "temperature_drift": -0.004}
MAP = """[channels]
"Position (mm)" = "damper/displacement"
"Load (kN)" = "damper/force"
"Oil temp (°C)" = "damper/temperature"
"""


def labview_csv(path, record, rates=None, position_unit=" (mm)"):
    """A record as LabVIEW writes a waveform export: a Time/Amplitude pair per channel, quoted headers, units in
    parentheses, displacement in mm, force in kN, and the load cell's raw voltage beside it."""
    rates = rates or {}
    channels = [(f"Position{position_unit}", record["damper/displacement"] * 1e3, "{:.5f}"),
                ("Load (kN)", record["damper/force"] / 1e3, "{:.6f}"),
                ("Load raw (V)", record["damper/force"] / 4e3, "{:.6f}"),
                ("Oil temp (°C)", record["damper/temperature"], "{:.3f}")]
    columns = []
    for name, values, fmt in channels:
        rate = rates.get(name, record.rate)
        time = np.arange(int(values.size * rate / record.rate)) / rate
        values = np.interp(time, record.time, values)
        columns += [(f'"Time - {name}"', [f"{t:.6f}" for t in time]),
                    (f'"Amplitude - {name}"', [fmt.format(v) for v in values])]
    rows = max(len(c) for _, c in columns)
    lines = [",".join(h for h, _ in columns)]
    lines += [",".join(c[i] if i < len(c) else "" for _, c in columns) for i in range(rows)]
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


@pytest.fixture(scope="module")
def exports(tmp_path_factory):
    folder = tmp_path_factory.mktemp("dyno")
    paths = [str(labview_csv(folder / f"{name}.csv", record)) for name, record in dyno_records(LAW)]
    (folder / "map.toml").write_text(MAP, encoding="utf-8")
    return folder, paths


def test_rig_dyno_fits_writes_and_checks_the_vehicle_file(exports, capsys):
    folder, paths = exports
    out, written = folder / "out", folder / "proton_x_dyno.toml"
    assert main(["dyno", "--record", *paths, "--map", str(folder / "map.toml"), "--out", str(out),
                 "--reference-temperature", "35", "--vehicle", "proton_x", "--axle", "rear",
                 "--motion-ratio", "0.7", "--write", str(written), "--simulate"]) == 0
    document = json.loads((out / "damper.json").read_text())
    assert document["law"] == "digressive+preload+temperature"
    for key, true in LAW.items():
        assert document["coefficients"][key] == pytest.approx(true, rel=0.03), key
        low, high = document["intervals"][key]
        assert low < document["coefficients"][key] < high
    assert document["residual_rms_pct"] < 3.0
    assert len(document["forms"]) == 40 and document["forms"][0]["law"] == document["law"]
    assert document["units"]["knee_rebound"] == "m/s" and document["reference_temperature_degC"] == 35.0
    vehicle = load_vehicle(written)
    assert vehicle.rear.damping == pytest.approx(0.5 * (6000 + 3000) * 0.49, rel=0.03)
    assert "front" not in vehicle.extensions["measured_law"] and "rear" in vehicle.extensions["damper_asymmetry"]
    reproduced = document["vehicle"]["reproduction"]
    assert reproduced["law_rms_pct"] < 1e-6
    # the loops at 25-45 degC against the file's one temperature: the fit's residual and up to 4 % of drift
    assert document["residual_rms_pct"] < reproduced["loop_rms_pct"] < document["residual_rms_pct"] + 2.0
    assert set(document["simulated"]["rms_difference_pct"]) == set(paths)
    for plot in ("force_velocity.png", "loops.png", "written_loops.png", "vehicle_loops.png"):
        assert (out / plot).stat().st_size > 10_000
    printed = capsys.readouterr()
    assert "law: digressive+preload+temperature" in printed.out and "raw voltage" not in printed.err
    assert "Load raw (V)" in printed.err  # left out of the map, and said so
    lines = printed.out.splitlines()
    law_line = lines.index(next(line for line in lines if line.startswith("law:")))
    assert lines[law_line + 1].strip().startswith("digressive+preload+temperature:")  # its residual tests
    assert lines[law_line + 2].split() == ["coefficient", "value", "95", "%", "interval", "unit"]
    for key in LAW:  # every coefficient in a labelled row: value, interval, unit
        row = next(line for line in lines if line.split()[:1] == [key])
        value, low, _, high = row.split()[1:5]
        assert float(low) < float(value) < float(high) and row.endswith(UNITS[key])
    assert any(line.split()[:1] == ["record"] and line.endswith("RMS of measured minus simulated force, % of the "
                                                                "measured RMS") for line in lines)
    for path in paths:
        row = next(line for line in lines if line.strip().startswith(path))
        assert row.split()[-1] == "%" and float(row.split()[-2]) == pytest.approx(
            document["simulated"]["rms_difference_pct"][path], abs=0.051)


def _refused(capsys, argv):
    """The refusal: exit 2, one line (after any notes on what the map left out)."""
    assert main(argv) == 2
    lines = capsys.readouterr().err.splitlines()
    assert lines[-1].startswith("rig dyno: error: ") and all(": unmapped: " in line for line in lines[:-1])
    return lines[-1]


def test_bad_dyno_input_is_refused_in_one_line(exports, tmp_path, capsys):
    folder, paths = exports
    _, record = dyno_records(LAW)[0]
    no_force = _refused(capsys, ["dyno", "--record", paths[0], "--map", "Position=damper/displacement",
                                 "--out", str(tmp_path)])
    assert "no 'damper/force' channel" in no_force
    unitless = labview_csv(tmp_path / "unitless.csv", record, position_unit="")
    in_mm = _refused(capsys, ["dyno", "--record", str(unitless), "--map", "Position=damper/displacement",
                              "Load (kN)=damper/force", "--out", str(tmp_path)])
    assert "channel 'damper/displacement' has no unit" in in_mm and 'unit = "mm"' in in_mm
    other_rate = labview_csv(tmp_path / "rates.csv", record, rates={"Load (kN)": 500.0})
    rates = _refused(capsys, ["dyno", "--record", str(other_rate), "--map", str(folder / "map.toml"),
                              "--out", str(tmp_path)])
    assert "'Time - Load (kN)' runs at 500 Hz" in rates and "--resample" in rates
    assert "need --vehicle" in _refused(capsys, ["dyno", "--record", paths[0], "--map", str(folder / "map.toml"),
                                                 "--out", str(tmp_path), "--write", str(tmp_path / "v.toml")])
