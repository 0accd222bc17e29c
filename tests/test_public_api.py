"""The curated surface of ``import rig`` and the package layering of ARCHITECTURE.md."""

import ast
from pathlib import Path

import pytest

import rig

PACKAGE = Path(rig.__file__).parent
#: stages in data-flow order: a module may import its own stage and the ones before it
STAGES = ["constants", "io", "signal", "elements", "vehicle", "causes", "road", "sim", "diagnosis", "envs", "sweep",
          "report", "cli"]


@pytest.mark.parametrize("name", rig.__all__)
def test_every_public_name_resolves(name):
    assert getattr(rig, name) is not None


def test_unknown_names_are_refused():
    with pytest.raises(AttributeError, match="no attribute 'nonsense'"):
        rig.nonsense  # noqa: B018


def _imports(path: Path) -> set[str]:
    """Modules a file imports at run time (imports for type checkers only are left out)."""
    tree = ast.parse(path.read_text())
    for node in ast.walk(tree):
        if isinstance(node, ast.If) and getattr(node.test, "id", "") == "TYPE_CHECKING":
            node.body = []
    names = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and node.module:
            names.add(node.module)
        elif isinstance(node, ast.Import):
            names.update(alias.name for alias in node.names)
    return names


def test_imports_flow_one_way_and_rig_below_its_cli_never_imports_controllers():
    wrong = []
    for path in PACKAGE.rglob("*.py"):
        parts = path.relative_to(PACKAGE).with_suffix("").parts
        stage = parts[0] if parts[0] in STAGES else None
        if stage is None:  # rig/__init__.py: the lazy public surface
            continue
        for module in _imports(path):
            top = module.split(".")
            if top[0] == "controllers" and stage != "cli":
                wrong.append(f"{path.relative_to(PACKAGE)} imports {module}")
            if top[0] == "rig" and len(top) > 1 and top[1] in STAGES and STAGES.index(top[1]) > STAGES.index(stage):
                wrong.append(f"{path.relative_to(PACKAGE)} ({stage}) imports {module} (a later stage)")
    assert not wrong, wrong


def test_cli_lists_every_cause_of_the_registry_with_units(capsys):
    from rig.causes import CAUSES
    from rig.cli import main

    assert main(["causes"]) == 0
    out = capsys.readouterr().out
    for name, cause in CAUSES.items():
        limited = "" if len(cause.layouts) == 3 else f"; layout {' or '.join(cause.layouts)} only"
        assert f"{name} ({cause.subsystem}{limited}): {cause.meaning}" in out
    assert "leaf_friction (car; layout truck only)" in out
    assert "strut_friction (car; layout full or quarter only)" in out
    assert "gap [m] 0..0.3" in out and "quadratic [N s^2/m^2] 0..1e+06" in out
