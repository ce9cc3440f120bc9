"""Shared fixtures of the preview tests."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

HERE = Path(__file__).parent
sys.path.insert(0, str(HERE))  # the synthetic clip and the browser helpers live next to the tests

from preview_synthetic import synthetic_clip  # noqa: E402

from animstudio.core.clip import Clip  # noqa: E402


@pytest.fixture(scope="session")
def walk_climb_clip() -> Clip:
    return synthetic_clip(signals=True)
