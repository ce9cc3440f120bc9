"""docs/script-language.md tells the truth: its examples parse and its error catalogue is exact."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from animstudio.errors import ScriptError
from animstudio.script import parse

DOC = Path(__file__).resolve().parents[2] / "docs" / "script-language.md"
BLOCK = re.compile(
    r"^```(gait|gait-error|gait-error-escaped)\n(.*?)^```$", re.DOTALL | re.MULTILINE
)
BLOCKS = BLOCK.findall(DOC.read_text(encoding="utf-8"))
EXAMPLES = [body for kind, body in BLOCKS if kind == "gait"]
ERRORS = [(kind, body) for kind, body in BLOCKS if kind != "gait"]


def test_the_doc_has_examples_and_a_catalogue() -> None:
    assert len(EXAMPLES) >= 4
    assert len(ERRORS) >= 50


@pytest.mark.parametrize("text", EXAMPLES)
def test_doc_examples_parse(text: str) -> None:
    assert parse(text, path="shot.gait").segments


@pytest.mark.parametrize(("kind", "body"), ERRORS, ids=[b.split("\n", 1)[0] for _, b in ERRORS])
def test_doc_error_catalogue_is_exact(kind: str, body: str) -> None:
    text, expected = body.split("---\n")
    if kind == "gait-error-escaped":
        text = text.encode("ascii").decode("unicode_escape")
    with pytest.raises(ScriptError) as caught:
        parse(text, path="shot.gait")
    assert str(caught.value) == expected.strip()
