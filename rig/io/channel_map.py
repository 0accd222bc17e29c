"""Channel maps (contract: docs/contracts.md): a DAQ's own channel names onto ``<corner>/<quantity>``, with units.

A map file (``--map MAP.toml``)::

    [channels]
    "PostDisp_LF" = "FL/actuator_disp"                                  # unit from the file's metadata
    "ACC_LF_BODY" = { name = "FL/sprung_acc", unit = "g", scale = -1.0 }  # explicit unit / sign

or inline ``FROM=TO`` pairs. A source (in either form) may also be the file's name without its unit (``"Fc (N)"``
finds ``"Fc (N"``, a header whose parenthesis the DAQ cut off) or a part of exactly one of the file's names
(``LF_=FL/unsprung_acc``). A record read through a map holds only the mapped channels, in SI:
``value * scale * factor(unit)``, the unit being the map's when it gives one, else the file's. The other
channels are ignored and listed. Readers apply the map before converting units, so a map can name the
unit of a channel whose file says nothing or something unknown.
"""

from __future__ import annotations

import math
import os
import tomllib
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from rig.io.channels import QUANTITY_UNITS, is_corner, split_channel
from rig.io.record import RecordError
from rig.io.text import read_text
from rig.io.units import UnitError, si_conversion, split_unit

_ENTRY_KEYS = {"name", "unit", "scale"}
#: quantities read unwrapped: angles that grow without bound (docs/contracts.md: ``wheel_angle`` is unwrapped)
UNWRAPPED = ("wheel_angle",)


@dataclass(frozen=True)
class MapEntry:
    """One mapped channel: the file's ``source`` becomes the record's ``name``.

    ``unit`` (when given) is the unit of the file's values and overrides the file's metadata; ``scale``
    multiplies the values before conversion to SI (``-1`` flips a sensor mounted upside down).
    ``source`` may also be the file's name without its unit, or a part of exactly one of its names (``_source``).
    """

    source: str
    name: str
    unit: str | None = None
    scale: float = 1.0


@dataclass(frozen=True)
class ChannelMap:
    """The entries of a map and where it came from (the map file, or ``--map`` for inline pairs)."""

    entries: tuple[MapEntry, ...]
    origin: str


@dataclass(frozen=True)
class Conversion:
    """How one channel of a file becomes a record channel: ``si_value = file_value * factor + offset`` (an offset
    only for degrees Fahrenheit or kelvin); a wheel's angle is unwrapped as well (a DAQ may log it modulo a turn,
    RPC III's 16 bits keep it only so)."""

    source: str
    name: str
    factor: float
    unit: str
    offset: float = 0.0

    def apply(self, values) -> np.ndarray:
        """The file's values of this channel in SI, as the record holds them."""
        values = np.asarray(values, dtype=float) * self.factor + self.offset
        return np.unwrap(values) if split_channel(self.name)[1] in UNWRAPPED else values


@dataclass(frozen=True)
class ChannelPlan:
    """The channels a reader takes from a file and how it converts them; ``ignored``: the file's other channels."""

    conversions: tuple[Conversion, ...]
    ignored: tuple[str, ...]

    @property
    def sources(self) -> list[str]:
        return [c.source for c in self.conversions]


def load_channel_map(path: str | os.PathLike) -> ChannelMap:
    """Read a map file (TOML, a ``[channels]`` table); a malformed entry is refused with its key named."""
    path = Path(path)
    try:
        document = tomllib.loads(read_text(path, "channel map", RecordError))
    except OSError as err:
        raise RecordError(f"channel map {path}: cannot read it ({err.strerror})") from None
    except tomllib.TOMLDecodeError as err:
        raise RecordError(f"channel map {path}: not valid TOML ({err})") from None
    table = document.get("channels")
    if not isinstance(table, dict) or not table:
        raise RecordError(f"channel map {path}: needs a [channels] table of \"DAQ name\" = \"<corner>/<quantity>\"")
    return ChannelMap(tuple(_entry(path, source, value) for source, value in table.items()), str(path))


def map_from_option(items: list[str] | None) -> ChannelMap | None:
    """The map that ``--map`` names: one ``MAP.toml`` file, or ``FROM=TO`` pairs; None without the option."""
    if not items:
        return None
    if len(items) == 1 and "=" not in items[0]:
        return load_channel_map(items[0])
    entries = []
    for item in items:
        source, sep, name = item.partition("=")
        if not sep or not source or not name:
            raise RecordError(f"--map item '{item}' is not FROM=TO (or give one MAP.toml file)")
        entries.append(MapEntry(source, name))
    return ChannelMap(tuple(entries), "--map")


def plan_channels(path: str | os.PathLike, file_units: dict[str, str], channel_map: ChannelMap | None = None,
                  places: dict[str, str] | None = None) -> ChannelPlan:
    """Which of a file's channels to read, under which names, and their conversion to SI.

    ``file_units`` maps the file's channel names, in file order, to their units as the file writes them;
    ``places`` optionally says where each is in the file (``header column 3``), for messages. Without a
    map every channel is read under its own name. Refused, one line naming the channels: a mapped name
    the file lacks (or, for a part of a name, matches several), two sources mapped to one channel, an
    unknown unit, and a unit of the wrong kind for a contract quantity (``g`` for ``FL/actuator_disp``).
    """
    places = places or {}
    if channel_map is None:
        entries = [(MapEntry(name, name), name) for name in file_units]
    else:
        entries = [(entry, _source(path, channel_map, entry, file_units)) for entry in channel_map.entries]
    conversions: dict[str, Conversion] = {}
    for entry, source in entries:
        if entry.name in conversions:
            raise RecordError(f"{channel_map.origin}: channels '{conversions[entry.name].source}' and '{source}' "
                              f"of {path} are both mapped to '{entry.name}'")
        unit = entry.unit if entry.unit is not None else file_units[source]
        where = f"unit from {channel_map.origin}" if entry.unit is not None else places.get(source)
        label = f"{path}: channel '{source}'" + (f" ({where})" if where else "")
        corner, quantity = split_channel(entry.name)
        if is_corner(corner) and quantity not in QUANTITY_UNITS:
            raise RecordError(f"{channel_map.origin}: '{entry.name}' (for '{source}' of {path}) names no quantity of "
                              f"the contract: '{quantity}' is not one of {', '.join(QUANTITY_UNITS)}")
        expected = QUANTITY_UNITS.get(quantity)
        temperature = expected == "degC" or "temp" in source.lower()
        try:
            factor, offset, si_unit = si_conversion(unit, temperature)
        except UnitError as err:
            raise RecordError(f"{label}: {err}") from None
        if expected is not None and si_unit != expected:
            in_unit = f"in '{unit}'" if unit.strip() else "without a unit"
            raise RecordError(f"{label} {in_unit} cannot be '{entry.name}', which is in {expected}"
                              f"{'; give its unit in a channel map' if not unit.strip() else ''}")
        conversions[entry.name] = Conversion(source, entry.name, factor * entry.scale, si_unit, offset)
    used = {c.source for c in conversions.values()}
    return ChannelPlan(tuple(conversions.values()), tuple(n for n in file_units if n not in used))


def plan_metadata(plan: ChannelPlan, channel_map: ChannelMap | None) -> dict[str, str]:
    """The record metadata that says which channels a map left out (key ``unmapped``), if any."""
    if channel_map is None or not plan.ignored:
        return {}
    return {"unmapped": f"{len(plan.ignored)} channel(s) not in {channel_map.origin} ignored: "
                        + ", ".join(plan.ignored)}


def _source(path: str | os.PathLike, channel_map: ChannelMap, entry: MapEntry, file_units: dict[str, str]) -> str:
    """The file's channel an entry names: the same name; else the same name without its unit (a measured and a
    held-out export whose headers differ by a cut-off parenthesis share one map); else the one name it is a part of."""
    if entry.source in file_units:
        return entry.source
    base = split_unit(entry.source)[0]
    for matches in ([n for n in file_units if split_unit(n)[0] == base],
                    [n for n in file_units if entry.source in n or base in split_unit(n)[0]]):
        if len(matches) == 1:
            return matches[0]
        if matches:
            raise RecordError(f"{channel_map.origin}: '{entry.source}' (for '{entry.name}') matches "
                              f"{len(matches)} channels of {path} ({', '.join(matches)})")
    raise RecordError(f"{channel_map.origin}: channel '{entry.source}' (for '{entry.name}') is not in {path} "
                      f"(it has: {', '.join(file_units)})")


def _entry(path: Path, source: str, value: object) -> MapEntry:
    if isinstance(value, str):
        return MapEntry(source, value)
    if not isinstance(value, dict) or "name" not in value or set(value) - _ENTRY_KEYS:
        raise RecordError(f"channel map {path}: entry '{source}' must be \"<corner>/<quantity>\" or "
                          f"{{ name = \"<corner>/<quantity>\", unit = \"...\", scale = ... }}")
    name, unit, scale = value["name"], value.get("unit"), value.get("scale", 1.0)
    if not isinstance(name, str) or not name or (unit is not None and not isinstance(unit, str)):
        raise RecordError(f"channel map {path}: entry '{source}': name and unit must be strings")
    if isinstance(scale, bool) or not isinstance(scale, int | float) or not scale or not math.isfinite(scale):
        raise RecordError(f"channel map {path}: entry '{source}': scale must be a non-zero number, got {scale!r}")
    return MapEntry(source, name, unit, float(scale))
