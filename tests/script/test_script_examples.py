"""The example scripts in scripts_gait/ parse to what their comments say."""

from __future__ import annotations

from pathlib import Path

import pytest

from animstudio.script import Script, parse
from animstudio.script.parser import decode_utf8

EXAMPLES = Path(__file__).resolve().parents[2] / "scripts_gait"


def load(name: str) -> Script:
    path = EXAMPLES / name
    return parse(decode_utf8(path.read_bytes(), path=str(path)), path=str(path))


def test_walk_run_climb_in_seconds() -> None:
    script = load("walk_run_climb.gait")
    assert (script.engine, script.character, script.fps) == ("som", "humanoid", 30)
    assert [(s.gait, s.start_frame, s.frames) for s in script.segments] == [
        ("walk", 0, 60),
        ("run", 60, 45),
        ("climb", 105, 60),
        ("walk", 165, 15),
    ]
    assert script.events == ()


def test_cpg_push_is_the_issues_example() -> None:
    script = load("cpg_push.gait")
    assert (script.engine, script.character, script.reinit) == ("cpg", "humanoid", "auto")
    assert [(s.gait, s.start_frame, s.frames) for s in script.segments] == [
        ("walk", 0, 300),
        ("walk", 300, 240),
    ]
    (push,) = script.events
    assert (push.frame, push.force_n, push.direction, push.duration_s) == (
        300,
        350.0,
        "backward",
        0.1,
    )


def test_hexapod_gaits() -> None:
    script = load("hexapod_gaits.gait")
    assert (script.engine, script.character, script.fps) == ("obb", "hexapod", 30)
    assert [(s.gait, s.frames) for s in script.segments] == [
        ("wave", 120),
        ("tetrapod", 90),
        ("tripod", 60),
    ]


@pytest.mark.parametrize("path", sorted(EXAMPLES.glob("*.gait")), ids=lambda p: p.name)
def test_every_shipped_example_parses(path: Path) -> None:
    assert load(path.name).total_frames > 0
