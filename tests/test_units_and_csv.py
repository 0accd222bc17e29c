"""CSV record contract: unit conversion on import, round trips, and every bad-input message."""

import numpy as np
import pytest

from rig.io.csv_format import read_csv, write_csv
from rig.io.record import Record, RecordError
from rig.io.units import STANDARD_GRAVITY, UnitError, to_si

HEADER = "time [s],FL/drive [mm],FL/sprung_acc [g],FL/tyre_force [kN]\n"


def write(tmp_path, text, name="r.csv"):
    path = tmp_path / name
    path.write_text(text)
    return path


def test_units_convert_to_si_and_unknown_units_are_refused():
    assert to_si("mm") == (1e-3, "m")
    assert to_si("g") == (STANDARD_GRAVITY, "m/s^2")
    assert to_si("kN") == (1e3, "N")
    with pytest.raises(UnitError, match="unknown unit 'furlong'"):
        to_si("furlong")
    with pytest.raises(UnitError, match="unknown unit 'G'"):  # case-sensitive: G is not g
        to_si("G")
    # US dynamometers log in pounds-force and inches: the exact definitions (NIST SP 811)
    assert to_si("lbf") == (0.45359237 * STANDARD_GRAVITY, "N")
    assert to_si("in") == (0.0254, "m") and to_si("in/s") == (0.0254, "m/s")
    assert to_si("us") == (1e-6, "s")


def test_read_converts_units_and_keeps_metadata(tmp_path):
    path = write(tmp_path, "# vehicle: proton_x\n# test: rig\n" + HEADER + "0,1.5,0.5,4\n0.002,2,1,4.5\n0.004,0,0,3\n")
    record = read_csv(path)
    assert record.rate == pytest.approx(500.0)
    assert record.metadata == {"vehicle": "proton_x", "test": "rig"}
    np.testing.assert_allclose(record["FL/drive"], [1.5e-3, 2e-3, 0.0])
    np.testing.assert_allclose(record["FL/sprung_acc"], [0.5 * STANDARD_GRAVITY, STANDARD_GRAVITY, 0.0])
    np.testing.assert_allclose(record["FL/tyre_force"], [4000, 4500, 3000])
    assert record.units["FL/sprung_acc"] == "m/s^2"


def test_round_trip_preserves_values_to_the_written_precision(tmp_path):
    rng = np.random.default_rng(0)
    original = Record(512.0, {"FL/sprung_acc": rng.standard_normal(1000),
                              "RR/susp_travel": 0.01 * rng.standard_normal(1000)},
                      metadata={"vehicle": "proton_x"})
    path = tmp_path / "round.csv"
    write_csv(path, original, units={"RR/susp_travel": "mm"})
    again = read_csv(path)
    assert again.rate == 512.0
    assert again.metadata == original.metadata
    for name in original.names:  # 10 significant digits written
        np.testing.assert_allclose(again[name], original[name], rtol=1e-9, atol=1e-12)


@pytest.mark.parametrize(
    "text, message",
    [
        (HEADER + "0,1,nan,4\n0.002,1,1,4\n",
         r"column 'FL/sprung_acc' has a non-finite value \(nan\) in data row 1 \(line 2\)"),
        (HEADER + "0,1,1,4\n0.002,1,inf,4\n",
         r"column 'FL/sprung_acc' has a non-finite value \(inf\) in data row 2 \(line 3\)"),
        (HEADER + "0,1,1,4\n0.002,1,1,4\n0.005,1,1,4\n0.006,1,1,4\n", r"non-uniform time at data row 3 \(line 4\)"),
        ("time [s],FL/drive [inch]\n0,1\n0.1,2\n", r"channel 'FL/drive' \(header column 2\): unknown unit 'inch'"),
        ("time [s],FL/drive\n0,1\n0.1,2\n", r"header column 2 'FL/drive' has no unit"),
        ("time [s],FL/drive [m],FL/drive [mm]\n0,1,1\n0.1,2,2\n",
         r"duplicate channel 'FL/drive' in header columns 2 and 3"),
        ("x [m],FL/drive [m]\n0,1\n0.1,2\n", r"first column must be 'time \[s\]'"),
        (HEADER + "0,1,1,4\n0.002,1,abc,4\n", r"data row 2 \(line 3\), column 3: 'abc' is not a number"),
        (HEADER + "0,1,1\n0.002,1,1,4\n", r"data row 1 \(line 2\) has 3 fields, expected 4"),
        (HEADER + "0,1,1,4\n0,1,1,4\n", r"time does not increase"),
    ],
)
def test_bad_csv_is_refused_with_a_message_naming_the_place(tmp_path, text, message):
    with pytest.raises(RecordError, match=message):
        read_csv(write(tmp_path, text))


def test_missing_corner_is_named():
    record = Record(100.0, {"FL/drive": np.zeros(3), "FR/drive": np.zeros(3), "RL/drive": np.zeros(3)})
    with pytest.raises(RecordError, match=r"no 'drive' channel for corner\(s\) RR \(expected RR/drive\)"):
        record.quantity("drive")


def test_failed_write_keeps_the_existing_file(tmp_path):
    path = write(tmp_path, "precious\n", "out.csv")
    record = Record(100.0, {"FL/drive": np.zeros(3)})
    with pytest.raises(UnitError):
        write_csv(path, record, units={"FL/drive": "kN"})  # a force unit for a displacement
    assert path.read_text() == "precious\n"
    assert list(tmp_path.iterdir()) == [path]


@pytest.mark.parametrize("encoding", ["utf-16", "cp1252", "utf-8-sig"])
def test_text_exports_in_other_encodings_are_read(tmp_path, encoding):
    text = "# operator: Jürgen Müller\n# site: Prüfstand 2\n" + HEADER + "0,1.5,0.5,4\n0.002,2,1,4.5\n0.004,0,0,3\n"
    path = tmp_path / "r.csv"
    path.write_bytes(text.encode(encoding))
    record = read_csv(path)
    assert record.metadata["operator"] == "Jürgen Müller"
    np.testing.assert_allclose(record["FL/drive"], [1.5e-3, 2e-3, 0.0])


def test_a_binary_file_named_csv_is_refused_as_binary(tmp_path):
    path = tmp_path / "r.csv"
    path.write_bytes(b"\x89HDF\r\n\x1a\n\x00\x00\x00" + bytes(200))
    with pytest.raises(RecordError, match=r"r.csv: binary content \(a zero byte at offset 8\), not a text CSV"):
        read_csv(path)


def test_result_files_are_readable_as_the_umask_says(tmp_path):
    import os

    from rig.io.atomic import write_text_atomic

    old = os.umask(0o027)
    try:
        write_text_atomic(tmp_path / "a.json", "{}")
        os.umask(0o022)
        write_text_atomic(tmp_path / "b.json", "{}")
    finally:
        os.umask(old)
    assert (tmp_path / "a.json").stat().st_mode & 0o777 == 0o640
    assert (tmp_path / "b.json").stat().st_mode & 0o777 == 0o644
