"""Small real gait scripts and helpers shared by the preview tests."""

from __future__ import annotations

import socket

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


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])
