"""The project's error types.

Caller mistakes raise an :class:`AnimstudioError` subclass; only ``animstudio.cli`` turns
them into messages and exit codes. Every error's ``str()`` is a complete, user-facing message.
"""

from __future__ import annotations

import difflib
from collections.abc import Iterable
from dataclasses import dataclass


class AnimstudioError(Exception):
    """Base of every error animstudio raises on purpose."""


@dataclass(frozen=True)
class SourceSpan:
    """Where something stands in a script: 1-based line and column, and its length in characters."""

    path: str
    line: int
    column: int
    length: int = 1

    def __str__(self) -> str:
        return f"{self.path}:{self.line}:{self.column}"


class ScriptError(AnimstudioError):
    """A problem in a gait script, located at a :class:`SourceSpan`.

    Renders as ``walk.gait:3:9: unknown gait 'wlak' (did you mean 'walk'?)``.
    """

    def __init__(self, span: SourceSpan, message: str) -> None:
        super().__init__(f"{span}: {message}")
        self.span = span
        self.message = message


class ScriptErrors(AnimstudioError):
    """Several located script errors found in one pass (``animstudio check`` lists them all)."""

    def __init__(self, errors: Iterable[ScriptError]) -> None:
        self.errors = tuple(errors)
        assert self.errors, "ScriptErrors needs at least one error"
        super().__init__("\n".join(str(e) for e in self.errors))


class DataError(AnimstudioError):
    """A data file (weights, training data, USD input, reference gait) is missing, corrupt or of the wrong shape."""


class ExportError(AnimstudioError):
    """An export could not be written (bad extension, unwritable directory, ...)."""


class SimulationError(AnimstudioError):
    """A simulation could not be carried out with the given settings (not a fall: falls are reported, not raised)."""


def suggest(name: str, choices: Iterable[str]) -> str:
    """Return the ``(did you mean 'x'?)``-style hint listing the valid choices for an unknown name."""
    options = sorted(set(choices))
    close = difflib.get_close_matches(name, options, n=1, cutoff=0.6)
    if close:
        return f"did you mean '{close[0]}'?"
    return "valid choices: " + ", ".join(f"'{o}'" for o in options)


def lookup(kind: str, name: str, choices: Iterable[str]) -> str:
    """Return ``name`` if it is one of ``choices``, else raise :class:`UnknownName`.

    The message reads ``unknown gait 'wlak' (did you mean 'walk'?)``; the parser wraps it in a
    :class:`ScriptError` with the span of the name so the user sees where it stands.
    """
    options = tuple(choices)
    if name in options:
        return name
    raise UnknownName(f"unknown {kind} '{name}' ({suggest(name, options)})")


class UnknownName(AnimstudioError):
    """A name (gait, engine, character, setting, format) that is not among the valid choices."""
