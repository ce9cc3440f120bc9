"""Numbers in a gait script: durations (``60``, ``2s``, ``1.5s``, ``.5s``), forces (``350N``), integers.

Seconds are converted to frames exactly: the written decimal is read as a :class:`~decimal.Decimal`
(never a binary float, so ``0.35s`` at 30 fps is exactly 10.5 frames) and rounded half up, so
``0.35s`` gives 11 frames, not the 10 a float product ``10.499999999999998`` would round to.
Only ASCII digits count: ``str.isdigit`` would accept ``'٣'``.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from decimal import ROUND_HALF_UP, Decimal, localcontext
from typing import Literal

from animstudio.errors import ScriptError
from animstudio.script.lexer import Word

_DECIMAL = r"(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)"
_DURATION = re.compile(rf"({_DECIMAL})(s?)", re.ASCII)
_FORCE = re.compile(rf"({_DECIMAL})N", re.ASCII)
_INTEGER = re.compile(r"[0-9]+", re.ASCII)

# Beyond this many significant integer digits a value is far over any limit the language has
# (one hour at 240 fps is 864000 frames); capping keeps int() away from huge digit strings.
_HUGE_DIGITS = 15
HUGE = 10**_HUGE_DIGITS

DURATION_HELP = "expected frames (60) or seconds (2s, 1.5s)"


def looks_numeric(text: str) -> bool:
    """Whether a word is meant as a number (so an error about it should be about numbers)."""
    return text[:1] in set("0123456789.-+")


def _significant(digits: str) -> str:
    return digits.lstrip("0") or "0"


def _integer(digits: str) -> int:
    """``int(digits)`` for ASCII digits, capped at :data:`HUGE`."""
    digits = _significant(digits)
    return HUGE if len(digits) > _HUGE_DIGITS else int(digits)


@dataclass(frozen=True)
class Duration:
    """A duration as written: whole frames, or seconds (exact decimal)."""

    unit: Literal["frames", "s"]
    value: Decimal

    def to_frames(self, fps: int) -> int:
        """Frames at ``fps``; seconds are rounded half up (1.5 frames -> 2). Capped at :data:`HUGE`."""
        if self.unit == "frames":
            return min(int(self.value), HUGE)
        integer_digits = self.value.adjusted() + 1
        if integer_digits > _HUGE_DIGITS:
            return HUGE
        # Enough precision for every written digit plus fps's: the product and rounding are exact.
        with localcontext() as ctx:
            ctx.prec = len(self.value.as_tuple().digits) + 10
            frames = (self.value * fps).to_integral_value(rounding=ROUND_HALF_UP)
        return int(frames)

    def to_seconds(self, fps: int) -> float:
        """Seconds: as written, or ``frames / fps`` (not rounded to frames)."""
        return float(self.value) / fps if self.unit == "frames" else float(self.value)


def parse_duration(word: Word, *, path: str) -> Duration:
    """Read ``60``, ``2s``, ``1.5s`` or ``.5s``; zero is allowed here (callers check the minimum).

    Raises:
        ScriptError: at ``word`` for anything else, naming what a duration looks like.
    """
    text = word.text
    match = _DURATION.fullmatch(text)
    if match:
        number, unit = match.groups()
        if unit == "s":
            return Duration("s", Decimal(number))
        if "." in number:
            raise ScriptError(
                word.span(path),
                f"duration '{text}' is not a whole number of frames (did you mean '{text}s'?)",
            )
        return Duration("frames", Decimal(_integer(number)))
    if text.startswith("-") and _DURATION.fullmatch(text[1:]):
        raise ScriptError(word.span(path), f"negative duration '{text}': {DURATION_HELP}")
    if text != text.lower() and _DURATION.fullmatch(text.lower()):
        raise ScriptError(
            word.span(path),
            f"durations use a lowercase 's': '{text}' (did you mean '{text.lower()}'?)",
        )
    raise ScriptError(word.span(path), f"'{text}' is not a duration: {DURATION_HELP}")


def parse_force(word: Word, *, path: str) -> Decimal:
    """Read a force in newtons written ``350N`` or ``87.5N`` (range checked by the caller).

    Raises:
        ScriptError: at ``word``: a number without its ``N``, a negative force, or not a force.
    """
    text = word.text
    match = _FORCE.fullmatch(text)
    if match:
        return Decimal(match.group(1))
    if text.startswith("-") and _FORCE.fullmatch(text[1:]):
        return -Decimal(text[1:-1])
    if _DURATION.fullmatch(text) and not text.endswith("s"):
        raise ScriptError(
            word.span(path), f"push force '{text}' has no unit: write '{text}N' (newtons)"
        )
    if text.endswith("n") and _FORCE.fullmatch(text[:-1] + "N"):
        raise ScriptError(
            word.span(path), f"forces are in newtons, 'N': '{text}' (did you mean '{text[:-1]}N'?)"
        )
    raise ScriptError(word.span(path), f"'{text}' is not a force: expected newtons, e.g. 350N")


def parse_integer(word: Word, *, path: str, what: str, low: int, high: int) -> int:
    """Read a whole number from ``low`` to ``high`` (a setting's value).

    Raises:
        ScriptError: at ``word`` naming ``what`` and the range.
    """
    text = word.text
    digits = _significant(text)
    # Compare lengths first: int() of a thousands-digit string is slow, and refused by Python.
    fits = _INTEGER.fullmatch(text) is not None and len(digits) <= len(str(high))
    if not fits or not low <= int(digits) <= high:
        raise ScriptError(
            word.span(path), f"{what} must be a whole number from {low} to {high}, got '{text}'"
        )
    return int(digits)
