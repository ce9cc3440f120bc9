"""check_gaits (used by every engine's validate) and decode_utf8 (used when loading a file)."""

from __future__ import annotations

import pytest

from animstudio.errors import ScriptError
from animstudio.script import parse
from animstudio.script.parser import check_gaits, decode_utf8

CPG = ("walk", "stand")


def messages(text: str, gaits: tuple[str, ...] = CPG, label: str = "cpg") -> list[str]:
    return [str(e) for e in check_gaits(parse(text, path="g.gait"), gaits, engine_label=label)]


def test_known_gaits_give_no_errors() -> None:
    assert messages("walk 60 / stand 30\nwalk 1") == []


def test_one_located_error_per_unknown_segment_in_order() -> None:
    assert messages("wlak 60 / stand 30 / fly 3\nwlak 2") == [
        "g.gait:1:1: unknown gait 'wlak' (did you mean 'walk'?)",
        "g.gait:1:22: unknown gait 'fly' for engine cpg: valid gaits are 'stand', 'walk'",
        "g.gait:2:1: unknown gait 'wlak' (did you mean 'walk'?)",
    ]


def test_a_biped_gait_in_a_hexapod_script_lists_the_valid_gaits() -> None:
    assert messages("engine obb\nwalk 60", ("wave", "tetrapod", "tripod", "obb"), "obb") == [
        "g.gait:2:1: unknown gait 'walk' for engine obb: valid gaits are "
        "'obb', 'tetrapod', 'tripod', 'wave'"
    ]


def test_errors_are_script_errors_with_the_gait_span() -> None:
    (error,) = check_gaits(parse("walk 1 / run 2"), CPG, engine_label="cpg")
    assert isinstance(error, ScriptError)
    assert (error.span.line, error.span.column, error.span.length) == (1, 10, 3)


def test_a_setting_like_first_segment_gets_a_setting_hint() -> None:
    assert messages("fsp 24\nwalk 60") == [
        "g.gait:1:1: unknown gait 'fsp' for engine cpg: valid gaits are 'stand', 'walk' "
        "(if this line is meant as a setting: did you mean 'fps'?)"
    ]
    # ... but not after the header, where it cannot be a setting
    assert messages("walk 60\nfsp 24") == [
        "g.gait:2:1: unknown gait 'fsp' for engine cpg: valid gaits are 'stand', 'walk'"
    ]
    assert messages("push 300N\nfsp 24") == [
        "g.gait:2:1: unknown gait 'fsp' for engine cpg: valid gaits are 'stand', 'walk'"
    ]


def test_an_engine_without_gaits_says_so() -> None:
    assert messages("walk 1", (), "som (weights w.npz)") == [
        "g.gait:1:1: unknown gait 'walk' for engine som (weights w.npz): valid gaits are none"
    ]


# -- decode_utf8 ---------------------------------------------------------------------------------


def test_utf8_decodes_and_drops_a_bom() -> None:
    assert decode_utf8("walk 60 # é\n".encode(), path="x") == "walk 60 # é\n"
    assert decode_utf8(b"\xef\xbb\xbfwalk 60", path="x") == "walk 60"
    assert decode_utf8(b"", path="x") == ""


@pytest.mark.parametrize(
    ("raw", "expected"),
    [
        (b"walk 60\nrun 3\xff0\n", "s.gait:2:6: invalid UTF-8 byte 0xff"),
        (b"\xfe", "s.gait:1:1: invalid UTF-8 byte 0xfe"),
        (b"\xef\xbb\xbfwalk \xe9", "s.gait:1:6: invalid UTF-8 byte 0xe9"),  # BOM not counted
        ("# é€\r\nwalk".encode() + b" \x80", "s.gait:2:6: invalid UTF-8 byte 0x80"),
        ("é€ ".encode() + b"\xc3", "s.gait:1:4: invalid UTF-8 byte 0xc3"),  # truncated sequence
        (b"a\xed\xa0\x80", "s.gait:1:2: invalid UTF-8 byte 0xed"),  # encoded surrogate
    ],
)
def test_invalid_utf8_is_located_at_the_first_bad_byte(raw: bytes, expected: str) -> None:
    with pytest.raises(ScriptError) as caught:
        decode_utf8(raw, path="s.gait")
    assert str(caught.value) == expected
