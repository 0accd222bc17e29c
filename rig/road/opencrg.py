"""Road-surface grids from ASAM OpenCRG files.

Format: "ASAM OpenCRG 1.2 file format" (ASAM e.V., https://www.asam.net/standards/detail/opencrg/).

``read_opencrg`` returns the elevation grid ``z[i_u, j_v]`` in metres on the file's regular grid: ``u`` along the
reference line (m, from ``reference_line_start_u``), ``v`` across it (m, left positive). Version handled: OpenCRG 1.2
(the layout read by its C loader, crgLoader.c) in the four data formats of the specification: binary ``KRBI`` /
``KDBI`` (big-endian float32 / float64) and text ``LRFI`` / ``LDFI`` (fixed 10 / 20 character fields in 80 column
lines). Long sections are defined by number (``D:long section N``, placed by ``long_section_v_right/left/increment``)
or by position (``D:long section at v = X``); u comes from the header or from a ``D:reference line u`` channel. One
record holds one value per channel in the order of the ``D:`` lines. NaN marks missing points and is kept as NaN;
trailing NaN padding is ignored.

Not applied: the reference line geometry (``phi`` channel, start/end phi, x/y/z, banking, slope) and the
``$ROAD_CRG_MODS`` modifiers. The grid is the road as seen along the reference line, so curvature is ignored: a
curved reference line (the ASAM belgian block sample turns by about -20 degrees over its 10 m) comes back straightened.
Include files (``$ROAD_CRG_FILE``) and reference lines given by x/y channels are refused.

Binary files whose header was treated as text by a CRLF -> LF conversion (git, FTP) lose the CR byte of every CR LF
pair in the data, which shifts the rest of the block; such a block is repaired with a warning (see
``_restore_carriage_returns``). The shared copy of the ASAM belgian block sample has six such lost bytes.

No maintained reader on PyPI fitted: ``pycrg`` (2.2.0) wraps the OpenCRG C library in a compiled extension, not a
pure-Python install; ``pyopencrg`` (0.2.2, alpha, one author) is pure Python but refuses the belgian block file
("size of the binary data is not a multiple of 4 bytes"); the other ``*crg*`` names are unrelated packages.
"""

from __future__ import annotations

import math
import os
import re
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np

_END_OF_HEADER = re.compile(rb"^\$\$\$\$[^\n]*\n", re.MULTILINE)
_FORMATS = {"KRBI": ">f4", "KDBI": ">f8", "LRFI": 10, "LDFI": 20}  # binary dtype, or text field width
_LINE = 80  # text records are written in lines of 80 columns
_SNAP = 1e-9  # m: a v offset this close to a grid line uses that long section alone


@dataclass(frozen=True)
class CrgSurface:
    """An OpenCRG elevation grid; all lengths in metres."""

    u: np.ndarray  # m, longitudinal positions along the reference line (ascending)
    v: np.ndarray  # m, lateral positions (ascending, left positive)
    z: np.ndarray  # m, elevation, shape (u.size, v.size); NaN where the file has no data
    header: dict[str, str]  # the key = value pairs of the header sections (keys in lower case)

    def long_section(self, v_offset: float) -> np.ndarray:
        """Elevation (m) along ``u`` at lateral offset ``v_offset`` (m), linear in v, missing points filled along u.

        Gaps are interpolated linearly along u; gaps at the ends take the nearest value.
        """
        v_offset = float(v_offset)
        if not self.v[0] - _SNAP <= v_offset <= self.v[-1] + _SNAP:
            raise ValueError(f"v_offset = {v_offset} m is outside the lateral range "
                             f"[{self.v[0]}, {self.v[-1]}] m of the surface")
        j = int(np.clip(np.searchsorted(self.v, v_offset), 1, self.v.size - 1))
        right, left = v_offset - self.v[j - 1], self.v[j] - v_offset  # distances to the neighbouring sections
        if right <= _SNAP:
            section = self.z[:, j - 1].copy()
        elif left <= _SNAP:
            section = self.z[:, j].copy()
        else:
            section = (left * self.z[:, j - 1] + right * self.z[:, j]) / (left + right)
        known = np.isfinite(section)
        if not known.any():
            raise ValueError(f"long section at v_offset = {v_offset} m has no data (all NaN)")
        section[~known] = np.interp(self.u[~known], self.u[known], section[known])
        return section


def read_opencrg(path: str | os.PathLike) -> CrgSurface:
    """Read an OpenCRG file into a CrgSurface (m); ValueError naming the problem when the file is malformed."""
    path = Path(path)
    raw = path.read_bytes()
    end = _END_OF_HEADER.search(raw)
    if end is None:
        raise ValueError(f"{path}: no end-of-header line ($$$$...) found: not an OpenCRG file or truncated header")
    header, fmt, channels = _parse_header(raw[:end.start()].decode("latin-1"), path)
    block = raw[end.end():]

    u_channels = [k for k, name in enumerate(channels) if name == "u"]
    n_u = _record_count(header, path)
    if fmt in ("KRBI", "KDBI"):
        values = _binary_records(block, n_u, len(channels), np.dtype(_FORMATS[fmt]), path)
    else:
        values = _text_records(block, len(channels), _FORMATS[fmt], path)
        if n_u is not None and values.shape[0] != n_u:
            raise ValueError(f"{path}: text data has {values.shape[0]} records, the header's u range needs {n_u}")
    if u_channels:
        u = values[:, u_channels[0]]
        if not np.all(np.diff(u) > 0):
            raise ValueError(f"{path}: 'reference line u' channel is not strictly ascending")
    else:
        u = _number(header, "reference_line_start_u", path, 0.0) + (
            _number(header, "reference_line_increment", path) * np.arange(values.shape[0]))

    sections = [(k, name) for k, name in enumerate(channels) if isinstance(name, tuple)]
    kinds = {kind for _, (kind, _) in sections}
    if len(sections) < 2:
        raise ValueError(f"{path}: {len(sections)} long section(s) defined in $KD_DEFINITION, at least 2 needed")
    if len(kinds) > 1:
        raise ValueError(f"{path}: long sections defined both by number and by position")
    if kinds == {"at"}:
        v = np.array([pos for _, (_, pos) in sections])
    else:
        numbers = [pos for _, (_, pos) in sections]
        if numbers != list(range(1, len(sections) + 1)):
            raise ValueError(f"{path}: long sections are not numbered 1..{len(sections)} in order")
        v = _lateral_positions(header, len(sections), path)
    order = np.argsort(v)
    if np.any(np.diff(v[order]) <= 0):
        raise ValueError(f"{path}: long section positions are not distinct")
    z = values[:, [sections[i][0] for i in order]]
    return CrgSurface(u=np.asarray(u, dtype=float), v=v[order], z=z, header=header)


def _parse_header(text: str, path: Path) -> tuple[dict[str, str], str, list]:
    """Key = value pairs, data format and channel list (``"u"``, ``(kind, position)`` or None) of the header."""
    header: dict[str, str] = {}
    fmt = None
    channels: list = []
    section = ""
    for line in text.splitlines():
        stripped = line.strip()
        if stripped.startswith("$"):
            section = stripped.split("!")[0].strip()[1:].strip().upper()
            if section == "ROAD_CRG_FILE":
                raise ValueError(f"{path}: include files ($ROAD_CRG_FILE) are not supported")
            continue
        if section == "CT" or not stripped or stripped[0] in "%*!":
            continue
        content = stripped.split("!")[0].strip()
        if section == "KD_DEFINITION":
            if content.startswith("#:"):
                fmt = content[2:6].upper()
            elif content.startswith("D:"):
                channels.append(_channel(content[2:], path))
        elif "=" in content:
            key, value = content.split("=", 1)
            header[key.strip().lower()] = value.strip()
    if fmt is None:
        raise ValueError(f"{path}: no data format line ('#:KRBI', ...) in a $KD_DEFINITION section")
    if fmt not in _FORMATS:
        raise ValueError(f"{path}: unsupported data format '#:{fmt}' (supported: {', '.join(_FORMATS)})")
    return header, fmt, channels


def _channel(definition: str, path: Path) -> str | tuple[str, float] | None:
    """A ``D:`` channel: ``"u"``, ``("number", N)`` or ``("at", v)`` for long sections, None when not used."""
    name, _, unit = definition.partition(",")
    name, unit = name.strip().lower(), unit.split(",")[0].strip()
    if name.startswith("long section"):
        if unit != "m":
            raise ValueError(f"{path}: long section '{definition.strip()}' is not in metres")
        at = re.fullmatch(r"long section\s+at\s+v\s*=\s*(\S+)", name)
        number = re.fullmatch(r"long section\s+(\d+)", name)
        if at:
            return ("at", _to_float(at.group(1), definition, path))
        if number:
            return ("number", int(number.group(1)))
        raise ValueError(f"{path}: cannot read long section definition 'D:{definition.strip()}'")
    if name in ("reference line x", "reference line y"):
        raise ValueError(f"{path}: reference lines given by x/y channels are not supported")
    if name == "reference line u":
        if unit != "m":
            raise ValueError(f"{path}: 'reference line u' channel is not in metres")
        return "u"
    return None


def _to_float(text: str, what: str, path: Path) -> float:
    try:
        return float(text.replace("D", "E").replace("d", "e"))
    except ValueError:
        raise ValueError(f"{path}: '{what}' has a non-numeric value '{text}'") from None


def _number(header: dict[str, str], key: str, path: Path, default: float | None = None) -> float:
    """Numeric header value ``key``; ValueError naming the key when it is missing (without default) or not a number."""
    if key not in header:
        if default is None:
            raise ValueError(f"{path}: header key '{key}' is missing")
        return default
    return _to_float(header[key], key, path)


def _record_count(header: dict[str, str], path: Path) -> int | None:
    """Number of u positions from the header's u range, or None when the header has no end_u."""
    if "reference_line_end_u" not in header:
        return None
    start = _number(header, "reference_line_start_u", path, 0.0)
    span = (_number(header, "reference_line_end_u", path) - start) / _number(header, "reference_line_increment", path)
    if span < 1 or abs(span - round(span)) > 1e-6 * max(1.0, span):
        raise ValueError(f"{path}: u range from reference_line_start_u to reference_line_end_u is not a positive "
                         f"whole number of reference_line_increment steps ({span})")
    return round(span) + 1


def _lateral_positions(header: dict[str, str], n: int, path: Path) -> np.ndarray:
    """v of long sections numbered 1..n (m) from long_section_v_right / _left / _increment (centred by default)."""
    right, left = header.get("long_section_v_right"), header.get("long_section_v_left")
    if right is not None and left is not None:
        right_m, left_m = _to_float(right, "long_section_v_right", path), _to_float(left, "long_section_v_left", path)
        if "long_section_v_increment" in header:
            inc = _number(header, "long_section_v_increment", path)
            if not math.isclose(right_m + (n - 1) * inc, left_m, abs_tol=1e-6 * max(1.0, abs(left_m))):
                raise ValueError(f"{path}: {n} long sections at long_section_v_increment = {inc} m do not span "
                                 f"long_section_v_right = {right_m} m to long_section_v_left = {left_m} m")
        return np.linspace(right_m, left_m, n)
    inc = _number(header, "long_section_v_increment", path)
    if right is not None:
        first = _to_float(right, "long_section_v_right", path)
    elif left is not None:
        first = _to_float(left, "long_section_v_left", path) - (n - 1) * inc
    else:  # centred on the reference line
        first = -0.5 * (n - 1) * inc
    return first + inc * np.arange(n)


def _binary_records(block: bytes, n_u: int | None, n_channels: int, dtype: np.dtype, path: Path) -> np.ndarray:
    """(n_u, n_channels) float64 values of a binary data block."""
    if n_u is None:
        raise ValueError(f"{path}: header key 'reference_line_end_u' is missing (needed to size binary data)")
    size = n_u * n_channels * dtype.itemsize
    if not _is_padding(block, size, dtype):
        repaired, restored = _restore_carriage_returns(block, size, dtype)
        if repaired is None:
            if len(block) < size:
                raise ValueError(f"{path}: binary data block is truncated: {len(block)} bytes, {size} needed for "
                                 f"{n_u} u positions x {n_channels} channels x {dtype.itemsize} bytes")
            raise ValueError(f"{path}: binary data block has {len(block) - size} bytes after its {size} bytes of "
                             f"records ({n_u} u positions x {n_channels} channels) that are not NaN padding")
        warnings.warn(f"{path}: binary data lost {len(restored)} CR byte(s) before LF bytes to a text-mode line "
                      f"ending conversion; restored at offsets {restored} of the repaired data block", stacklevel=3)
        block = repaired
    return np.frombuffer(block, dtype=dtype, count=n_u * n_channels).reshape(n_u, n_channels).astype(float)


def _is_padding(block: bytes, size: int, dtype: np.dtype) -> bool:
    """True when ``block`` has ``size`` bytes of records followed only by NaN values and line ends."""
    tail = block[size:].rstrip(b"\r\n")
    if len(block) < size or len(tail) % dtype.itemsize:
        return False
    return bool(np.isnan(np.frombuffer(tail, dtype=dtype)).all())


def _plausible(values: np.ndarray) -> np.ndarray:
    """Values that can be stored road data (NaN, zero or 1e-12 < |x| < 1e12); misaligned bytes rarely are."""
    magnitude = np.abs(values)
    return np.isnan(values) | (magnitude == 0) | ((magnitude > 1e-12) & (magnitude < 1e12))


def _restore_carriage_returns(block: bytes, size: int, dtype: np.dtype, window: int = 16,
                              run: int = 256) -> tuple[bytes | None, list[int]]:
    """Undo a CRLF -> LF conversion of a binary block: put back the CR bytes it removed before LF bytes.

    Such a block contains no CR LF pair at all and goes out of step after each lost byte. Walking the values, at the
    first implausible one a CR is put back before one of the LF bytes of the last ``window`` values, the one that
    keeps the most following values plausible (ties: the value closest to its predecessor, as the surface is
    continuous). Returns the repaired block and the offsets of the restored bytes, or (None, []) when that does not
    give ``size`` bytes of plausible records followed by NaN padding.
    """
    if b"\r\n" in block:
        return None, []
    data, restored, start, step = bytearray(block), [], 0, dtype.itemsize
    while True:
        count = (min(len(data), size) - start) // step
        bad = np.flatnonzero(~_plausible(np.frombuffer(data, dtype=dtype, count=count, offset=start)))
        if bad.size == 0:
            break
        first_bad = start + int(bad[0]) * step
        lo = max(restored[-1] + 2 if restored else 0, first_bad - window * step)
        best, best_score = None, None
        for lf in (i for i in range(lo, first_bad + step) if data[i] == 0x0A):
            at = lf // step * step
            trial = bytes(data[at:lf]) + b"\r" + bytes(data[lf:lf + run * step])
            values = np.frombuffer(trial, dtype=dtype, count=len(trial) // step)
            ok = _plausible(values)
            length = int(np.argmin(ok)) if not ok.all() else ok.size
            previous = np.frombuffer(data, dtype=dtype, count=1, offset=at - step)[0] if at >= step else np.nan
            jump = abs(values[0] - previous) if np.isfinite(values[0] - previous) else 0.0
            score = (length, -jump)
            if best_score is None or score > best_score:
                best, best_score = lf, score
        if best is None or best_score[0] <= 1:
            return None, []
        data.insert(best, 0x0D)
        restored.append(best)
        start = best // step * step
    if not _is_padding(bytes(data), size, dtype):
        return None, []
    return bytes(data), restored


def _text_records(block: bytes, n_channels: int, width: int, path: Path) -> np.ndarray:
    """(n_records, n_channels) values of a text data block; fields that are not numbers become NaN."""
    per_line = _LINE // width
    lines_per_record = -(-n_channels // per_line)
    lines = [line for line in block.decode("latin-1").splitlines() if line.strip()]
    if not lines or len(lines) % lines_per_record:
        raise ValueError(f"{path}: text data block has {len(lines)} lines, not a whole number of records of "
                         f"{lines_per_record} lines ({n_channels} channels, {per_line} per line)")
    records = []
    for first in range(0, len(lines), lines_per_record):
        fields = [line[k:k + width] for line in lines[first:first + lines_per_record]
                  for k in range(0, len(line.rstrip()), width)]
        if len(fields) != n_channels:
            raise ValueError(f"{path}: text record {first // lines_per_record + 1} has {len(fields)} values, "
                             f"{n_channels} channels are defined")
        records.append([_field(f) for f in fields])
    return np.array(records, dtype=float)


def _field(text: str) -> float:
    """A text data field; NaN when it is not a number (OpenCRG writes missing values as non-numeric text)."""
    try:
        return float(text.replace("D", "E").replace("d", "e"))
    except ValueError:
        return math.nan
