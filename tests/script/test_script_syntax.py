"""Every construct of the gait-script language parses to the values docs/script-language.md states."""

from __future__ import annotations

import pytest

from animstudio.errors import SourceSpan
from animstudio.script import parse
from animstudio.script.model import PushEvent, Setting


def frames(text: str) -> list[tuple[str, int, int]]:
    return [(s.gait, s.start_frame, s.frames) for s in parse(text).segments]


def test_segments_on_one_line_separated_by_slash() -> None:
    assert frames("walk 60 / run 30 / climb 45") == [
        ("walk", 0, 60),
        ("run", 60, 30),
        ("climb", 90, 45),
    ]


def test_segments_on_separate_lines_with_comments_and_blank_lines() -> None:
    text = "# a comment\n\nwalk 60   # trailing comment\n\t\n  run 30\n# end\n"
    assert frames(text) == [("walk", 0, 60), ("run", 60, 30)]


def test_slashes_need_no_spaces() -> None:
    assert frames("walk 60/run 30") == [("walk", 0, 60), ("run", 60, 30)]


def test_tabs_separate_words() -> None:
    assert frames("walk\t60\t/\trun\t30") == [("walk", 0, 60), ("run", 60, 30)]


def test_gait_names_may_hold_digits_and_underscores() -> None:
    assert frames("walk_slow2 10") == [("walk_slow2", 0, 10)]


@pytest.mark.parametrize(
    ("duration", "fps", "expected"),
    [
        ("60", 30, 60),
        ("007", 30, 7),
        ("2s", 30, 60),
        ("1.5s", 30, 45),
        (".5s", 30, 15),
        ("2.s", 30, 60),
        ("0.05s", 30, 2),  # 1.5 frames: half rounds up
        ("0.35s", 30, 11),  # 10.5 exactly (a float product would give 10.4999… and 10)
        ("0.0167s", 30, 1),  # 0.501 frames
        ("1.0166s", 30, 30),  # 30.498 frames rounds down
        ("0.1s", 240, 24),
        ("1s", 1, 1),
    ],
)
def test_durations_in_frames_or_seconds(duration: str, fps: int, expected: int) -> None:
    script = parse(f"fps {fps}\nwalk {duration}")
    assert script.segments[0].frames == expected


def test_seconds_use_the_scripts_fps() -> None:
    assert frames("fps 24\nwalk 2s / run 1.5s / climb 10") == [
        ("walk", 0, 48),
        ("run", 48, 36),
        ("climb", 84, 10),
    ]


def test_one_hour_exactly_is_accepted() -> None:
    script = parse("fps 240\nwalk 1800s\nrun 1800s")
    assert script.total_frames == 3600 * 240
    assert script.duration_s == 3600.0


def test_spans_point_at_gait_and_duration() -> None:
    segment = parse("walk 60 /  run  2s", path="a.gait").segments[1]
    assert segment.span == SourceSpan("a.gait", 1, 12, 3)
    assert segment.duration_span == SourceSpan("a.gait", 1, 17, 2)


def test_columns_count_characters_and_tabs_count_one() -> None:
    segment = parse("\t\tobb k=€é 60").segments[0]
    assert (segment.span.line, segment.span.column) == (1, 3)
    assert segment.duration_span.column == 12  # '€' is 3 bytes in UTF-8 but one column
    assert segment.params["k"] == "€é"


def test_crlf_and_bom_are_accepted_and_not_counted() -> None:
    script = parse("\ufeffwalk 60\r\nrun 30\r\n")
    assert [(s.gait, s.frames) for s in script.segments] == [("walk", 60), ("run", 30)]
    assert script.segments[0].span.column == 1
    assert script.segments[1].duration_span.column == 5


def test_expert_parameters() -> None:
    segment = parse("obb r=1,5 k_2=x.y 90", path="p.gait").segments[0]
    assert segment.gait == "obb" and segment.frames == 90
    assert dict(segment.params) == {"r": "1,5", "k_2": "x.y"}
    assert segment.param_spans["r"] == SourceSpan("p.gait", 1, 5, 5)
    assert segment.param_spans["k_2"] == SourceSpan("p.gait", 1, 11, 7)


def test_a_comment_ends_a_parameter_value() -> None:
    segment = parse("obb r=1,5 90 # r=2").segments[0]
    assert dict(segment.params) == {"r": "1,5"}


def test_defaults() -> None:
    script = parse("walk 1")
    assert (script.engine, script.character, script.fps) == ("som", "humanoid", 30)
    assert (script.blend_frames, script.reinit, script.seed) == (0, "auto", 0)
    assert script.settings == () and script.events == ()
    assert script.path == "<string>"


def test_all_settings() -> None:
    text = "engine cpg\ncharacter humanoid\nfps 24\nblend 6\nreinit off\nseed 42\nwalk 1"
    script = parse(text, path="s.gait")
    assert (script.engine, script.character, script.fps) == ("cpg", "humanoid", 24)
    assert (script.blend_frames, script.reinit, script.seed) == (6, "off", 42)
    assert script.settings[2] == Setting("fps", "24", SourceSpan("s.gait", 3, 5, 2))
    assert script.setting_span("seed") == SourceSpan("s.gait", 6, 6, 2)
    assert script.setting_span("nope") is None


@pytest.mark.parametrize(
    ("header", "engine", "character"),
    [
        ("engine obb", "obb", "hexapod"),
        ("engine som", "som", "humanoid"),
        ("engine cpg", "cpg", "humanoid"),
        ("character hexapod", "obb", "hexapod"),
        ("character humanoid", "som", "humanoid"),
        ("character hexapod\nengine obb", "obb", "hexapod"),
        ("engine cpg\ncharacter humanoid", "cpg", "humanoid"),
    ],
)
def test_engine_and_character_default_from_each_other(
    header: str, engine: str, character: str
) -> None:
    script = parse(f"{header}\nwave 10")
    assert (script.engine, script.character) == (engine, character)


def test_settings_with_comments_and_blank_lines_between() -> None:
    script = parse("# header\nfps 60   # smooth\n\nseed 0\n\nwalk 1s")
    assert script.fps == 60 and script.segments[0].frames == 60


def test_largest_setting_values() -> None:
    script = parse(f"fps 240\nseed {2**63 - 1}\nblend 864000\nwalk 1")
    assert (script.fps, script.seed, script.blend_frames) == (240, 2**63 - 1, 864000)


def test_push_event_defaults_and_frame() -> None:
    script = parse("engine cpg\nwalk 300 / push 350N / walk 240", path="c.gait")
    assert script.events == (
        PushEvent(
            frame=300,
            force_n=350.0,
            direction="backward",
            duration_s=0.1,
            span=SourceSpan("c.gait", 2, 12, 9),
        ),
    )
    assert script.events[0].signed_force_n == -350.0
    assert script.total_frames == 540


@pytest.mark.parametrize(
    ("event", "force", "direction", "duration_s"),
    [
        ("push 87.5N forward", 87.5, "forward", 0.1),
        ("push 350N backward 0.25s", 350.0, "backward", 0.25),
        ("push 5000N 6", 5000.0, "backward", 0.2),  # 6 frames at 30 fps
        ("push .5N forward 1s", 0.5, "forward", 1.0),
        ("push 0.001N 0.001s", 0.001, "backward", 0.001),  # not rounded to frames
        ("push 1N 1", 1.0, "backward", 1 / 30),
    ],
)
def test_push_event_forms(event: str, force: float, direction: str, duration_s: float) -> None:
    push = parse(f"walk 30\n{event}\nwalk 30").events[0]
    assert (push.frame, push.force_n, push.direction) == (30, force, direction)
    assert push.duration_s == pytest.approx(duration_s, rel=1e-12)


def test_events_before_the_first_segment_and_several_at_one_frame() -> None:
    script = parse("push 100N\nwalk 10 / push 200N forward / push 300N\nrun 5")
    assert [(e.frame, e.force_n, e.direction) for e in script.events] == [
        (0, 100.0, "backward"),
        (10, 200.0, "forward"),
        (10, 300.0, "backward"),
    ]


def test_an_event_ends_the_header_but_is_no_segment() -> None:
    script = parse("fps 10\npush 100N\nwalk 1s")
    assert script.fps == 10 and script.total_frames == 10


def test_two_word_header_line_with_a_number_is_a_segment() -> None:
    # "Setting or segment?": 'fsp 24' has a duration, so it is a segment; the engine reports
    # the unknown gait (with a hint that it may be a misspelt setting).
    assert frames("fsp 24") == [("fsp", 0, 24)]


def test_total_frames_is_the_sum_and_segments_are_contiguous() -> None:
    script = parse("a 1 / b 2\nc 3s\nd .1s")
    assert script.total_frames == sum(s.frames for s in script.segments) == 1 + 2 + 90 + 3
    for before, after in zip(script.segments, script.segments[1:], strict=False):
        assert after.start_frame == before.end_frame
