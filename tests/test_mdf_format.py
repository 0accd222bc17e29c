"""ASAM MDF4 through asammdf: DAQ files read back in SI to float precision through a map, multi-rate groups
brought to one rate with an anti-alias filter, our writer round-trips, and the issue's acceptance test: an MDF4
file with DAQ names in mm, mapped, replays like the exact record."""

import numpy as np
import pytest
from asammdf import MDF, Signal

from rig.sim.broadband import broadband_drive
from rig.cli.main import main
from rig.io.channel_map import load_channel_map
from rig.io.channels import CORNERS, channel
from rig.io.files import read_record, write_record
from rig.io.record import Record, RecordError
from rig.io.units import STANDARD_GRAVITY
from rig.signal.metrics import tddi
from rig.sim.replay import replay
from rig.vehicle.vehicle_file import load_vehicle

DAQ_CORNERS = {"FL": "LF", "FR": "RF", "RL": "LR", "RR": "RR"}  # the DAQ's corner names


def write_daq_mdf(path, groups, comment="<HDcomment><TX>rig test</TX></HDcomment>"):
    """An MDF4 file as a DAQ writes it: ``groups`` is a list of (rate Hz, duration s, {name: (values, unit)})."""
    mdf = MDF(version="4.10")
    mdf.header.comment = comment
    for rate, duration, channels in groups:
        time = np.arange(round(duration * rate)) / rate
        mdf.append([Signal(np.asarray(values(time) if callable(values) else values), time, name=name, unit=unit)
                    for name, (values, unit) in channels.items()])
    mdf.save(path, overwrite=True)
    return path


def daq_map(tmp_path, text):
    path = tmp_path / "map.toml"
    path.write_text("[channels]\n" + text)
    return load_channel_map(path)


def test_daq_names_and_units_read_back_in_si_to_float_precision(tmp_path):
    rng = np.random.default_rng(4)
    disp, acc, force = rng.standard_normal((3, 2048))
    path = write_daq_mdf(tmp_path / "daq.mf4", [(1024.0, 2.0, {
        "PostDisp_LF": (20 * disp, "mm"), "ACC_LF_BODY": (0.3 * acc, "g"), "LoadCell_LF": (4 * force, "kN"),
        "CAN_Speed": (np.full(2048, 13.9), "km/h")})])
    channel_map = daq_map(tmp_path, '"PostDisp_LF" = "FL/actuator_disp"\n'
                                    '"ACC_LF_BODY" = { name = "FL/sprung_acc", unit = "g", scale = -1.0 }\n'
                                    '"LoadCell_LF" = "FL/actuator_force"\n')
    record = read_record(path, channel_map=channel_map)
    assert record.rate == 1024.0 and record.start_time == 0.0 and record.n_samples == 2048
    assert record.units == {"FL/actuator_disp": "m", "FL/sprung_acc": "m/s^2", "FL/actuator_force": "N"}
    np.testing.assert_allclose(record["FL/actuator_disp"], 20 * disp * 1e-3, rtol=1e-15, atol=0)
    np.testing.assert_allclose(record["FL/sprung_acc"], -0.3 * acc * STANDARD_GRAVITY, rtol=1e-15, atol=0)
    np.testing.assert_allclose(record["FL/actuator_force"], 4 * force * 1e3, rtol=1e-15, atol=0)
    assert record.metadata["unmapped"].endswith("ignored: CAN_Speed")  # km/h is not known, and not needed


def test_our_writer_round_trips_exactly_with_metadata(tmp_path):
    rng = np.random.default_rng(5)
    original = Record(512.0, {"FL/drive": 0.01 * rng.standard_normal(3000), "FL/sprung_acc": rng.standard_normal(3000)},
                      metadata={"vehicle": "proton_x", "test": "rig"}, start_time=-0.25)
    write_record(tmp_path / "r.mf4", original, units={"FL/drive": "mm"})
    with MDF(tmp_path / "r.mf4") as mdf:  # what another tool sees: the units asked for
        assert mdf.get("FL/drive").unit == "mm"
    again = read_record(tmp_path / "r.mf4")
    assert again.rate == 512.0 and again.start_time == -0.25
    assert again.metadata == {"vehicle": "proton_x", "test": "rig"}
    np.testing.assert_allclose(again["FL/drive"], original["FL/drive"], rtol=1e-15, atol=0)
    np.testing.assert_array_equal(again["FL/sprung_acc"], original["FL/sprung_acc"])


def test_multi_rate_groups_are_decimated_with_an_anti_alias_filter(tmp_path):
    """2048 Hz body accelerometer, three 512 Hz post LVDTs: the record takes 512 Hz (most channels), and the
    400 Hz tone above the new 256 Hz Nyquist frequency does not fold back to 112 Hz."""
    duration = 8.0
    posts = {f"PostDisp_{DAQ_CORNERS[c]}": (lambda t, k=k: 5 * np.sin(2 * np.pi * (1 + k) * t), "mm")
             for k, c in enumerate(CORNERS[:3])}
    fast = {"ACC_LF_BODY": (lambda t: np.sin(2 * np.pi * 10 * t) + 0.5 * np.sin(2 * np.pi * 400 * t), "g")}
    path = write_daq_mdf(tmp_path / "daq.mf4", [(2048.0, duration, fast), (512.0, duration, posts)])
    channel_map = daq_map(tmp_path, '"ACC_LF_BODY" = "FL/sprung_acc"\n' + "".join(
        f'"PostDisp_{DAQ_CORNERS[c]}" = "{c}/actuator_disp"\n' for c in CORNERS[:3]))
    record = read_record(path, channel_map=channel_map)
    assert record.rate == 512.0 and record.n_samples == 512 * duration
    assert "FL/sprung_acc at 2048 Hz resampled to 512 Hz (anti-alias filter: scipy.signal.resample_poly" \
        in record.metadata["resampled"]
    np.testing.assert_allclose(record["FR/actuator_disp"], 5e-3 * np.sin(2 * np.pi * 2 * record.time),
                               rtol=1e-15, atol=0)
    inner = slice(256, -256)  # away from the ends, where the filter sees its padding
    acc = record["FL/sprung_acc"] / STANDARD_GRAVITY
    error = acc[inner] - np.sin(2 * np.pi * 10 * record.time[inner])
    assert np.abs(error).max() < 2e-3  # amplitude and phase of the 10 Hz sine kept
    spectrum = np.abs(np.fft.rfft(acc[inner])) * 2 / acc[inner].size
    freqs = np.fft.rfftfreq(acc[inner].size, 1 / record.rate)
    alias = spectrum[np.argmin(np.abs(freqs - 112.0))]
    naive = np.abs(np.fft.rfft((np.sin(2 * np.pi * 400 * record.time) * 0.5)[inner]))[np.argmin(np.abs(freqs - 112))]
    assert naive * 2 / acc[inner].size == pytest.approx(0.5, rel=1e-2)  # every 4th sample alone would alias it
    assert alias < 1e-3
    print(f"10 Hz max error {np.abs(error).max():.2e} g, 400 Hz tone folded to 112 Hz: {alias:.2e} g "
          "(0.5 g unfiltered)")


def test_a_slow_minority_group_is_interpolated_up(tmp_path):
    accs = {f"ACC_{DAQ_CORNERS[c]}_BODY": (lambda t: np.sin(2 * np.pi * 10 * t), "g") for c in CORNERS}
    slow = {"PostDisp_LF": (lambda t: 5 * np.sin(2 * np.pi * 3 * t), "mm")}
    path = write_daq_mdf(tmp_path / "daq.mf4", [(512.0, 4.0, slow), (2048.0, 4.0, accs)])
    record = read_record(path)  # no map: every channel, under the file's names
    assert record.rate == 2048.0
    assert record.metadata["resampled"].startswith("PostDisp_LF at 512 Hz resampled to 2048 Hz")
    inner = slice(1024, -1024)
    error = record["PostDisp_LF"][inner] - 5e-3 * np.sin(2 * np.pi * 3 * record.time[inner])
    assert np.abs(error).max() < 5e-3 * 1e-3
    np.testing.assert_array_equal(record["ACC_LF_BODY"], STANDARD_GRAVITY * np.sin(2 * np.pi * 10 * record.time))


def test_groups_covering_different_spans_keep_the_common_one(tmp_path):
    path = write_daq_mdf(tmp_path / "daq.mf4", [(512.0, 3.0, {"A": (lambda t: t, "m")}),
                                                 (512.0, 2.0, {"B": (lambda t: 2 * t, "m")})])
    record = read_record(path)
    assert record.n_samples == 1024
    np.testing.assert_array_equal(record["A"], record.time)


def test_refusals_name_the_channel_or_group(tmp_path):
    path = write_daq_mdf(tmp_path / "daq.mf4", [(512.0, 1.0, {"ACC_LF_BODY": (np.zeros(512), "furlong/s^2")})])
    with pytest.raises(RecordError, match=r"daq.mf4: channel 'ACC_LF_BODY' \(group 0\): unknown unit 'furlong/s\^2'"):
        read_record(path)
    mdf = MDF(version="4.10")
    time = np.sort(np.random.default_rng(6).uniform(0, 1, 300))
    mdf.append([Signal(2 * time, time, name="Drive_LF", unit="mm")])
    mdf.save(tmp_path / "irregular.mf4", overwrite=True)
    with pytest.raises(RecordError, match=r"irregular.mf4: group 0 \(Drive_LF\): non-uniform time at sample \d+: "
                                          r".*resample it \(--resample\)$"):
        read_record(tmp_path / "irregular.mf4")
    record = read_record(tmp_path / "irregular.mf4", resample=True)
    assert "group 0: irregular time stamps" in record.metadata["resampled"]
    np.testing.assert_allclose(record["Drive_LF"], 2e-3 * record.time, rtol=1e-9)
    (tmp_path / "text.mf4").write_text("not an MDF file")
    with pytest.raises(RecordError, match=r"text.mf4: not a readable MDF file"):
        read_record(tmp_path / "text.mf4")


def test_an_mdf4_file_with_daq_names_in_mm_mapped_replays_like_the_exact_record(tmp_path, capsys):
    """Issue acceptance: DAQ names, post displacements in mm, a body accelerometer in g nobody maps."""
    vehicle = load_vehicle("proton_x")
    drive = broadband_drive(vehicle.corners, duration=12.0)
    daq = {f"PostCmd_{DAQ_CORNERS[c]}": (drive[channel(c, "drive")] * 1e3, "mm") for c in CORNERS}
    daq["ACC_LF_BODY"] = (np.zeros(drive.n_samples), "g")
    path = write_daq_mdf(tmp_path / "daq.mf4", [(drive.rate, drive.duration, daq)])
    (tmp_path / "map.toml").write_text("[channels]\n" + "".join(
        f'"PostCmd_{DAQ_CORNERS[c]}" = "{c}/drive"\n' for c in CORNERS))
    out = tmp_path / "r.mf4"
    assert main(["replay", "--vehicle", "proton_x", "--drive", str(path), "--out", str(out),
                 "--map", str(tmp_path / "map.toml")]) == 0
    assert capsys.readouterr().err.count("unmapped: 1 channel(s) not in") == 1
    replayed = read_record(out)
    reference = replay(vehicle, drive).record
    worst = 0.0
    for quantity in ("sprung_acc", "unsprung_acc", "susp_travel", "tyre_force"):
        for corner in CORNERS:
            name = channel(corner, quantity)
            worst = max(worst, tddi(reference[name], replayed[name]))
    assert worst <= 1e-3
    print(f"worst TDDI of the mapped MDF4 replay against the exact record: {worst:.2e}")
