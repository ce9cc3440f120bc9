"""Every syntax error of the gait-script language: exact ``path:line:col: message``."""

from __future__ import annotations

import pytest

from animstudio.errors import ScriptError
from animstudio.script import parse

DURATION_HELP = "expected frames (60) or seconds (2s, 1.5s)"
END_HELP = "expected '/', a new line or a '#' comment"
NAME_RULE = "gait names are a lowercase letter followed by lowercase letters, digits or '_'"

# (script text, "line:column: message")
CASES: list[tuple[str, str]] = [
    # -- script as a whole
    ("", "1:1: the script has no segments"),
    ("# only a comment\n\n   \n", "1:1: the script has no segments"),
    ("fps 24\nseed 3\n", "1:1: the script has no segments"),
    ("push 350N\n", "1:1: the script has no segments"),
    (
        "walk 60\npush 350N",
        "2:1: event after the end of the script (an event needs a segment after it)",
    ),
    (
        "walk 60 / push 350N # last",
        "1:11: event after the end of the script (an event needs a segment after it)",
    ),
    # -- separators
    ("walk 60 / / run 30", "1:11: empty segment between '/'"),
    ("walk 60 //run 30", "1:10: empty segment between '/'"),
    ("/ walk 60", "1:1: empty segment before '/' (a line cannot start with '/')"),
    ("walk 60\n  / run 30", "2:3: empty segment before '/' (a line cannot start with '/')"),
    (
        "walk 60 /\nrun 30",
        "1:9: empty segment after '/' at the end of the line "
        "(remove the '/': a new line already separates segments)",
    ),
    (
        "walk 60 / # more below\nrun 30",
        "1:9: empty segment after '/' at the end of the line "
        "(remove the '/': a new line already separates segments)",
    ),
    # -- stray characters
    ("fps 24\nwalk 60 ; run 30", f"2:9: unexpected ';' after 'walk 60': {END_HELP}"),
    ("walk 60 run 30", f"1:9: unexpected 'run' after 'walk 60': {END_HELP}"),
    ("walk@ 60", f"1:5: unexpected character '@' in gait name 'walk@': {NAME_RULE}"),
    ("wälk 60", f"1:2: unexpected character 'ä' in gait name 'wälk': {NAME_RULE}"),
    ("_walk 60", f"1:1: unexpected character '_' in gait name '_walk': {NAME_RULE}"),
    ("; 60", "1:1: unexpected ';': expected a gait name, 'push' or a setting"),
    ("walk 60\x07", "1:8: control character U+0007 is not allowed"),
    ("walk\x0060", "1:5: control character U+0000 is not allowed"),
    ("walk 6\r0", "1:7: control character U+000D is not allowed"),
    ("walk\u200b 60", "1:5: control character U+200B (ZERO WIDTH SPACE) is not allowed"),
    (
        "walk\u00a060",
        "1:5: unexpected character U+00A0 (NO-BREAK SPACE): separate words with spaces or tabs",
    ),
    # -- segments
    ("60", "1:1: expected a gait name before the duration '60' (e.g. 'walk 60')"),
    ("walk 60\n2s", "2:1: expected a gait name before the duration '2s' (e.g. 'walk 2s')"),
    ("walk", f"1:1: missing duration after 'walk': {DURATION_HELP}"),
    ("walk 60 / run", f"1:11: missing duration after 'run': {DURATION_HELP}"),
    ("walk run 30", f"1:6: expected a duration after 'walk', got 'run': {DURATION_HELP}"),
    ("walk 60 / run fast", f"1:15: expected a duration after 'run', got 'fast': {DURATION_HELP}"),
    ("Walk 60", "1:1: gait names are lowercase: 'Walk' (did you mean 'walk'?)"),
    ("walk 60 / RUN 30", "1:11: gait names are lowercase: 'RUN' (did you mean 'run'?)"),
    ("PUSH 350N\nwalk 1", "1:1: keywords are lowercase: 'PUSH' (did you mean 'push'?)"),
    # -- durations
    ("walk 0", "1:6: duration 0 is zero frames: a segment lasts at least 1 frame"),
    ("walk 000", "1:6: duration 000 is zero frames: a segment lasts at least 1 frame"),
    ("walk -5", f"1:6: negative duration '-5': {DURATION_HELP}"),
    ("walk -2s", f"1:6: negative duration '-2s': {DURATION_HELP}"),
    ("walk 6o", f"1:6: '6o' is not a duration: {DURATION_HELP}"),
    ("walk 1e3", f"1:6: '1e3' is not a duration: {DURATION_HELP}"),
    ("walk +5", f"1:6: '+5' is not a duration: {DURATION_HELP}"),
    ("walk 60f", f"1:6: '60f' is not a duration: {DURATION_HELP}"),
    ("walk 60.5", "1:6: duration '60.5' is not a whole number of frames (did you mean '60.5s'?)"),
    ("walk 2S", "1:6: durations use a lowercase 's': '2S' (did you mean '2s'?)"),
    ("walk 0s", "1:6: duration 0s is less than one frame at 30 fps"),
    ("walk 0.01s", "1:6: duration 0.01s is less than one frame at 30 fps"),
    ("fps 24\nwalk 0.02s", "2:6: duration 0.02s is less than one frame at 24 fps"),
    ("walk 0.0166s", "1:6: duration 0.0166s is less than one frame at 30 fps"),  # 0.498 frames
    (
        "walk 3600.1s",
        "1:6: this segment makes the script longer than 1 hour (3600 s = 108000 frames at 30 fps)",
    ),
    (
        "walk 3000s\nrun 18001",
        "2:5: this segment makes the script longer than 1 hour (3600 s = 108000 frames at 30 fps)",
    ),
    (
        "fps 240\nwalk 99999999999999999999999999999999",
        "2:6: this segment makes the script longer than 1 hour (3600 s = 864000 frames at 240 fps)",
    ),
    (
        "walk " + "9" * 5000,
        "1:6: this segment makes the script longer than 1 hour (3600 s = 108000 frames at 30 fps)",
    ),
    (
        "walk 1" + "0" * 5000 + "s",
        "1:6: this segment makes the script longer than 1 hour (3600 s = 108000 frames at 30 fps)",
    ),
    # -- parameters
    ("obb r=1 r=2 90", "1:9: duplicate parameter 'r' (first at 1:5)"),
    ("obb r= 90", "1:5: parameter 'r' has no value: write r=VALUE"),
    ("obb =1 90", "1:5: parameter '=1' has no name: write key=value"),
    (
        "obb r-x=1 90",
        "1:6: unexpected character '-' in parameter name 'r-x': expected letters, digits or '_'",
    ),
    ("obb 90 r=1", "1:8: parameters go between the gait and the duration ('obb r=1 90')"),
    ("obb r=1,5", f"1:1: missing duration after 'obb r=1,5': {DURATION_HELP}"),
    ("obb r=1,5 fast", f"1:11: expected a duration after 'obb r=1,5', got 'fast': {DURATION_HELP}"),
    (
        "r=1 90",
        "1:1: expected a gait name before the parameter 'r=1' (a segment is 'gait [key=value ...] duration')",
    ),
    # -- settings
    ("walk 60\nfps 24", "2:1: settings must come before the first segment"),
    ("walk 60 / seed 3", "1:11: settings must come before the first segment"),
    ("push 10N\nfps 24\nwalk 1", "2:1: settings must come before the first segment"),
    ("fps 24 / walk 60", "1:1: setting 'fps' must be alone on its line"),
    ("fps 24\nseed 1\nfps 30\nwalk 1", "3:1: setting 'fps' is given twice (first at 1:1)"),
    ("engine som\n  engine som\nwalk 1", "2:3: setting 'engine' is given twice (first at 1:1)"),
    ("fps\nwalk 1", "1:1: setting 'fps' needs a value: fps N (1 to 240)"),
    ("engine\nwalk 1", "1:1: setting 'engine' needs a value: engine som|cpg|obb"),
    ("character\nwalk 1", "1:1: setting 'character' needs a value: character humanoid|hexapod"),
    ("blend\nwalk 1", "1:1: setting 'blend' needs a value: blend N (frames, 0 or more)"),
    ("reinit\nwalk 1", "1:1: setting 'reinit' needs a value: reinit auto|off"),
    ("seed\nwalk 1", "1:1: setting 'seed' needs a value: seed N (0 or more)"),
    ("fps 24 30\nwalk 1", "1:8: unexpected '30' after 'fps 24': a setting takes one value"),
    ("engine cgp\nwalk 1", "1:8: unknown engine 'cgp' (did you mean 'cpg'?)"),
    (
        "engine kohonen\nwalk 1",
        "1:8: unknown engine 'kohonen' (valid choices: 'cpg', 'obb', 'som')",
    ),
    ("character hexapd\nwalk 1", "1:11: unknown character 'hexapd' (did you mean 'hexapod'?)"),
    ("reinit of\nwalk 1", "1:8: unknown reinit mode 'of' (did you mean 'off'?)"),
    ("fps 0\nwalk 1", "1:5: fps must be a whole number from 1 to 240, got '0'"),
    ("fps 241\nwalk 1", "1:5: fps must be a whole number from 1 to 240, got '241'"),
    ("fps 29.97\nwalk 1", "1:5: fps must be a whole number from 1 to 240, got '29.97'"),
    ("fps -1\nwalk 1", "1:5: fps must be a whole number from 1 to 240, got '-1'"),
    ("fps thirty\nwalk 1", "1:5: fps must be a whole number from 1 to 240, got 'thirty'"),
    ("blend -1\nwalk 1", "1:7: blend (frames) must be a whole number from 0 to 864000, got '-1'"),
    (
        "blend 0.5s\nwalk 1",
        "1:7: blend (frames) must be a whole number from 0 to 864000, got '0.5s'",
    ),
    (
        "seed 9223372036854775808\nwalk 1",
        "1:6: seed must be a whole number from 0 to 9223372036854775807, got '9223372036854775808'",
    ),
    (
        "seed " + "9" * 5000 + "\nwalk 1",
        "1:6: seed must be a whole number from 0 to 9223372036854775807, got '" + "9" * 5000 + "'",
    ),
    ("fsp abc\nwalk 1", "1:1: unknown setting 'fsp' (did you mean 'fps'?)"),
    ("engin som\nwalk 1", "1:1: unknown setting 'engin' (did you mean 'engine'?)"),
    (
        "colour red\nwalk 1",
        "1:1: unknown setting 'colour' (valid choices: 'blend', 'character', 'engine', 'fps', 'reinit', 'seed')",
    ),
    (
        "engine som\ncharacter hexapod\nwalk 1",
        "2:11: engine som animates a humanoid, not a hexapod "
        "(engine set at 1:8; a hexapod needs engine obb)",
    ),
    (
        "character humanoid\nengine obb\nwalk 1",
        "2:8: engine obb animates a hexapod, not a humanoid "
        "(character set at 1:11; a humanoid needs engine som)",
    ),
    (
        "engine cpg\ncharacter hexapod\nwalk 1",
        "2:11: engine cpg animates a humanoid, not a hexapod "
        "(engine set at 1:8; a hexapod needs engine obb)",
    ),
    # -- events
    ("push\nwalk 1", "1:1: push needs a force in newtons, e.g. 'push 350N'"),
    (
        "push forward 350N\nwalk 1",
        "1:6: expected a force after 'push', got 'forward' (e.g. 'push 350N')",
    ),
    ("push 350\nwalk 1", "1:6: push force '350' has no unit: write '350N' (newtons)"),
    ("push 350n\nwalk 1", "1:6: forces are in newtons, 'N': '350n' (did you mean '350N'?)"),
    ("push 35oN\nwalk 1", "1:6: '35oN' is not a force: expected newtons, e.g. 350N"),
    ("push 0N\nwalk 1", "1:6: push force 0N is out of range: more than 0 N, at most 5000 N"),
    ("push -350N\nwalk 1", "1:6: push force -350N is out of range: more than 0 N, at most 5000 N"),
    (
        "push 5000.1N\nwalk 1",
        "1:6: push force 5000.1N is out of range: more than 0 N, at most 5000 N",
    ),
    (
        "push 350N sideways\nwalk 1",
        "1:11: unknown push direction 'sideways' (valid choices: 'backward', 'forward')",
    ),
    (
        "push 350N backwards\nwalk 1",
        "1:11: unknown push direction 'backwards' (did you mean 'backward'?)",
    ),
    (
        "push 350N 0.2s backward\nwalk 1",
        "1:16: the direction comes before the duration: 'push 350N backward 0.2s'",
    ),
    (
        "push 350N forward 0.2s 3\nwalk 1",
        f"1:24: unexpected '3' after 'push 350N forward 0.2s': {END_HELP}",
    ),
    ("push 350N 0s\nwalk 1", "1:11: push duration 0s is zero: a push lasts more than 0 s"),
    ("push 350N 0\nwalk 1", "1:11: push duration 0 is zero: a push lasts more than 0 s"),
    ("push 350N -1s\nwalk 1", f"1:11: negative duration '-1s': {DURATION_HELP}"),
    ("push 350N 3601s\nwalk 1", "1:11: push duration 3601s is longer than 1 hour"),
    ("push 350N 0.0009s\nwalk 1", "1:11: push duration 0.0009s is shorter than 1 ms"),
    (
        "push 1e-400N\nwalk 1".replace("1e-400", "0." + "0" * 400 + "1"),
        "1:6: push force 0." + "0" * 400 + "1N is out of range: more than 0 N, at most 5000 N",
    ),
    (
        "push 350N 1.5\nwalk 1",
        "1:11: duration '1.5' is not a whole number of frames (did you mean '1.5s'?)",
    ),
]


@pytest.mark.parametrize(("text", "expected"), CASES, ids=[repr(c[0][:40]) for c in CASES])
def test_error_is_located_with_exact_message(text: str, expected: str) -> None:
    with pytest.raises(ScriptError) as caught:
        parse(text, path="e.gait")
    assert str(caught.value) == f"e.gait:{expected}"
    line, column, message = expected.split(":", 2)
    assert (caught.value.span.path, caught.value.span.line, caught.value.span.column) == (
        "e.gait",
        int(line),
        int(column),
    )
    assert caught.value.message == message.lstrip()


def test_the_first_problem_is_reported() -> None:
    with pytest.raises(ScriptError, match=r"^e\.gait:2:5: '6o'"):
        parse("walk 60\nrun 6o\nclimb 0\nfps 3", path="e.gait")


def test_span_length_covers_the_offending_word() -> None:
    with pytest.raises(ScriptError) as caught:
        parse("walk 60 / run 6oo", path="e.gait")
    assert caught.value.span.length == 3
    with pytest.raises(ScriptError) as caught:
        parse("walk 60\npush 350N forward", path="e.gait")
    assert caught.value.span.length == len("push 350N forward")


def test_crlf_does_not_shift_columns() -> None:
    with pytest.raises(ScriptError, match=r"^e\.gait:2:5: '6o'"):
        parse("\ufeffwalk 60\r\nrun 6o\r\n", path="e.gait")
