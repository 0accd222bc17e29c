"""Time columns as real exports print them: rounded stamps are accepted, real gaps, repeated and reversed
stamps are refused with the row named, irregular logs are resampled only when asked."""

import numpy as np
import pytest

from rig.sim.broadband import broadband_drive
from rig.cli.main import main
from rig.io.channels import CORNERS, channel
from rig.io.csv_format import read_csv
from rig.io.files import read_record
from rig.io.record import RecordError
from rig.io.time_stamps import printed_resolution
from rig.signal.metrics import tddi
from rig.sim.replay import replay
from rig.vehicle.vehicle_file import load_vehicle

HEADER = "time [s],FL/drive [mm]\n"


def export(path, time, values, digits, header=HEADER):
    """A DAQ-style export: every number printed to ``digits`` significant digits."""
    rows = "".join(f"{t:.{digits}g},{v:.{digits}g}\n" for t, v in zip(time, values))
    path.write_text(header + rows)
    return path


def test_printed_resolution_is_half_a_unit_in_the_last_digit():
    np.testing.assert_allclose(printed_resolution(["1.011719", "3.5e-02", "12", "0", "0.000", "100.0"]),
                               [5e-7, 5e-4, 0.5, 0.0, 0.0, 0.05])


@pytest.mark.parametrize("rate", [200.0, 512.0, 2048.0])
@pytest.mark.parametrize("digits", [5, 6, 7])
def test_rounded_exports_read_at_their_exact_rate(tmp_path, rate, digits):
    time = np.arange(int(30 * rate)) / rate  # past 10 s, 5 digits print milliseconds: coarser than 2048 Hz
    values = 10 * np.sin(2 * np.pi * 1.3 * time)
    record = read_csv(export(tmp_path / "r.csv", time, values, digits))
    assert record.rate == rate
    assert record.start_time == 0.0
    assert record.n_samples == time.size
    np.testing.assert_allclose(record["FL/drive"], values * 1e-3, atol=10 ** -digits * 10e-3)


@pytest.mark.parametrize("rate", [200.0, 512.0, 2048.0])
@pytest.mark.parametrize("digits", [5, 6, 7])
def test_a_real_gap_is_refused_naming_its_row(tmp_path, rate, digits):
    time = np.arange(int(8 * rate)) / rate  # below 10 s every export here resolves a sample interval
    gap = int(3.3 * rate)
    time = np.delete(time, gap)
    path = export(tmp_path / "r.csv", time, np.zeros(time.size), digits)
    with pytest.raises(RecordError, match=rf"non-uniform time at data row {gap + 1} \(line {gap + 2}\): "
                                          rf"step .* \((1.9\d|2.0\d) samples: a gap or an irregular log\); "
                                          rf".*--resample"):
        read_csv(path)


def test_repeated_and_reversed_stamps_are_refused_naming_the_row(tmp_path):
    time = np.arange(2000) / 512.0
    repeated = np.insert(time, 700, time[699])
    with pytest.raises(RecordError, match=r"data row 701 \(line 702\): time stamp 1.365234 s repeats the previous"):
        read_csv(export(tmp_path / "a.csv", repeated, np.zeros(repeated.size), 7))
    reversed_ = time.copy()
    reversed_[[900, 901]] = reversed_[[901, 900]]
    with pytest.raises(RecordError, match=r"data row 902 \(line 903\): time stamp 1.757812 s goes back"):
        read_csv(export(tmp_path / "b.csv", reversed_, np.zeros(time.size), 7))


def test_irregular_log_is_refused_unless_resampling_is_asked_and_then_said(tmp_path):
    rng = np.random.default_rng(3)
    time = np.cumsum(np.full(3000, 0.01) * (1 + 0.3 * rng.uniform(-1, 1, 3000))) - 0.01
    path = export(tmp_path / "log.csv", time, 5.0 + 2.0 * time, 9)  # a ramp: linear interpolation is exact
    with pytest.raises(RecordError, match=r"non-uniform time at data row \d+ .*--resample"):
        read_csv(path)
    record = read_record(path, resample=True)
    assert record.rate == 100.0
    assert "linearly interpolated to 100 Hz" in record.metadata["resampled"]
    np.testing.assert_allclose(record["FL/drive"], (5.0 + 2.0 * record.time) * 1e-3, rtol=1e-8)


def test_time_in_milliseconds_printed_as_integers(tmp_path):
    time = np.arange(0, 4000, 2)  # ms at 500 Hz
    record = read_csv(export(tmp_path / "ms.csv", time, np.ones(time.size), 7, header="time [ms],FL/drive [mm]\n"))
    assert record.rate == 500.0 and record.n_samples == time.size


def test_a_seven_digit_export_in_mm_replays_like_the_exact_record(tmp_path, capsys):
    """Issue acceptance: the export that used to be refused at row 518 replays to TDDI <= 1e-3."""
    vehicle = load_vehicle("proton_x")
    drive = broadband_drive(vehicle.corners, duration=12.0)
    columns = [drive.time] + [drive[channel(c, "drive")] * 1e3 for c in CORNERS]
    header = "time [s]," + ",".join(f"{channel(c, 'drive')} [mm]" for c in CORNERS)
    path = tmp_path / "export.csv"
    np.savetxt(path, np.column_stack(columns), delimiter=",", fmt="%.7g", header=header, comments="")
    assert main(["replay", "--vehicle", "proton_x", "--drive", str(path), "--out", str(tmp_path / "r.csv")]) == 0
    replayed = read_record(tmp_path / "r.csv")
    reference = replay(vehicle, drive).record
    for quantity in ("sprung_acc", "unsprung_acc", "susp_travel", "tyre_force"):
        for corner in CORNERS:
            name = channel(corner, quantity)
            assert tddi(reference[name], replayed[name]) <= 1e-3, name
