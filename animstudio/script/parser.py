"""The gait-script parser: ``parse(text)`` -> :class:`~animstudio.script.model.Script`.

The language is specified in docs/script-language.md (with its error catalogue, which the tests
check message by message). This module checks syntax and settings only; gait names are checked
against an engine's vocabulary by that engine, through :func:`check_gaits`.

The first problem raises :class:`~animstudio.errors.ScriptError` located at the offending word
(1-based line and column, columns counting characters).
"""

from __future__ import annotations

import difflib
import re
from collections.abc import Collection
from dataclasses import dataclass, field
from decimal import Decimal
from typing import cast

from animstudio.errors import ScriptError, SourceSpan, UnknownName, lookup
from animstudio.script.lexer import BOM, Item, Word, scan
from animstudio.script.model import (
    CHARACTERS,
    ENGINES,
    MAX_DURATION_S,
    CharacterName,
    EngineName,
    PushDirection,
    PushEvent,
    ReinitMode,
    Script,
    Segment,
    Setting,
)
from animstudio.script.quantities import (
    DURATION_HELP,
    Duration,
    looks_numeric,
    parse_duration,
    parse_force,
    parse_integer,
)

SETTING_NAMES = ("engine", "character", "fps", "blend", "reinit", "seed")
RESERVED_WORDS = frozenset((*SETTING_NAMES, "push"))
"""Words that can never be gait names."""

ENGINE_CHARACTER: dict[EngineName, CharacterName] = {
    "som": "humanoid",
    "cpg": "humanoid",
    "obb": "hexapod",
}
CHARACTER_ENGINE: dict[CharacterName, EngineName] = {"humanoid": "som", "hexapod": "obb"}
REINIT_MODES: tuple[ReinitMode, ...] = ("auto", "off")
PUSH_DIRECTIONS: tuple[PushDirection, ...] = ("backward", "forward")

DEFAULT_FPS = 30
MAX_FPS = 240
MAX_SEED = 2**63 - 1  # fits a signed 64-bit integer wherever an engine passes it on
MAX_BLEND_FRAMES = int(MAX_DURATION_S) * MAX_FPS
MAX_PUSH_N = 5000
DEFAULT_PUSH_S = 0.1
MIN_PUSH_S = Decimal("0.001")  # shorter pushes are below any simulator's time step (and float)

_NAME = re.compile(r"[a-z][a-z0-9_]*", re.ASCII)
_KEY = re.compile(r"[A-Za-z_][A-Za-z0-9_]*", re.ASCII)
_NAME_CHAR = re.compile(r"[A-Za-z0-9_]", re.ASCII)
_END_HELP = "expected '/', a new line or a '#' comment"
_SETTING_HELP = {
    "engine": "engine som|cpg|obb",
    "character": "character humanoid|hexapod",
    "fps": "fps N (1 to 240)",
    "blend": "blend N (frames, 0 or more)",
    "reinit": "reinit auto|off",
    "seed": "seed N (0 or more)",
}


def decode_utf8(raw: bytes, *, path: str) -> str:
    """Decode a script file's bytes; a leading UTF-8 BOM is dropped.

    Raises:
        ScriptError: ``invalid UTF-8 byte 0xff`` at the line and column where the first byte that
            is not valid UTF-8 stands (columns count the characters before it on its line).
    """
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        before = raw[: exc.start].decode("utf-8")  # valid: the error is the first bad byte
        if before.startswith(BOM):
            before = before[1:]
        line_start = before.rfind("\n") + 1
        span = SourceSpan(path, before.count("\n") + 1, len(before) - line_start + 1)
        raise ScriptError(span, f"invalid UTF-8 byte 0x{raw[exc.start]:02x}") from None
    return text[1:] if text.startswith(BOM) else text


def parse(text: str, *, path: str = "<string>") -> Script:
    """Parse a gait script.

    Args:
        text: the script (a leading BOM and CRLF line endings are accepted).
        path: the name errors and spans report (the file name, or ``<string>``).

    Returns:
        The script with defaults filled in: segments contiguous from frame 0, events at the frame
        where they stand.

    Raises:
        ScriptError: at the first syntax or setting problem.
    """
    parser = _Parser(path)
    for line in scan(text, path=path):
        for item in line.items:
            parser.item(item, alone=len(line.items) == 1)
    return parser.finish()


def check_gaits(script: Script, gaits: Collection[str], *, engine_label: str) -> list[ScriptError]:
    """One located error per segment whose gait is not in ``gaits`` (in script order).

    Messages read ``unknown gait 'wlak' (did you mean 'walk'?)`` when a valid gait is close, and
    ``unknown gait 'fly' for engine cpg: valid gaits are 'stand', 'walk'`` otherwise.
    """
    valid = sorted(set(gaits))
    listing = ", ".join(f"'{g}'" for g in valid) if valid else "none"
    header_event = any(e.frame == 0 for e in script.events)  # an event before segment 0
    errors = []
    for index, segment in enumerate(script.segments):
        if segment.gait in valid:
            continue
        close = difflib.get_close_matches(segment.gait, valid, n=1, cutoff=0.6)
        if close:
            message = f"unknown gait '{segment.gait}' (did you mean '{close[0]}'?)"
        else:
            message = f"unknown gait '{segment.gait}' for engine {engine_label}: valid gaits are {listing}"
            # The parser reads a header line like 'fsp 24' as a segment (docs: "settings or
            # segments?"); if that is what happened, the user most likely meant a setting.
            setting = difflib.get_close_matches(segment.gait, SETTING_NAMES, n=1, cutoff=0.6)
            if index == 0 and setting and not header_event:
                message += f" (if this line is meant as a setting: did you mean '{setting[0]}'?)"
        errors.append(ScriptError(segment.span, message))
    return errors


@dataclass
class _Parser:
    """The mutable state of one parse; :meth:`finish` freezes it into a Script."""

    path: str
    settings: dict[str, Setting] = field(default_factory=dict)
    name_spans: dict[str, SourceSpan] = field(default_factory=dict)
    engine: EngineName | None = None
    character: CharacterName | None = None
    fps: int = DEFAULT_FPS
    blend_frames: int = 0
    reinit: ReinitMode = "auto"
    seed: int = 0
    segments: list[Segment] = field(default_factory=list)
    events: list[PushEvent] = field(default_factory=list)
    frame: int = 0

    @property
    def in_header(self) -> bool:
        return not self.segments and not self.events

    def error(self, word: Word, message: str) -> ScriptError:
        return ScriptError(word.span(self.path), message)

    # -- items ---------------------------------------------------------------------------------

    def item(self, item: Item, *, alone: bool) -> None:
        words = item.words
        first = words[0].text
        if first == "push":
            self.event(item)
        elif first in SETTING_NAMES:
            self.setting(item, alone=alone)
        elif (
            self.in_header
            and alone
            and len(words) == 2
            and not looks_numeric(words[1].text)
            and "=" not in words[1].text
        ):
            # A two-word header line 'fsp abc' cannot be a segment (its second word is neither a
            # duration nor a parameter): read it as a misspelt setting (docs, "Setting or segment?").
            try:
                lookup("setting", first, SETTING_NAMES)
            except UnknownName as exc:
                raise self.error(words[0], str(exc)) from None
        else:
            self.segment(item)

    def segment(self, item: Item) -> None:
        gait_word, *rest = item.words
        self.check_name(gait_word)
        params: dict[str, str] = {}
        param_spans: dict[str, SourceSpan] = {}
        while rest and "=" in rest[0].text and not looks_numeric(rest[0].text):
            key, value = self.param(rest.pop(0), param_spans)
            params[key] = value
        written = " ".join([gait_word.text, *(f"{k}={v}" for k, v in params.items())])
        if not rest:
            raise self.error(gait_word, f"missing duration after '{written}': {DURATION_HELP}")
        duration_word, *extra = rest
        if not looks_numeric(duration_word.text):
            raise self.error(
                duration_word,
                f"expected a duration after '{written}', got '{duration_word.text}': "
                + DURATION_HELP,
            )
        frames = self.segment_frames(duration_word)
        if extra:
            if "=" in extra[0].text and not looks_numeric(extra[0].text):
                raise self.error(
                    extra[0],
                    "parameters go between the gait and the duration "
                    f"('{gait_word.text} {extra[0].text} {duration_word.text}')",
                )
            raise self.error(
                extra[0],
                f"unexpected '{extra[0].text}' after '{written} {duration_word.text}': {_END_HELP}",
            )
        limit = MAX_DURATION_S * self.fps
        if self.frame + frames > limit:
            raise self.error(
                duration_word,
                f"this segment makes the script longer than 1 hour "
                f"({MAX_DURATION_S:g} s = {limit:.0f} frames at {self.fps} fps)",
            )
        self.segments.append(
            Segment(
                gait=gait_word.text,
                frames=frames,
                start_frame=self.frame,
                span=gait_word.span(self.path),
                duration_span=duration_word.span(self.path),
                params=params,
                param_spans=param_spans,
            )
        )
        self.frame += frames

    def segment_frames(self, word: Word) -> int:
        duration = parse_duration(word, path=self.path)
        frames = duration.to_frames(self.fps)
        if frames >= 1:
            return frames
        if duration.unit == "frames":
            raise self.error(
                word, f"duration {word.text} is zero frames: a segment lasts at least 1 frame"
            )
        raise self.error(word, f"duration {word.text} is less than one frame at {self.fps} fps")

    def check_name(self, word: Word) -> None:
        """A gait name is a lowercase letter followed by lowercase letters, digits and '_'."""
        text = word.text
        if _NAME.fullmatch(text):
            return
        if looks_numeric(text):
            raise self.error(
                word, f"expected a gait name before the duration '{text}' (e.g. 'walk {text}')"
            )
        if "=" in text:
            raise self.error(
                word,
                f"expected a gait name before the parameter '{text}' "
                "(a segment is 'gait [key=value ...] duration')",
            )
        lower = text.lower()
        if _NAME.fullmatch(lower):
            kind = "keywords" if lower in RESERVED_WORDS else "gait names"
            raise self.error(word, f"{kind} are lowercase: '{text}' (did you mean '{lower}'?)")
        for offset, char in enumerate(text):
            if not _NAME_CHAR.fullmatch(char) or (offset == 0 and not char.isalpha()):
                if len(text) == 1:
                    message = f"unexpected '{char}': expected a gait name, 'push' or a setting"
                else:
                    message = (
                        f"unexpected character '{char}' in gait name '{text}': gait names are a "
                        "lowercase letter followed by lowercase letters, digits or '_'"
                    )
                raise ScriptError(word.at(self.path, offset), message)
        raise AssertionError(f"unreachable: {text!r} is a valid name in some case")

    def param(self, word: Word, spans: dict[str, SourceSpan]) -> tuple[str, str]:
        key, _, value = word.text.partition("=")
        if not key:
            raise self.error(word, f"parameter '{word.text}' has no name: write key=value")
        if not _KEY.fullmatch(key):
            bad = next(i for i, c in enumerate(key) if not _KEY.fullmatch(key[: i + 1]))
            raise ScriptError(
                word.at(self.path, bad),
                f"unexpected character '{key[bad]}' in parameter name '{key}': "
                "expected letters, digits or '_'",
            )
        if not value:
            raise self.error(word, f"parameter '{key}' has no value: write {key}=VALUE")
        if key in spans:
            raise self.error(word, f"duplicate parameter '{key}' (first at {_at(spans[key])})")
        spans[key] = word.span(self.path)
        return key, value

    def event(self, item: Item) -> None:
        push, *rest = item.words
        if not rest:
            raise self.error(push, "push needs a force in newtons, e.g. 'push 350N'")
        force_word, *rest = rest
        if not looks_numeric(force_word.text):
            raise self.error(
                force_word,
                f"expected a force after 'push', got '{force_word.text}' (e.g. 'push 350N')",
            )
        force = parse_force(force_word, path=self.path)
        # float(force) > 0 too: a written 1e-400 N is positive but would become a 0.0 N push.
        if not 0 < force <= MAX_PUSH_N or float(force) == 0:
            raise self.error(
                force_word,
                f"push force {force_word.text} is out of range: more than 0 N, at most "
                f"{MAX_PUSH_N} N",
            )
        direction: PushDirection = "backward"
        if rest and not looks_numeric(rest[0].text):
            word = rest.pop(0)
            direction = cast(
                PushDirection, self.lookup_value(word, "push direction", PUSH_DIRECTIONS)
            )
        duration_s = DEFAULT_PUSH_S
        if rest and looks_numeric(rest[0].text):
            duration_s = self.push_seconds(rest.pop(0))
        if rest:
            if rest[0].text in PUSH_DIRECTIONS:
                message = "the direction comes before the duration: 'push 350N backward 0.2s'"
            else:
                written = " ".join(w.text for w in item.words[: len(item.words) - len(rest)])
                message = f"unexpected '{rest[0].text}' after '{written}': {_END_HELP}"
            raise self.error(rest[0], message)
        self.events.append(
            PushEvent(
                frame=self.frame,
                force_n=float(force),
                direction=direction,
                duration_s=duration_s,
                span=item.span(self.path),
            )
        )

    def push_seconds(self, word: Word) -> float:
        duration: Duration = parse_duration(word, path=self.path)
        seconds = duration.value / (self.fps if duration.unit == "frames" else 1)
        if seconds <= 0:
            raise self.error(word, f"push duration {word.text} is zero: a push lasts more than 0 s")
        if seconds < MIN_PUSH_S:
            raise self.error(word, f"push duration {word.text} is shorter than 1 ms")
        if seconds > Decimal(MAX_DURATION_S):
            raise self.error(word, f"push duration {word.text} is longer than 1 hour")
        return duration.to_seconds(self.fps)

    def lookup_value(self, word: Word, kind: str, choices: tuple[str, ...]) -> str:
        try:
            return lookup(kind, word.text, choices)
        except UnknownName as exc:
            raise self.error(word, str(exc)) from None

    def setting(self, item: Item, *, alone: bool) -> None:
        name_word, *rest = item.words
        name = name_word.text
        if not self.in_header:
            raise self.error(name_word, "settings must come before the first segment")
        if not alone:
            raise self.error(name_word, f"setting '{name}' must be alone on its line")
        if name in self.settings:
            first = self.name_spans[name]
            raise self.error(name_word, f"setting '{name}' is given twice (first at {_at(first)})")
        if not rest:
            raise self.error(name_word, f"setting '{name}' needs a value: {_SETTING_HELP[name]}")
        value_word, *extra = rest
        if extra:
            raise self.error(
                extra[0],
                f"unexpected '{extra[0].text}' after '{name} {value_word.text}': "
                "a setting takes one value",
            )
        self.set_value(name, value_word)
        self.settings[name] = Setting(name, value_word.text, value_word.span(self.path))
        self.name_spans[name] = name_word.span(self.path)
        self.check_engine_character(name, value_word)

    def set_value(self, name: str, word: Word) -> None:
        if name == "engine":
            self.engine = cast(EngineName, self.lookup_value(word, "engine", ENGINES))
        elif name == "character":
            self.character = cast(CharacterName, self.lookup_value(word, "character", CHARACTERS))
        elif name == "reinit":
            self.reinit = cast(ReinitMode, self.lookup_value(word, "reinit mode", REINIT_MODES))
        elif name == "fps":
            self.fps = parse_integer(word, path=self.path, what="fps", low=1, high=MAX_FPS)
        elif name == "blend":
            self.blend_frames = parse_integer(
                word, path=self.path, what="blend (frames)", low=0, high=MAX_BLEND_FRAMES
            )
        else:
            assert name == "seed", name
            self.seed = parse_integer(word, path=self.path, what="seed", low=0, high=MAX_SEED)

    def check_engine_character(self, name: str, word: Word) -> None:
        engine, character = self.engine, self.character
        if engine is None or character is None or ENGINE_CHARACTER[engine] == character:
            return
        other = "character" if name == "engine" else "engine"
        raise self.error(
            word,
            f"engine {engine} animates a {ENGINE_CHARACTER[engine]}, not a {character} "
            f"({other} set at {_at(self.settings[other].span)}; a {character} needs engine "
            f"{CHARACTER_ENGINE[character]})",
        )

    # -- the whole script ----------------------------------------------------------------------

    def finish(self) -> Script:
        if not self.segments:
            raise ScriptError(SourceSpan(self.path, 1, 1), "the script has no segments")
        for event in self.events:
            if event.frame >= self.frame:
                raise ScriptError(
                    event.span,
                    "event after the end of the script (an event needs a segment after it)",
                )
        engine = self.engine
        if engine is None:
            engine = CHARACTER_ENGINE[self.character] if self.character is not None else "som"
        return Script(
            path=self.path,
            engine=engine,
            character=self.character or ENGINE_CHARACTER[engine],
            fps=self.fps,
            segments=tuple(self.segments),
            events=tuple(self.events),
            blend_frames=self.blend_frames,
            reinit=self.reinit,
            seed=self.seed,
            settings=tuple(self.settings.values()),
        )


def _at(span: SourceSpan) -> str:
    return f"{span.line}:{span.column}"
