"""The checkout itself: what a fresh clone gets must set up on any machine, and CI must run the README's own lines."""

import re
import runpy
import subprocess
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
# absolute paths that exist only on the machine that wrote them
MACHINE_PATH = re.compile(r"(?<![\w.])(/work/|/home/\w|/root/|/Users/\w|/tmp/bash_jobs|[A-Za-z]:\\Users\\)")


def tracked() -> list[tuple[str, str]]:
    """(mode, path) of every file git tracks here; skipped where the tests run outside a git checkout."""
    try:
        out = subprocess.run(["git", "-C", str(REPO), "ls-files", "-s"], capture_output=True, text=True, check=True)
    except (OSError, subprocess.CalledProcessError):
        pytest.skip("not a git checkout: the tracked files cannot be listed")
    return [(line.split()[0], line.split("\t", 1)[1]) for line in out.stdout.splitlines()]


def test_no_symlink_is_tracked():
    links = [path for mode, path in tracked() if mode == "120000"]
    assert links == [], f"tracked symlinks point at folders of the machine that committed them: {links}"


def test_no_machine_specific_path_is_tracked():
    found = []
    for _, path in tracked():
        file = REPO / path
        if file == Path(__file__).resolve() or not file.is_file() or file.stat().st_size > 2_000_000:
            continue
        try:
            text = file.read_text(encoding="utf-8")
        except UnicodeDecodeError:  # binary data
            continue
        found += [f"{path}:{n}" for n, line in enumerate(text.splitlines(), 1) if MACHINE_PATH.search(line)]
    assert found == [], f"machine-specific absolute paths: {found}"


def test_the_machine_path_pattern_finds_what_it_should():
    assert MACHINE_PATH.search("see /work/wt/trust/.venv") and MACHINE_PATH.search(r"C:\Users\me\rig")
    assert not MACHINE_PATH.search("rig demo --out /tmp/demo") and not MACHINE_PATH.search("docs/work/x")


def test_ci_runs_the_readme_quick_start_lines():
    quick_start = runpy.run_path(str(REPO / ".ci" / "quick_start.py"))["quick_start"]
    readme = (REPO / "README.md").read_text(encoding="utf-8")
    demo, tests = quick_start(readme, "demo"), quick_start(readme, "tests")
    assert demo.startswith("python3.11 -m venv .venv ") and demo.endswith("rig demo")
    assert tests.startswith("python3.11 -m venv .venv ") and "pytest" in tests
    ci = (REPO / ".ci" / "run").read_text(encoding="utf-8")
    assert "quick_start.py demo" in ci and "quick_start.py tests" in ci
