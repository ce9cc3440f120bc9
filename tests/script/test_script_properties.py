"""Property tests: the parser never fails with anything but a located ScriptError, and generated
valid scripts parse to the frame counts computed here independently (exact fractions)."""

from __future__ import annotations

import math
import string
from dataclasses import dataclass
from fractions import Fraction

from hypothesis import given, settings
from hypothesis import strategies as st

from animstudio.errors import ScriptError
from animstudio.script import Script, parse
from animstudio.script.parser import decode_utf8

# Words that steer random text into every branch of the grammar.
VOCABULARY = [
    "walk", "run", "Walk", "push", "PUSH", "fps", "fsp", "engine", "character", "blend",
    "reinit", "seed", "som", "cpg", "obb", "hexapod", "humanoid", "auto", "off", "forward",
    "backward", "60", "0", "-5", "2s", "1.5s", ".5s", "0.01s", "60.5", "6o", "350N", "350",
    "0N", "r=1,5", "=3", "r=", "3600s", "99999999999999999999", "/", "//", "#", "\n", "\r\n",
    "\t", " ", ";", "@", "\x00", "\u00a0", "\ufeff", "é", "\u2028",
]  # fmt: skip


def check_invariants(script: Script, text: str) -> None:
    """What every successfully parsed script satisfies, whatever its text."""
    assert script.segments
    assert script.segments[0].start_frame == 0
    for before, after in zip(script.segments, script.segments[1:], strict=False):
        assert after.start_frame == before.end_frame
    assert script.total_frames == sum(s.frames for s in script.segments)
    assert all(s.frames >= 1 for s in script.segments)
    assert script.total_frames <= 3600 * script.fps
    assert all(0 <= e.frame < script.total_frames for e in script.events)
    lines = text.removeprefix("\ufeff").split("\n")
    for segment in script.segments:  # the span really points at the gait name
        line = lines[segment.span.line - 1]
        start = segment.span.column - 1
        assert line[start : start + segment.span.length] == segment.gait


def parse_or_error(text: str) -> None:
    try:
        script = parse(text, path="p.gait")
    except ScriptError as exc:
        assert exc.span.path == "p.gait"
        assert exc.span.line >= 1 and exc.span.column >= 1
        assert str(exc).startswith(f"p.gait:{exc.span.line}:{exc.span.column}: ")
        return
    check_invariants(script, text)


@settings(max_examples=300, deadline=None)
@given(st.text())
def test_arbitrary_text_parses_or_raises_script_error(text: str) -> None:
    parse_or_error(text)


@settings(max_examples=300, deadline=None)
@given(st.lists(st.sampled_from(VOCABULARY) | st.text(max_size=3), max_size=30))
def test_arbitrary_word_soup_parses_or_raises_script_error(words: list[str]) -> None:
    parse_or_error(" ".join(words))


@settings(max_examples=300, deadline=None)
@given(
    st.binary()
    | st.lists(st.sampled_from([w.encode() for w in VOCABULARY]) | st.binary(max_size=2)).map(
        b" ".join
    )
)
def test_arbitrary_bytes_decode_and_parse_or_raise_script_error(raw: bytes) -> None:
    try:
        text = decode_utf8(raw, path="p.gait")
    except ScriptError as exc:
        try:
            raw.decode("utf-8")
        except UnicodeDecodeError as decode_error:
            assert exc.span.line == raw[: decode_error.start].count(b"\n") + 1
        else:
            raise AssertionError("decode_utf8 refused valid UTF-8") from exc
        return
    parse_or_error(text)


# -- generated valid scripts ---------------------------------------------------------------------


@dataclass(frozen=True)
class Seg:
    gait: str
    params: tuple[tuple[str, str], ...]
    duration: str  # as written


@dataclass(frozen=True)
class Push:
    force: str  # as written, without N
    direction: str | None
    duration: str | None


def expected_frames(duration: str, fps: int) -> int:
    """Independent of the parser: exact fraction, round half up."""
    if duration.endswith("s"):
        return math.floor(Fraction(duration[:-1]) * fps + Fraction(1, 2))
    return int(duration)


LOWER, DIGITS = string.ascii_lowercase, string.digits
gaits = st.builds(
    str.__add__, st.sampled_from(LOWER), st.text(LOWER + DIGITS + "_", max_size=7)
).filter(lambda g: g not in {"push", "engine", "character", "fps", "blend", "reinit", "seed"})
params = st.lists(
    st.tuples(
        st.builds(
            str.__add__,
            st.sampled_from(string.ascii_letters + "_"),
            st.text(string.ascii_letters + DIGITS + "_", max_size=4),
        ),
        st.text(string.ascii_letters + DIGITS + ".,:+-", min_size=1, max_size=6),
    ),
    max_size=2,
    unique_by=lambda kv: kv[0],
).map(tuple)
seconds = st.builds(
    lambda whole, frac, dot: f"{whole}{'.' if dot or frac else ''}{frac}s",
    st.sampled_from(["", "0", "1", "2", "12"]),
    st.text(DIGITS, max_size=4),
    st.booleans(),
).filter(lambda s: any(c.isdigit() for c in s))
# Half-frame values at common frame rates (0.35 s at 30 fps = 10.5 frames) test the rounding.
half_frames = st.sampled_from(["0.05s", "0.35s", "0.25s", "0.75s", "1.25s", "0.02s", ".1s"])
durations = st.integers(1, 400).map(str) | seconds | half_frames
segments = st.builds(Seg, gaits, params, durations)
pushes = st.builds(
    Push,
    st.sampled_from(["350", "87.5", ".5", "5000", "1"]),
    st.none() | st.sampled_from(["backward", "forward"]),
    st.none() | st.integers(1, 30).map(str) | st.sampled_from(["0.1s", "0.25s", "1s", ".05s"]),
)
blank = st.sampled_from(["", " ", "\t", "  \t"])
comment = st.sampled_from(["", "", " # note", "\t#", "# / walk 60 ; @"])
separator = st.sampled_from([" / ", "/", " /", "/ ", "\t/\t", "\n", "\n\n", "\r\n", "\n# c\n  "])


@st.composite
def valid_scripts(draw: st.DrawFn) -> tuple[str, dict[str, object], list[Seg | Push]]:
    character = draw(st.none() | st.sampled_from(["humanoid", "hexapod"]))
    engines = {"humanoid": ["som", "cpg"], "hexapod": ["obb"], None: ["som", "cpg", "obb"]}
    header: dict[str, object] = {}
    if draw(st.booleans()):
        header["engine"] = draw(st.sampled_from(engines[character]))
    if character is not None:
        header["character"] = character
    for name, strategy in (
        ("fps", st.sampled_from([10, 20, 24, 25, 30, 50, 60]) | st.integers(1, 240)),
        ("blend", st.integers(0, 100)),
        ("reinit", st.sampled_from(["auto", "off"])),
        ("seed", st.integers(0, 2**63 - 1)),
    ):
        if draw(st.booleans()):
            header[name] = draw(strategy)
    order = draw(st.permutations(list(header)))
    header = {name: header[name] for name in order}  # in the order written
    items: list[Seg | Push] = draw(st.lists(segments | pushes, max_size=12))
    items.append(draw(segments))  # the script ends with a segment
    if not any(isinstance(i, Seg) for i in items[:-1]) and draw(st.booleans()):
        items.insert(0, draw(pushes))
    fps = int(header.get("fps", 30))  # type: ignore[call-overload]
    # A seconds duration shorter than one frame is an error (tested elsewhere): write 1 frame.
    items = [
        Seg(i.gait, i.params, "1") if isinstance(i, Seg) and expected_frames(i.duration, fps) < 1
        else i
        for i in items
    ]  # fmt: skip
    gaps = [" ", "\t", "  "]
    parts = [
        f"{draw(blank)}{name}{draw(st.sampled_from(gaps))}{header[name]}{draw(comment)}\n"
        for name in order
    ]
    body = ""
    for index, item in enumerate(items):
        if isinstance(item, Seg):
            words = [item.gait, *(f"{k}={v}" for k, v in item.params), item.duration]
        else:
            words = ["push", f"{item.force}N"]
            words += [w for w in (item.direction, item.duration) if w is not None]
        body += draw(blank) + " ".join(words) + draw(blank)
        if index < len(items) - 1:
            sep = draw(separator)
            body += draw(comment) + sep if "\n" in sep else sep
    text = draw(st.sampled_from(["", "\ufeff"])) + "".join(parts) + body + draw(comment)
    return text, header, items


@settings(max_examples=200, deadline=None)
@given(valid_scripts())
def test_generated_valid_scripts_round_trip(
    case: tuple[str, dict[str, object], list[Seg | Push]],
) -> None:
    text, header, items = case
    script = parse(text, path="v.gait")
    fps = int(header.get("fps", 30))  # type: ignore[call-overload]
    assert script.fps == fps
    assert script.blend_frames == header.get("blend", 0)
    assert script.reinit == header.get("reinit", "auto")
    assert script.seed == header.get("seed", 0)
    assert script.engine == header.get(
        "engine", {"hexapod": "obb"}.get(str(header.get("character")), "som")
    )
    assert script.character == header.get(
        "character", "hexapod" if script.engine == "obb" else "humanoid"
    )
    assert [s.name for s in script.settings] == list(header)

    frame = 0
    expected_segments, expected_events = [], []
    for item in items:
        if isinstance(item, Seg):
            frames = expected_frames(item.duration, fps)
            expected_segments.append((item.gait, dict(item.params), frame, frames))
            frame += frames
        else:
            if item.duration is None:
                duration_s = 0.1
            elif item.duration.endswith("s"):
                duration_s = float(Fraction(item.duration[:-1]))
            else:
                duration_s = int(item.duration) / fps
            direction = item.direction or "backward"
            expected_events.append((frame, float(item.force), direction, duration_s))
    got = [(s.gait, dict(s.params), s.start_frame, s.frames) for s in script.segments]
    assert got == expected_segments
    assert [(e.frame, e.force_n, e.direction, e.duration_s) for e in script.events] == (
        expected_events
    )
    assert script.total_frames == frame
    check_invariants(script, text)
