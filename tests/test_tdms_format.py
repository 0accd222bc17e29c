"""NI TDMS through npTDMS: waveform channels and time-channel groups read back in SI to float precision through a
map, rates from the file, channels at different rates brought to one, refusals that name the channel."""

import numpy as np
import pytest
from nptdms import ChannelObject, GroupObject, RootObject, TdmsWriter

from rig.io.channel_map import load_channel_map, map_from_option
from rig.io.files import read_record
from rig.io.record import RecordError
from rig.io.units import STANDARD_GRAVITY


def waveform(group, name, values, unit, rate, start=0.0):
    """A channel as NI DAQ software logs it: samples with wf_increment / wf_start_offset and a unit_string."""
    return ChannelObject(group, name, np.asarray(values, dtype=float),
                         {"unit_string": unit, "wf_increment": 1.0 / rate, "wf_start_offset": start})


def write_tdms(path, objects):
    with TdmsWriter(path) as writer:
        writer.write_segment([RootObject({"vehicle": "proton_x", "operator": "rig lab"}), *objects])
    return path


def test_daq_waveforms_read_back_in_si_through_a_map(tmp_path):
    rng = np.random.default_rng(7)
    disp, acc = rng.standard_normal((2, 3000))
    path = write_tdms(tmp_path / "daq.tdms", [
        GroupObject("Rig"), waveform("Rig", "PostDisp_LF", 12 * disp, "mm", 1000.0, start=0.5),
        waveform("Rig", "ACC_LF_BODY", 0.4 * acc, "g", 1000.0, start=0.5),
        waveform("Rig", "Oil_Temp", np.full(3000, 70.0), "degC", 1000.0, start=0.5)])
    map_path = tmp_path / "map.toml"
    map_path.write_text('[channels]\n"PostDisp_LF" = "FL/actuator_disp"\n'
                        '"ACC_LF_BODY" = { name = "FL/sprung_acc", unit = "g", scale = -1.0 }\n')
    record = read_record(path, channel_map=load_channel_map(map_path))
    assert record.rate == 1000.0 and record.start_time == 0.5 and record.n_samples == 3000
    np.testing.assert_allclose(record["FL/actuator_disp"], 12 * disp * 1e-3, rtol=1e-15, atol=0)
    np.testing.assert_allclose(record["FL/sprung_acc"], -0.4 * acc * STANDARD_GRAVITY, rtol=1e-15, atol=0)
    assert record.metadata["vehicle"] == "proton_x"
    assert record.metadata["unmapped"].endswith("ignored: Oil_Temp")


def test_a_group_timed_by_a_time_channel_in_ms(tmp_path):
    time_ms = np.arange(2560) * 1000 / 512
    path = write_tdms(tmp_path / "log.tdms", [
        ChannelObject("Log", "Time", time_ms, {"unit_string": "ms"}),
        ChannelObject("Log", "FL/drive", 3 * np.sin(time_ms / 100), {"unit_string": "mm"})])
    record = read_record(path)
    assert record.names == ["FL/drive"]
    assert record.rate == 512.0 and record.n_samples == 2560
    np.testing.assert_allclose(record["FL/drive"], 3e-3 * np.sin(time_ms / 100), rtol=1e-15, atol=0)


def test_channels_at_two_rates_come_to_the_rate_most_have(tmp_path):
    t_fast, t_slow = np.arange(8192) / 2048, np.arange(2048) / 512
    path = write_tdms(tmp_path / "daq.tdms", [
        waveform("Fast", "ACC_LF_BODY", np.sin(2 * np.pi * 10 * t_fast) + 0.5 * np.sin(2 * np.pi * 400 * t_fast),
                 "g", 2048.0),
        waveform("Slow", "PostDisp_LF", np.sin(2 * np.pi * 2 * t_slow), "mm", 512.0),
        waveform("Slow", "PostDisp_RF", np.cos(2 * np.pi * 2 * t_slow), "mm", 512.0)])
    record = read_record(path)
    assert record.rate == 512.0
    assert record.metadata["resampled"].startswith("ACC_LF_BODY at 2048 Hz resampled to 512 Hz (anti-alias filter")
    inner = slice(256, -256)
    error = record["ACC_LF_BODY"][inner] / STANDARD_GRAVITY - np.sin(2 * np.pi * 10 * record.time[inner])
    assert np.abs(error).max() < 2e-3  # the 400 Hz tone is filtered out, not folded to 112 Hz


def test_groups_with_absolute_time_keep_their_offsets(tmp_path):
    """Two logs of one test, started 0.25 s apart on the DAQ clock (absolute time stamps in one group, a
    waveform's wf_start_time in the other): the record covers their common span, each sample at its moment."""
    t0 = np.datetime64("2026-11-24T08:00:00.000000")
    stamps = t0 + (np.arange(2048) * 1e6 / 512).astype("timedelta64[us]")
    late = np.arange(2048) / 512 + 0.25
    path = write_tdms(tmp_path / "two_logs.tdms", [
        ChannelObject("Posts", "Time", stamps), ChannelObject("Posts", "FL/actuator_disp", np.arange(2048) / 512.0,
                                                              {"unit_string": "m"}),
        ChannelObject("Body", "FL/sprung_acc", late, {"unit_string": "m/s^2", "wf_increment": 1 / 512,
                                                      "wf_start_offset": 0.0,
                                                      "wf_start_time": t0 + np.timedelta64(250, "ms")})])
    record = read_record(path)
    assert record.start_time == pytest.approx(0.25) and record.n_samples == 2048 - 128
    np.testing.assert_allclose(record["FL/actuator_disp"], record.time, atol=1e-12)
    np.testing.assert_allclose(record["FL/sprung_acc"], record.time, atol=1e-12)


def test_an_upsampled_group_ends_where_its_data_end(tmp_path):
    """A 256 Hz group brought to 1024 Hz: the resampler's padding past its last sample is not read as data."""
    path = write_tdms(tmp_path / "daq.tdms", [
        waveform("Fast", "A", np.zeros(4096), "m", 1024.0), waveform("Fast", "B", np.zeros(4096), "m", 1024.0),
        waveform("Slow", "C", np.ones(1024), "m", 256.0)])
    record = read_record(path)
    assert record.rate == 1024.0 and record.time[-1] <= 1023 / 256 + 1e-9


def test_refusals_name_the_channel(tmp_path):
    path = write_tdms(tmp_path / "a.tdms", [waveform("Rig", "ACC_LF_BODY", np.zeros(100), "G", 512.0)])
    with pytest.raises(RecordError, match=r"a.tdms: channel 'ACC_LF_BODY' \(group 'Rig'\): unknown unit 'G'"):
        read_record(path)
    path = write_tdms(tmp_path / "b.tdms", [ChannelObject("Rig", "PostDisp_LF", np.zeros(100), {"unit_string": "mm"})])
    with pytest.raises(RecordError, match=r"b.tdms: channel 'PostDisp_LF' of group 'Rig' has no wf_increment "
                                          r"property and its group has no time channel$"):
        read_record(path)
    path = write_tdms(tmp_path / "c.tdms", [waveform("Rig", "PostDisp_LF", np.zeros(100), "", 512.0)])
    with pytest.raises(RecordError, match=r"c.tdms: channel 'PostDisp_LF' \(group 'Rig'\) without a unit cannot be "
                                          r"'FL/actuator_disp', which is in m; give its unit in a channel map$"):
        read_record(path, channel_map=map_from_option(["PostDisp_LF=FL/actuator_disp"]))
    (tmp_path / "d.tdms").write_text("not a TDMS file, " * 4)
    with pytest.raises(RecordError, match=r"d.tdms: not a readable TDMS file"):
        read_record(tmp_path / "d.tdms")
    (tmp_path / "e.tdms").write_bytes(b"")
    with pytest.raises(RecordError, match=r"e.tdms: TDMS file has no channels"):
        read_record(tmp_path / "e.tdms")

