"""The structure drawn from the imports of the ``rig`` package's source: no module reaches itself through its imports
(those for type checkers and those inside functions count too), no module imports another package's private
(``_``-prefixed) modules, and a cause's name is written in its own module only (the registry is the one way to it)."""

import ast
import graphlib
from pathlib import Path

import rig
from rig.causes import CAUSES
from rig.vehicle.layouts import layouts

PACKAGE = Path(rig.__file__).parent


def _module_name(path: Path) -> str:
    parts = path.relative_to(PACKAGE.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


MODULES = {_module_name(path): path for path in PACKAGE.rglob("*.py")}


def _resolve(name: str) -> str | None:
    """The module of ``rig`` that ``name`` (a module, or a name inside one) lives in, or None outside ``rig``."""
    while name and name not in MODULES:
        name = name.rpartition(".")[0]
    return name or None


def _imported(module: str) -> set[str]:
    """Every module of ``rig`` that ``module`` imports, anywhere in its source."""
    path = MODULES[module]
    package = module if path.name == "__init__.py" else module.rpartition(".")[0]
    found = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                anchor = package.split(".")[: len(package.split(".")) - node.level + 1]
                base = ".".join([*anchor, base] if base else anchor)
            found |= {_resolve(f"{base}.{alias.name}") for alias in node.names}
        elif isinstance(node, ast.Import):
            found |= {_resolve(alias.name) for alias in node.names}
    return found - {None, module}


GRAPH = {module: _imported(module) for module in MODULES}


def test_the_graph_reads_the_imports_it_should():
    assert "rig.vehicle.extensions" in GRAPH["rig.vehicle.mjcf"]
    assert "rig.elements.air_spring" in GRAPH["rig.vehicle.suspensions.beam_air"]
    assert "rig.vehicle.parts" in GRAPH["rig.vehicle.plausibility"]  # an import for type checkers counts


def test_no_module_reaches_itself_through_its_imports():
    sorter = graphlib.TopologicalSorter(GRAPH)
    try:
        sorter.prepare()
    except graphlib.CycleError as err:
        raise AssertionError(f"import circle: {' -> '.join(err.args[1])}") from None


def test_a_circle_is_found_where_there_is_one():
    circle = {**GRAPH, "rig.vehicle.parts": GRAPH["rig.vehicle.parts"] | {"rig.vehicle.vehicle_file"}}
    sorter = graphlib.TopologicalSorter(circle)
    try:
        sorter.prepare()
    except graphlib.CycleError:
        return
    raise AssertionError("a circle through vehicle_file and parts was not found")


def test_no_module_imports_another_packages_private_modules():
    wrong = []
    for module, imported in GRAPH.items():
        for target in imported:
            package, _, leaf = target.rpartition(".")
            if leaf.startswith("_") and not (module == package or module.startswith(f"{package}.")):
                wrong.append(f"{module} imports {target}")
    assert not wrong, wrong


def _names_written(path: Path, names) -> set[str]:
    """Which of ``names`` ``path`` writes as a string of its own (a docstring or a message may name them)."""
    return set(names) & {node.value for node in ast.walk(ast.parse(path.read_text()))
                         if isinstance(node, ast.Constant) and isinstance(node.value, str)}


def test_a_causes_name_is_written_in_its_own_module_only():
    """Code outside a cause's module reaches it through the registry (its subsystem, its damper part, its hooks) or
    its ``CAUSE.name``, never by writing its name. A cause without a section of its own lives in keys of a baseline
    table (``tyre_damping`` in ``[front]``), which the vehicle file's schema names."""
    named = [name for name, cause in CAUSES.items() if cause.has_section()]
    wrong = [f"{module} writes {sorted(written)}" for module, path in MODULES.items()
             if (written := _names_written(path, named) - {module.rpartition(".")[2]})]
    assert not wrong, wrong


def test_the_name_check_finds_a_name_written_elsewhere(tmp_path):
    path = tmp_path / "elsewhere.py"
    path.write_text('"""Friction in the strut (strut_friction)."""\nFRICTION = "strut_friction"\n')
    assert _names_written(path, CAUSES) == {"strut_friction"}
    path.write_text('"""Friction in the strut (strut_friction)."""\nFRICTION = CAUSE.name\n')
    assert _names_written(path, CAUSES) == set()


def test_tests_share_helpers_through_the_support_package_not_each_other():
    tests = Path(__file__).parent
    wrong = []
    for path in tests.glob("test_*.py"):
        for node in ast.walk(ast.parse(path.read_text())):
            names = [node.module or ""] if isinstance(node, ast.ImportFrom) else \
                [a.name for a in node.names] if isinstance(node, ast.Import) else []
            wrong += [f"{path.name} imports {n}" for n in names if n.startswith("test_")]
    assert not wrong, wrong


PIPELINES = {  # a diagnosis pipeline -> the parts of rig.diagnosis it may import besides itself
    "core": set(),
    "rig_test": {"core"},
    "track": {"core", "rig_test"},  # a track test over a measured road is diagnosed as a rig test is
    "kc": set(),
    "dyno": set(),
}


def test_each_diagnosis_pipeline_stands_on_the_shared_core_only():
    """Rig test, track test, K&C and dyno are sub-packages of ``rig.diagnosis``; the core (experiment, fitting,
    held-out split, noise, validation) imports none of them, and no pipeline imports another's modules but the
    track test the rig test's."""
    packages = {p.name for p in (PACKAGE / "diagnosis").iterdir() if (p / "__init__.py").is_file()}
    assert packages == set(PIPELINES)
    wrong = []
    for module, imported in GRAPH.items():
        parts = module.split(".")
        if parts[:2] != ["rig", "diagnosis"] or len(parts) < 4:
            continue
        allowed = PIPELINES[parts[2]] | {parts[2]}
        wrong += [f"{module} imports {target}" for target in imported
                  if target.startswith("rig.diagnosis.") and target.split(".")[2] not in allowed]
    assert not wrong, wrong


def test_module_names_are_unique_but_for_a_commands_own():
    """A module's file name says which it is wherever it is read (a traceback, a search): no two modules of ``rig``
    or ``controllers`` share one, but a command's module in ``rig/cli`` (named after its command) and the private
    ``_base`` of a registry."""
    paths = [p for root in (PACKAGE, PACKAGE.parent / "controllers") for p in root.rglob("*.py")
             if p.name not in ("__init__.py", "_base.py") and p.parent != PACKAGE / "cli"]
    names = [p.name for p in paths]
    assert sorted({n for n in names if names.count(n) > 1}) == []


LAYOUTS_PACKAGE = PACKAGE / "vehicle" / "layouts"


def _layout_names_compared(path: Path, names) -> set[str]:
    """The layout names that ``path`` compares something with (``==``, ``!=``, ``in``, ``not in`` a string constant,
    or a tuple, list or set of them)."""
    compared = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Compare):
            for operand in (node.left, *node.comparators):
                items = operand.elts if isinstance(operand, (ast.Tuple, ast.List, ast.Set)) else [operand]
                compared |= {item.value for item in items if isinstance(item, ast.Constant) and item.value in names}
    return compared


def test_no_module_branches_on_a_layouts_name():
    """Code outside the layout registry (rig/vehicle/layouts/) asks a vehicle's ``layout_type`` what it needs (its
    corners per axle, whether its axles are ``[[axles]]``, its body's motions, its frame), never compares the name."""
    names = set(layouts())
    roots = (PACKAGE, PACKAGE.parent / "controllers")
    wrong = [f"{path} compares {sorted(compared)}" for root in roots for path in root.rglob("*.py")
             if LAYOUTS_PACKAGE not in path.parents and (compared := _layout_names_compared(path, names))]
    assert not wrong, wrong


def test_the_layout_check_finds_a_comparison_where_there_is_one(tmp_path):
    path = tmp_path / "elsewhere.py"
    path.write_text('def corners(vehicle):\n    return 1 if vehicle.layout == "quarter" else 2\n')
    assert _layout_names_compared(path, layouts()) == {"quarter"}
    path.write_text('def pitch(vehicle):\n    return vehicle.layout in ("full", "truck")\n')
    assert _layout_names_compared(path, layouts()) == {"full", "truck"}
    path.write_text('def corners(vehicle):\n    return vehicle.layout_type.corners_per_axle\nQUARTER = "quarter"\n')
    assert _layout_names_compared(path, layouts()) == set()
