"""Lab-DAQ CSV exports (rig/io/labview_csv.py), read through the CSV reader and a channel map: LabVIEW's
``Time - X`` / ``Amplitude - X`` pairs, quoted headers with units in parentheses, ISO date-time stamps, raw
voltage columns, a microcontroller's clock and its event lines, and the refusals (a pair on another time base,
a pair without its partner, bad stamps)."""

from datetime import datetime, timedelta

import numpy as np
import pytest

from rig.io.channel_map import load_channel_map, map_from_option
from rig.io.csv_format import read_csv
from rig.io.files import read_record
from rig.io.record import RecordError

RATE = 500.0
N = 600
T = np.arange(N) / RATE
FORCE = 1200.0 * np.sin(2 * np.pi * 2.0 * T)          # N
DISP_MM = 25.0 * np.sin(2 * np.pi * 2.0 * T + 0.3)     # mm


def _pairs(tmp_path, rates=(RATE, RATE, RATE), name="pairs.csv"):
    """A LabVIEW waveform export: force in N, displacement in mm, the force's raw voltage, each with its time."""
    columns = []
    for (label, values, fmt), rate in zip((("Force (N)", FORCE, "{:.4f}"), ("Displacement (mm)", DISP_MM, "{:.5f}"),
                                          ("Force raw (V)", FORCE / 400.0, "{:.6f}")), rates):
        n = round(N * rate / RATE)
        time = np.arange(n) / rate
        sampled = np.interp(time, T, values)
        columns.append((f'"Time - {label}"', [f"{t:.6f}" for t in time]))
        columns.append((f'"Amplitude - {label}"', [fmt.format(v) for v in sampled]))
    rows = max(len(c[1]) for c in columns)
    lines = [",".join(h for h, _ in columns)]
    lines += [",".join(c[1][i] if i < len(c[1]) else "" for c in columns) for i in range(rows)]
    path = tmp_path / name
    path.write_text("\n".join(lines) + "\n")
    return path


def _iso(tmp_path, jitter_row=None):
    """One wall-clock ISO time column, quoted headers with units in parentheses, a raw voltage column."""
    start = datetime(2025, 11, 14, 20, 7, 10, 531160)
    lines = ['"Timestamp","Force (kN)","Displacement (mm)","Temperature (°C)","Force (V)"']
    for i in range(N):
        moment = start + timedelta(seconds=i / RATE + (0.4 / RATE if i == jitter_row else 0.0))
        lines.append(f"{moment.isoformat(sep=' ')},{FORCE[i] / 1e3:.7f},{DISP_MM[i]:.5f},{30 + 0.01 * i:.2f},"
                     f"{FORCE[i] / 400:.6f}")
    path = tmp_path / "iso.csv"
    path.write_text("\n".join(lines) + "\n")
    return path


DYNO_MAP = ["Force (N)=damper/force", "Displacement=damper/displacement"]


def test_labview_pairs_read_through_a_map_in_si(tmp_path):
    record = read_csv(_pairs(tmp_path), channel_map=map_from_option(DYNO_MAP))
    assert record.rate == RATE and record.n_samples == N and record.start_time == 0.0
    np.testing.assert_allclose(record["damper/force"], FORCE, atol=5e-5)
    np.testing.assert_allclose(record["damper/displacement"], DISP_MM * 1e-3, atol=5e-9)
    assert record.units == {"damper/force": "N", "damper/displacement": "m"}
    assert "Force raw (V)" in record.metadata["unmapped"]


def test_raw_voltages_are_left_out_unless_mapped(tmp_path):
    path = _pairs(tmp_path)
    plain = read_record(path)
    assert plain.names == ["Force (N)", "Displacement (mm)"]
    assert "raw voltage" in plain.metadata["unmapped"] and "Force raw (V)" in plain.metadata["unmapped"]
    mapped = read_record(path, channel_map=map_from_option(["Force raw=volts"]))
    np.testing.assert_allclose(mapped["volts"], FORCE / 400.0, atol=5e-7)
    assert mapped.units["volts"] == "V"


def test_iso_stamps_give_the_rate_and_the_start(tmp_path):
    record = read_csv(_iso(tmp_path), channel_map=map_from_option(
        ["Force (kN)=damper/force", "Displacement=damper/displacement", "Temperature=damper/temperature"]))
    assert record.rate == RATE and record.start_time == 0.0
    assert record.metadata["start"] == "2025-11-14 20:07:10.531160"
    np.testing.assert_allclose(record["damper/force"], FORCE, atol=5e-5)
    np.testing.assert_allclose(record["damper/temperature"], 30 + 0.01 * np.arange(N), atol=5e-3)
    assert record.units["damper/temperature"] == "degC"


def test_irregular_iso_stamps_are_refused_with_the_row_or_resampled(tmp_path):
    path = _iso(tmp_path, jitter_row=100)
    with pytest.raises(RecordError, match=r"time column 1 .Timestamp.: non-uniform time at data row 101 \(line 102\)"):
        read_csv(path)
    record = read_csv(path, resample=True)
    assert record.rate == RATE and "irregular time stamps" in record.metadata["resampled"]


def test_a_pair_on_another_rate_is_refused_in_one_line_or_resampled(tmp_path):
    path = _pairs(tmp_path, rates=(RATE, RATE / 2, RATE))
    with pytest.raises(RecordError, match=r"'Time - Displacement \(mm\)' runs at 250 Hz .* but 'Time - Force \(N\)' "
                                          r"at 500 Hz .*--resample") as caught:
        read_csv(path, channel_map=map_from_option(DYNO_MAP))
    assert "\n" not in str(caught.value)
    record = read_csv(path, resample=True, channel_map=map_from_option(DYNO_MAP))
    assert record.rate == RATE and "resampled to 500 Hz" in record.metadata["resampled"]
    middle = slice(50, record.n_samples - 50)  # the anti-alias filter's edges aside
    np.testing.assert_allclose(record["damper/displacement"][middle], DISP_MM[middle] * 1e-3, atol=2e-5)


@pytest.mark.parametrize("text, message", [
    ('"Time - A (N)","Amplitude - A (N)","Amplitude - B (N)"\n0,1,2\n0.1,1,2\n', r"B \(N\) lack"),
    ('"Time - A (N)","Amplitude - A (N)","Other"\n0,1,2\n0.1,1,2\n', r"column 3 'Other' is not a 'Time - <name>'"),
    ('"Speed (m/s)","Force (N)"\n0,1\n0.1,2\n', r"column 1 'Speed \(m/s\)' is not a time column"),
    ('"Time (s)","Force (N)"\n0,1\n0.1,abc\n', r"column 2 'Force \(N\)', data row 2 \(line 3\): 'abc' is not a number"),
    ('"Timestamp","Force (N)"\n2025-11-14 20:07:10.5,1\n2025-11-14 20:07:10.4,2\n', r"does not increase"),
])
def test_bad_lab_exports_are_refused_naming_the_place(tmp_path, text, message):
    path = tmp_path / "bad.csv"
    path.write_text(text)
    with pytest.raises(RecordError, match=message):
        read_csv(path)


def test_contract_csv_still_goes_to_the_contract_reader(tmp_path):
    path = tmp_path / "c.csv"
    path.write_text("time [s],FL/drive\n0,1\n0.1,2\n")
    with pytest.raises(RecordError, match=r"header column 2 'FL/drive' has no unit"):
        read_csv(path)


def _as_daqs_write_it(tmp_path, force_header: str, temperature_unit: str, name: str) -> object:
    """A LabVIEW pair export whose force header may be cut short (``"Amplitude - Fc (N"``) and whose logger writes a
    temperature in bare ``C`` or ``F``."""
    temperature = 30.0 + 0.01 * np.arange(N)
    degrees = temperature if temperature_unit == "C" else temperature * 9 / 5 + 32
    columns = [(f'"Time - {force_header}"', [f"{t:.6f}" for t in T]),
               (f'"Amplitude - {force_header}"', [f"{v:.4f}" for v in FORCE]),
               (f'"Time - Temperature ({temperature_unit})"', [f"{t:.6f}" for t in T]),
               (f'"Amplitude - Temperature ({temperature_unit})"', [f"{v:.4f}" for v in degrees])]
    lines = [",".join(h for h, _ in columns)] + [",".join(c[1][i] for c in columns) for i in range(N)]
    path = tmp_path / name
    path.write_text("\n".join(lines) + "\n")
    return path


@pytest.mark.parametrize("unit", ["C", "F"])
def test_headers_as_daqs_write_them_a_cut_off_unit_and_bare_degrees(tmp_path, unit):
    path = _as_daqs_write_it(tmp_path, "Fc (N", unit, "cut.csv")
    record = read_record(path)
    assert record.units == {"Fc (N": "N", f"Temperature ({unit})": "degC"}
    np.testing.assert_allclose(record[f"Temperature ({unit})"], 30.0 + 0.01 * np.arange(N), atol=1e-4)
    mapped = read_record(path, channel_map=map_from_option(["Fc=FL/active_force", "Temperature=damper/temperature"]))
    np.testing.assert_allclose(mapped["FL/active_force"], FORCE, atol=5e-5)


def test_one_map_reads_a_measured_and_a_held_out_file_whose_headers_differ_by_a_cut_off(tmp_path):
    whole = _as_daqs_write_it(tmp_path, "Fc (N)", "C", "measured.csv")
    cut = _as_daqs_write_it(tmp_path, "Fc (N", "C", "holdout.csv")
    map_file = tmp_path / "bench.toml"
    map_file.write_text('[channels]\n"Fc (N)" = "FL/active_force"\n"Temperature (C)" = "damper/temperature"\n')
    for path in (whole, cut):
        record = read_record(path, channel_map=load_channel_map(map_file))
        np.testing.assert_allclose(record["FL/active_force"], FORCE, atol=5e-5)
    part = tmp_path / "part.toml"
    part.write_text('[channels]\n"Fc" = "FL/active_force"\n')  # a TOML map may name a unique part, as inline pairs do
    np.testing.assert_allclose(read_record(cut, channel_map=load_channel_map(part))["FL/active_force"], FORCE,
                               atol=5e-5)


def test_a_bare_degree_letter_is_refused_where_the_channel_is_no_temperature(tmp_path):
    path = _as_daqs_write_it(tmp_path, "Fc (C)", "C", "odd.csv")
    with pytest.raises(RecordError, match=r"channel 'Fc \(C\)'.*'C' is read as degrees only on a temperature channel"):
        read_record(path)


def _arduino_log(tmp_path, bad_line: str | None = None):
    """A shock dyno's Arduino log as one writes it: integer ``millis()`` stamps 10-12 ms apart, force in lbf and
    the pot in inches without units (one header with a word in parentheses), an empty thermocouple column, and
    the logger's event lines between samples where the operator changed the motor speed, and a last line cut short."""
    rng = np.random.default_rng(3)
    millis = 96 + np.cumsum(rng.choice([10, 11, 11, 12], 400))
    pot = 4.0 + 2.5 * np.sin(2 * np.pi * 1.5 * millis / 1e3)
    lbf = 15.0 * np.cos(2 * np.pi * 1.5 * millis / 1e3)
    lines = ["Millis,Load_Cell,Linear_Pot (scaled),Thermocouple"]
    for i, (ms, f, x) in enumerate(zip(millis, lbf, pot, strict=True)):
        lines.append(f"{ms},{f:.2f},{x:.3f},")
        if i in (100, 250):
            lines.append(f"{ms},Switched from {i // 100} to {i // 100 + 1},,")
    if bad_line is not None:
        lines.insert(300, bad_line)  # line 301 of the file, after two event lines: data row 298
    lines.append(f"{millis[-1] + 11},")  # the logger stopped mid-line
    path = tmp_path / "Shock_Dyno.csv"
    path.write_text("\n".join(lines) + "\n")
    return path, millis / 1e3, lbf, pot


def _imperial_map(tmp_path):
    map_file = tmp_path / "dyno.toml"
    map_file.write_text('[channels]\n"Load_Cell" = { name = "damper/force", unit = "lbf" }\n'
                        '"Linear_Pot" = { name = "damper/displacement", unit = "in" }\n')
    return load_channel_map(map_file)


def test_an_arduino_log_with_event_lines_is_read_in_si(tmp_path):
    path, seconds, lbf, pot = _arduino_log(tmp_path)
    with pytest.raises(RecordError, match=r"'Millis': non-uniform time at data row \d+ \(line \d+\).*--resample"):
        read_record(path, channel_map=_imperial_map(tmp_path))  # a loop's jitter, not a sampling clock
    record = read_record(path, resample=True, channel_map=_imperial_map(tmp_path))
    assert record.rate == pytest.approx(1e3 / 11, rel=0.02)
    assert record.metadata["events"] == ("2 event line(s) skipped: line 103: Switched from 1 to 2; "
                                         "line 254: Switched from 2 to 3")
    last = f"{1000 * seconds[-1] + 11:.0f},"
    assert record.metadata["truncated"] == f"line 404 ('{last}') holds a time and no value: left out"
    inside = record.time < seconds[-1]  # the record starts at the first stamp
    np.testing.assert_allclose(record["damper/force"][inside],
                               np.interp(record.time[inside], seconds, lbf) * 4.4482216152605, atol=0.03)
    np.testing.assert_allclose(record["damper/displacement"][inside],
                               np.interp(record.time[inside], seconds, pot) * 0.0254, atol=2e-5)


def test_a_bad_value_after_event_lines_is_named_by_its_own_line(tmp_path):
    """An event line leaves the other channels blank; a value that is not a number in a full row is refused, and
    the line named is the file's, event lines counted."""
    path, *_ = _arduino_log(tmp_path, bad_line="3300,1.5,abc,")
    with pytest.raises(RecordError, match=r"column 3 'Linear_Pot \(scaled\)', data row 298 \(line 301\): 'abc'"):
        read_record(path, resample=True, channel_map=_imperial_map(tmp_path))
