"""OpenCRG reader: the ASAM belgian block sample checked against its header and a direct read, synthetic formats."""

from __future__ import annotations

import re
import warnings
from pathlib import Path

import numpy as np
import pytest

from rig.road.opencrg import CrgSurface, read_opencrg

BELGIAN_BLOCK = "belgian_block.crg"
N_CHANNELS = 342  # D:reference line phi, then D:long section 1..341
# The shared copy went through a CRLF -> LF conversion: the CR of each CR LF pair in the float data is gone. Offsets
# (from the start of the data block) of the LF bytes that lost their CR, found by hand: before each, the big-endian
# float32 records decode to elevations near 2.1 m, after it only with a one-byte shift.
LOST_CR_BEFORE = (125998, 253333, 352452, 865607, 1118270, 1280329)
FIRST_DAMAGED_RECORD = LOST_CR_BEFORE[0] // (4 * N_CHANNELS)  # 92


@pytest.fixture(scope="module")
def crg_path(real_data) -> Path:
    path = real_data / BELGIAN_BLOCK
    if not path.is_file():
        pytest.skip(f"{path} not found")
    return path


@pytest.fixture(scope="module")
def surface(crg_path) -> CrgSurface:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the restored CR bytes; checked in test_lost_carriage_returns_are_reported
        return read_opencrg(crg_path)


def _header_value(path: Path, key: str) -> float:
    text = path.read_bytes().split(b"$$$$")[0].decode("latin-1")
    return float(re.search(rf"^\s*{key}\s*=\s*(\S+)", text, re.MULTILINE | re.IGNORECASE).group(1))


def _data_offset(raw: bytes) -> int:
    return raw.index(b"\n", raw.index(b"$$$$")) + 1


def _rms_mm(x: np.ndarray) -> float:
    return 1e3 * float(np.sqrt(np.mean((x - x.mean()) ** 2)))


def test_u_axis_matches_the_header(surface, crg_path):
    start = _header_value(crg_path, "reference_line_start_u")
    end = _header_value(crg_path, "reference_line_end_u")
    increment = _header_value(crg_path, "reference_line_increment")
    assert (start, end, increment) == (730.0, 740.0, 0.01)
    assert surface.u.size == round((end - start) / increment) + 1 == 1001
    assert surface.u[0] == start
    assert surface.u[-1] == pytest.approx(end, abs=1e-9)
    np.testing.assert_allclose(np.diff(surface.u), increment, atol=1e-9)


def test_v_axis_and_grid_shape(surface, crg_path):
    assert surface.v[0] == pytest.approx(_header_value(crg_path, "long_section_v_right")) == pytest.approx(-1.7)
    assert surface.v[-1] == pytest.approx(_header_value(crg_path, "long_section_v_left")) == pytest.approx(1.7)
    np.testing.assert_allclose(np.diff(surface.v), _header_value(crg_path, "long_section_v_increment"), atol=1e-9)
    assert surface.z.shape == (1001, 341)
    assert surface.header["reference_line_increment"] == "1.0000000000000000e-002"


def test_wheel_tracks_are_finite_and_elevations_plausible(surface):
    tracks = np.abs(np.abs(surface.v) - 0.75) <= 0.1 + 1e-9
    assert tracks.sum() == 42
    assert np.isfinite(surface.z[:, tracks]).all()
    finite = surface.z[np.isfinite(surface.z)]
    assert finite.min() > 2.0 and finite.max() < 2.2  # elevation of the scan, 15 cm from lowest to highest point
    # cobbles: centimetre steps between neighbouring points, no jumps of misread bytes
    assert np.nanmax(np.abs(np.diff(surface.z, axis=0))) < 0.04
    assert np.nanmax(np.abs(np.diff(surface.z, axis=1))) < 0.04
    assert np.isnan(surface.z[:, 0]).all()  # the right edge has no data


def test_records_before_the_damage_match_a_direct_read(surface, crg_path):
    raw = crg_path.read_bytes()
    direct = np.fromfile(crg_path, dtype=">f4", count=FIRST_DAMAGED_RECORD * N_CHANNELS, offset=_data_offset(raw))
    direct = direct.reshape(FIRST_DAMAGED_RECORD, N_CHANNELS)[:, 1:]  # drop the phi channel
    np.testing.assert_array_equal(surface.z[:FIRST_DAMAGED_RECORD], direct)


def test_long_section_rms_matches_a_direct_read(surface, crg_path):
    raw = crg_path.read_bytes()
    data = bytearray(raw[_data_offset(raw):])
    for lf in reversed(LOST_CR_BEFORE):
        assert data[lf] == 0x0A
        data.insert(lf, 0x0D)
    assert len(data) == 1001 * N_CHANNELS * 4 + 72 + 1  # records, NaN padding to 80-byte blocks, final newline
    direct = np.frombuffer(bytes(data), dtype=">f4", count=1001 * N_CHANNELS).reshape(1001, N_CHANNELS)
    left, right = direct[:, 1 + 245], direct[:, 1 + 95]  # long sections 246 (v = +0.75) and 96 (v = -0.75)
    assert _rms_mm(surface.long_section(0.75)) == pytest.approx(_rms_mm(left), rel=1e-6)
    assert _rms_mm(surface.long_section(-0.75)) == pytest.approx(_rms_mm(right), rel=1e-6)
    assert _rms_mm(left) == pytest.approx(25.65, abs=0.01)
    assert _rms_mm(right) == pytest.approx(25.71, abs=0.01)


def test_lost_carriage_returns_are_reported(crg_path):
    with pytest.warns(UserWarning, match="lost 6 CR byte"):
        read_opencrg(crg_path)


def test_long_section_interpolates_across_v_and_checks_its_range(surface):
    j = int(np.argmin(np.abs(surface.v - 0.75)))
    np.testing.assert_allclose(surface.long_section(0.755), 0.5 * (surface.z[:, j] + surface.z[:, j + 1]))
    with pytest.raises(ValueError, match=r"v_offset = 1.8 m is outside"):
        surface.long_section(1.8)
    with pytest.raises(ValueError, match=r"v_offset = -1.7 m has no data"):
        surface.long_section(-1.7)


def test_long_section_fills_missing_points_along_u():
    surface = CrgSurface(u=np.arange(5.0), v=np.array([-1.0, 1.0]),
                         z=np.array([[np.nan, 0], [1, 0], [np.nan, 0], [3, 0], [np.nan, 0]]), header={})
    np.testing.assert_allclose(surface.long_section(-1.0), [1, 1, 2, 3, 3])
    np.testing.assert_allclose(surface.long_section(0.0), [0.5, 0.5, 1.0, 1.5, 1.5])


def test_truncated_and_headerless_files_are_rejected(crg_path, tmp_path):
    raw = crg_path.read_bytes()
    truncated = tmp_path / "truncated.crg"
    truncated.write_bytes(raw[:_data_offset(raw) + 100_000])
    with pytest.raises(ValueError, match=r"binary data block is truncated: 100000 bytes, 1369368 needed"):
        read_opencrg(truncated)
    headerless = tmp_path / "headerless.crg"
    headerless.write_bytes(raw[:5000])
    with pytest.raises(ValueError, match=r"no end-of-header line"):
        read_opencrg(headerless)


def _write_crg(path: Path, fmt: str, definitions: list[str], data: bytes, road: str = "") -> Path:
    text = (f"$CT\nsynthetic surface ! not a key = value\n$\n$ROAD_CRG\n{road}$\n$KD_DEFINITION\n#:{fmt}\n"
            + "".join(f"D:{d}\n" for d in definitions) + "$\n" + "$" * 72 + "\n")
    path.write_bytes(text.encode() + data)
    return path


GRID = np.array([[0.010, 0.020, np.nan], [0.011, -0.021, 0.031], [0.012, 0.022, 0.032], [0.013, 0.023, 0.033]])


def test_text_format_with_sections_by_position(tmp_path):
    # LRFI: 10-character fields, 8 per 80-column line (a record of 10 channels takes two lines); sections listed out
    # of order, a missing value written as text
    v = np.array([0.5, -0.5, 0.0, 1.0, -1.0, 1.5, -1.5, 2.0, -2.0])
    z = 0.01 * np.arange(4)[:, None] + 0.001 * v[None, :]
    z[1, 2] = np.nan
    definitions = ["reference line u,m"] + [f"long section at v = {x},m" for x in v]
    lines = []
    for i, row in enumerate(z):
        fields = [f"{10.0 + 0.5 * i:10.4f}"] + [" *missing*" if np.isnan(x) else f"{x:10.6f}" for x in row]
        lines += ["".join(fields[:8]), "".join(fields[8:])]
    surface = read_opencrg(_write_crg(tmp_path / "text.crg", "LRFI", definitions, ("\n".join(lines) + "\n").encode()))
    np.testing.assert_allclose(surface.u, [10.0, 10.5, 11.0, 11.5])
    np.testing.assert_allclose(surface.v, np.sort(v))
    np.testing.assert_allclose(surface.z, z[:, np.argsort(v)], atol=1e-9)
    assert np.isnan(surface.z[1, 4])  # the missing value, at v = 0.0


def test_binary_double_format_with_numbered_sections(tmp_path):
    road = ("REFERENCE_LINE_START_U = 2.0\nreference_line_end_u = 2.3 ! comment\nreference_line_increment = 0.1\n"
            "long_section_v_right = -0.2\nlong_section_v_left = 0.2\n")
    definitions = ["reference line phi,rad", "long section 1,m", "long section 2,m", "long section 3,m"]
    data = np.column_stack([np.full(4, 1.0), GRID]).astype(">f8").tobytes()
    surface = read_opencrg(_write_crg(tmp_path / "double.crg", "KDBI", definitions, data, road))
    np.testing.assert_allclose(surface.u, [2.0, 2.1, 2.2, 2.3])
    np.testing.assert_allclose(surface.v, [-0.2, 0.0, 0.2])
    np.testing.assert_array_equal(surface.z, GRID)
    assert surface.header["reference_line_start_u"] == "2.0"
    assert surface.header["reference_line_end_u"] == "2.3"


def test_lost_carriage_returns_are_restored(tmp_path):
    grid = GRID.copy()
    grid[2, 1] = np.frombuffer(b"\x3c\x23\x0d\x0a", dtype=">f4")[0]  # 0.00996 m, stored with a CR LF pair
    road = ("reference_line_end_u = 3.0\nreference_line_increment = 1.0\nlong_section_v_right = -0.5\n"
            "long_section_v_increment = 0.5\n")
    definitions = ["long section 1,m", "long section 2,m", "long section 3,m"]
    data = grid.astype(">f4").tobytes() + np.full(8, np.nan, ">f4").tobytes()  # padded to 80 bytes
    clean = read_opencrg(_write_crg(tmp_path / "clean.crg", "KRBI", definitions, data, road))
    np.testing.assert_array_equal(clean.z, grid.astype(np.float32))
    damaged = _write_crg(tmp_path / "damaged.crg", "KRBI", definitions, data.replace(b"\r\n", b"\n"), road)
    with pytest.warns(UserWarning, match=r"lost 1 CR byte.*offsets \[30\]"):
        restored = read_opencrg(damaged)
    np.testing.assert_array_equal(restored.z, clean.z)
    truncated = _write_crg(tmp_path / "truncated.crg", "KRBI", definitions, data[:40], road)
    with pytest.raises(ValueError, match="truncated: 40 bytes, 48 needed for 4 u positions x 3 channels"):
        read_opencrg(truncated)
