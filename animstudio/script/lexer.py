"""Splitting gait-script text into lines, items and words (docs/script-language.md, "Lexical rules").

A script is read line by line. On each line, ``#`` starts a comment that runs to the end of the
line; the rest is cut at ``/`` into *items* (a segment, an event or a setting), and each item into
*words* at runs of spaces and tabs. Columns count characters (a tab is one column), 1-based,
which is what :class:`~animstudio.errors.SourceSpan` reports.

The lexer rejects characters that cannot be part of any word (control characters, other kinds
of white space, unassigned code points) and empty items around ``/``; everything else is the
grammar's business (:mod:`animstudio.script.parser`).
"""

from __future__ import annotations

import unicodedata
from collections.abc import Iterator
from dataclasses import dataclass

from animstudio.errors import ScriptError, SourceSpan

BOM = "\ufeff"

# Unicode categories a word may never contain: controls, format characters (zero-width
# space, a BOM in mid-text), surrogates, private use, unassigned, and separators other than
# the plain space and tab that separate words. They are invisible or ambiguous in an editor,
# so silently treating them as spaces or letters would hide the user's mistake.
_FORBIDDEN_CATEGORIES = frozenset({"Cc", "Cf", "Cs", "Co", "Cn", "Zs", "Zl", "Zp"})


@dataclass(frozen=True)
class Word:
    """A run of characters between spaces, tabs and ``/`` on one line.

    Attributes:
        text: the characters as written.
        line: 1-based line number.
        column: 1-based column of the first character.
    """

    text: str
    line: int
    column: int

    def span(self, path: str) -> SourceSpan:
        """The span of the whole word."""
        return SourceSpan(path, self.line, self.column, len(self.text))

    def at(self, path: str, offset: int) -> SourceSpan:
        """The span of the single character ``offset`` characters into the word."""
        return SourceSpan(path, self.line, self.column + offset, 1)


@dataclass(frozen=True)
class Item:
    """The words between two ``/`` (or a line's start/end); never empty."""

    words: tuple[Word, ...]

    def span(self, path: str) -> SourceSpan:
        """From the first word's first character to the last word's last character."""
        first, last = self.words[0], self.words[-1]
        return SourceSpan(
            path, first.line, first.column, last.column + len(last.text) - first.column
        )


@dataclass(frozen=True)
class Line:
    """A line that holds at least one item (blank and comment-only lines are skipped)."""

    number: int
    items: tuple[Item, ...]


def describe_char(char: str) -> str:
    """``'@'`` for a visible character, ``U+00A0 (NO-BREAK SPACE)`` for an invisible one."""
    if unicodedata.category(char) in _FORBIDDEN_CATEGORIES:
        name = unicodedata.name(char, None)
        return f"U+{ord(char):04X}" + (f" ({name})" if name else "")
    return f"'{char}'"


def _forbidden_message(char: str) -> str:
    category = unicodedata.category(char)
    if category == "Cc" or category == "Cf":
        return f"control character {describe_char(char)} is not allowed"
    if category in ("Zs", "Zl", "Zp"):
        return f"unexpected character {describe_char(char)}: separate words with spaces or tabs"
    return f"unexpected character {describe_char(char)}"


def split_lines(text: str) -> Iterator[tuple[int, str]]:
    """Yield ``(line number, content)`` without line endings.

    A leading BOM is dropped (it does not count as a column); lines end at ``\\n`` and one ``\\r``
    before it is part of the line ending (CRLF files). Any other ``\\r`` is a control character.
    """
    if text.startswith(BOM):
        text = text[1:]
    for index, raw in enumerate(text.split("\n")):
        yield index + 1, raw[:-1] if raw.endswith("\r") else raw


def scan_line(number: int, content: str, *, path: str) -> Line:
    """Cut one line into items and words.

    Raises:
        ScriptError: at a forbidden character, or at a ``/`` with nothing before or after it.
    """
    comment = content.find("#")
    code = content if comment < 0 else content[:comment]
    items: list[Item] = []
    words: list[Word] = []
    slashes: list[int] = []  # 0-based column of each '/' seen
    start = -1
    for col, char in enumerate(code + " "):  # the sentinel space ends the last word
        if char in " \t/":
            if start >= 0:
                words.append(Word(code[start:col], number, start + 1))
                start = -1
            if char == "/":
                if not words:
                    raise ScriptError(SourceSpan(path, number, col + 1), _empty_before(slashes))
                items.append(Item(tuple(words)))
                words = []
                slashes.append(col)
            continue
        if unicodedata.category(char) in _FORBIDDEN_CATEGORIES:
            raise ScriptError(SourceSpan(path, number, col + 1), _forbidden_message(char))
        if start < 0:
            start = col
    if words:
        items.append(Item(tuple(words)))
    elif slashes:
        raise ScriptError(
            SourceSpan(path, number, slashes[-1] + 1),
            "empty segment after '/' at the end of the line "
            "(remove the '/': a new line already separates segments)",
        )
    return Line(number, tuple(items))


def _empty_before(slashes: list[int]) -> str:
    if slashes:
        return "empty segment between '/'"
    return "empty segment before '/' (a line cannot start with '/')"


def scan(text: str, *, path: str) -> Iterator[Line]:
    """Yield every line that holds at least one item, in order."""
    for number, content in split_lines(text):
        line = scan_line(number, content, path=path)
        if line.items:
            yield line
