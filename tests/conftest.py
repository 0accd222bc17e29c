"""Shared fixtures: the real third-party data shipped in data/, and built simulators."""

from __future__ import annotations

from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
DATA = REPO / "data"


@pytest.fixture(scope="session")
def real_data() -> Path:
    """The real third-party data shipped in data/ (data/README.md says where each file comes from)."""
    return DATA
