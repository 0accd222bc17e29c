"""A Rerun recording read back from its .rrd file (``rerun.chunk.RrdReader``) for the tests: per entity its
timelines and components, and its default layout (the blueprint stored in the file)."""

from __future__ import annotations

import uuid
from collections import defaultdict

import numpy as np
import pyarrow as pa
from rerun.chunk import RrdReader

FLOAT32_RESOLUTION = 2e-7  # m: positions and quaternions are stored as float32

def numbers(column: pa.Array) -> np.ndarray:
    """A column of (nested) lists of numbers as rows x values."""
    rows = len(column)
    while pa.types.is_list(column.type) or pa.types.is_fixed_size_list(column.type):
        column = column.flatten()
    return np.asarray(column.to_numpy(zero_copy_only=False), float).reshape(rows, -1)


class Rrd:
    """The recording in a .rrd file: per entity, its timelines and components (temporal rows sorted by time;
    rows of chunks on other timelines left out), and its default layout (``Layout``)."""

    def __init__(self, path):
        reader = RrdReader(path)
        self.blueprints = reader.blueprints()
        self.layout = Layout(reader) if self.blueprints else None
        self.static: dict[str, dict[str, pa.Array]] = defaultdict(dict)
        parts: dict[str, list[pa.Table]] = defaultdict(list)
        for chunk in reader.store().stream():
            batch = chunk.to_record_batch()
            names = [n for n in batch.schema.names if not n.startswith("rerun.controls")]
            if chunk.is_static:
                self.static[chunk.entity_path].update({name: batch.column(name) for name in names})
            else:
                parts[chunk.entity_path].append(pa.Table.from_batches([batch.select(names)]))
        self.temporal: dict[str, dict[str, pa.Array]] = {}
        for entity, tables in parts.items():  # chunks on other timelines: their timeline columns are null
            table = pa.concat_tables(tables, promote_options="default")
            self.temporal[entity] = {name: table.column(name).combine_chunks() for name in table.column_names}

    def timelines(self, entity: str) -> set[str]:
        return {n for n in self.temporal[entity] if ":" not in n}

    def _rows(self, entity: str, timeline: str) -> np.ndarray:
        """The entity's rows on ``timeline``, in its order."""
        values = self.temporal[entity][timeline]
        rows = np.flatnonzero(values.is_valid().to_numpy(zero_copy_only=False))
        return rows[np.argsort(self._times(values.take(rows)), kind="stable")]

    @staticmethod
    def _times(values: pa.Array) -> np.ndarray:
        if pa.types.is_duration(values.type):
            return values.cast(pa.int64()).to_numpy() / 1e9  # s
        return values.to_numpy()

    def index(self, entity: str, timeline: str) -> np.ndarray:
        """The entity's times (s) or sequence numbers on ``timeline``, in order."""
        return self._times(self.temporal[entity][timeline].take(self._rows(entity, timeline)))

    def values(self, entity: str, component: str, timeline: str = "time") -> np.ndarray:
        """Rows x values of a temporal component, in timeline order."""
        return numbers(self.temporal[entity][component].take(self._rows(entity, timeline)))

    def scalars(self, entity: str, timeline: str = "time") -> tuple[np.ndarray, np.ndarray]:
        return self.index(entity, timeline), self.values(entity, "Scalars:scalars", timeline)[:, 0]

    def entities(self, query: str) -> list[str]:
        """Logged entities (static or temporal) that a view's ``+ path`` query (``**``: and everything below)
        selects."""
        path = "/" + query.removeprefix("+ ").lstrip("/")
        below = path.endswith("/**")
        base = path.removesuffix("/**")
        return sorted(e for e in set(self.static) | set(self.temporal)
                      if e == base or (below and e.startswith(base + "/")))

    def colors(self, entity: str) -> list[tuple[int, int, int]]:
        """The RGB colour of each series of an entity (its static SeriesLines)."""
        packed = np.asarray(self.static[entity]["SeriesLines:colors"].to_pylist()[0], np.uint32)
        return [tuple(int(v >> shift) & 0xFF for shift in (24, 16, 8)) for v in packed]


def _union_kinds(array: pa.Array) -> list[str]:
    """The variant names of a dense union array, e.g. TimeRangeBoundary's 'Infinite'."""
    names = {code: array.type.field(i).name for i, code in enumerate(array.type.type_codes)}
    return [names[code] for code in array.type_codes.to_numpy()]


def _one(column: pa.Array):
    """The single value of a blueprint component (its last row)."""
    return column[len(column) - 1].as_py()[0]


class Layout:
    """A recording's default blueprint: its views (class, name, origin, content queries, time ranges, x axis,
    legend) and the views on screen when it opens (every container's content, but only a tab container's
    first tab)."""

    def __init__(self, reader: RrdReader):
        parts: dict[str, dict[str, pa.Array]] = defaultdict(dict)
        for chunk in reader.store(store=reader.blueprints()[0]).stream():
            batch = chunk.to_record_batch()
            parts[chunk.entity_path].update({n: batch.column(n) for n in batch.schema.names if ":" in n})
        self.parts = parts = dict(parts)
        self.views = {}
        for path, columns in parts.items():
            if path.count("/") == 2 and path.startswith("/view/"):
                view = {"class": _one(columns["ViewBlueprint:class_identifier"]),
                        "name": _one(columns["ViewBlueprint:display_name"]),
                        "origin": "/" + _one(columns["ViewBlueprint:space_origin"]).lstrip("/"),
                        "contents": parts[f"{path}/ViewContents"]["ViewContents:query"][0].as_py()}
                ranges = parts.get(f"{path}/VisibleTimeRanges", {}).get("VisibleTimeRanges:ranges")
                if ranges is not None:
                    items = ranges[0].values
                    view["ranges"] = dict(zip(items.field("timeline").to_pylist(), zip(
                        _union_kinds(items.field("range").field("start")),
                        _union_kinds(items.field("range").field("end")))))
                axis = parts.get(f"{path}/TimeAxis")
                if axis:
                    view_range = axis["TimeAxis:view_range"][0].values
                    view["axis"] = (_union_kinds(view_range.field("start"))[0],
                                    _union_kinds(view_range.field("end"))[0], _one(axis["TimeAxis:link"]))
                legend = parts.get(f"{path}/PlotLegend")
                view["legend"] = _one(legend["PlotLegend:visible"]) if legend else True
                self.views[path.removeprefix("/")] = view
        root = _one(parts["/viewport"]["ViewportBlueprint:root_container"])  # a UUID as 16 bytes
        self.on_screen = self._visible(f"container/{uuid.UUID(bytes=bytes(root))}")
        self.timeline = _one(parts["/time_panel"]["TimePanelBlueprint:timeline"])

    def _visible(self, item: str) -> list[dict]:
        if item.startswith("view/"):
            return [self.views[item]]
        columns = self.parts[f"/{item}"]
        contents = columns["ContainerBlueprint:contents"][0].as_py()
        if _one(columns["ContainerBlueprint:container_kind"]) == 1:  # tabs: the first one shows
            contents = contents[:1]
        return [view for child in contents for view in self._visible(child)]

    def of_class(self, kind: str) -> list[dict]:
        return [view for view in self.views.values() if view["class"] == kind]




def selected(rrd: Rrd, view: dict) -> list[str]:
    """The logged entities a view of the layout shows."""
    return sorted({e for query in view["contents"] for e in rrd.entities(query.replace("$origin", view["origin"]))})


def text(rrd: Rrd, entity: str) -> str:
    """A static text document's markdown."""
    return rrd.static[entity]["TextDocument:text"].to_pylist()[0][0]
