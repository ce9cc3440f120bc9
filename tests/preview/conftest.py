"""Shared fixtures of the preview tests."""

from __future__ import annotations

import socket
import sys
from pathlib import Path

import pytest

HERE = Path(__file__).parent
sys.path.insert(0, str(HERE))  # the synthetic clip and the browser helpers live next to the tests

from synthetic import synthetic_clip  # noqa: E402

from animstudio.core.clip import Clip  # noqa: E402

SOM_SCRIPT = """\
# humanoid on the Kohonen controller (renders in a fraction of a second)
engine som
character humanoid
fps 30

walk 2s / run 2s
"""

OBB_SCRIPT = """\
# hexapod: tripod then wave (rendered by the obb engine in well under a second)
engine obb
character hexapod
fps 30

tripod 2s / wave 2s
"""


@pytest.fixture(scope="session")
def walk_climb_clip() -> Clip:
    return synthetic_clip(signals=True)


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])
