"""The Jupyter notebooks in notebooks/ run top to bottom in a fresh kernel (their own asserts check what they
show: IRI against the published figures, the hidden cause found, the mapped MDF4 file replayed within TDDI
1e-3...), and are committed with their outputs stripped.

Each runs as Jupyter runs it: kernel ``python3``, working directory the notebook's folder (that is how a
notebook finds the real data in ../data). One that needs an optional package (05 trains a policy with
stable-baselines3, the ``[rl]`` extra) lists it in its metadata (``requires_modules``) and is skipped with the
reason when it is not installed. Measured on two cores: 5 to 60 s
each, about 1.5 min for all.
"""

from __future__ import annotations

import importlib.util
import os
from pathlib import Path

import nbformat
import pytest
from nbclient import NotebookClient

import rig

REPO = Path(__file__).resolve().parents[1]
NOTEBOOKS = sorted((REPO / "notebooks").glob("*.ipynb"))
CELL_TIMEOUT = 300  # s


def test_there_are_notebooks():
    assert len(NOTEBOOKS) >= 4


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.stem)
def test_notebook_is_committed_without_outputs(path):
    notebook = nbformat.read(path, as_version=4)
    nbformat.validate(notebook)
    dirty = [index for index, cell in enumerate(notebook.cells) if cell.cell_type == "code"
             and (cell.outputs or cell.execution_count is not None)]
    assert not dirty, (f"{path.name}: code cell(s) {dirty} carry outputs or execution counts; clear them before "
                       f"committing (jupyter nbconvert --clear-output --inplace {path.name})")


#: notebooks that run a whole diagnosis (a minute on two cores): executed in the slow set
SLOW_NOTEBOOKS = ("03_diagnosis_force_laws",)


@pytest.mark.parametrize("path", [pytest.param(p, marks=pytest.mark.slow) if p.stem in SLOW_NOTEBOOKS else p
                                  for p in NOTEBOOKS], ids=lambda p: p.stem)
def test_notebook_runs_top_to_bottom(path, monkeypatch):
    notebook = nbformat.read(path, as_version=4)
    absent = [name for name in notebook.metadata.get("requires_modules", []) if importlib.util.find_spec(name) is None]
    if absent:
        pytest.skip(f"{path.name} needs {', '.join(absent)}, not installed (an optional extra: see the README)")
    # the kernel imports the same rig as this process: the checkout in development, the installed package in CI
    package_root = str(Path(rig.__file__).resolve().parents[1])
    monkeypatch.setenv("PYTHONPATH", os.pathsep.join(filter(None, [package_root, os.environ.get("PYTHONPATH")])))
    client = NotebookClient(notebook, timeout=CELL_TIMEOUT, kernel_name="python3",
                            resources={"metadata": {"path": str(path.parent)}})
    client.execute()
    figures = [output for cell in notebook.cells if cell.cell_type == "code" for output in cell.outputs
               if "image/png" in output.get("data", {})]
    assert figures, f"{path.name} drew no figure"
