"""The product's main path as pure functions: script text -> Script -> GaitChannels -> Clip.

Files are read here only through :func:`load_script`; writing exports is ``animstudio.export``'s job.
"""

from __future__ import annotations

from pathlib import Path

from animstudio.core.channels import GaitChannels
from animstudio.core.clip import Clip
from animstudio.engines import EngineOptions, get_engine
from animstudio.errors import DataError, ScriptErrors
from animstudio.rig import clip_from_channels
from animstudio.script import parse
from animstudio.script.model import Script


def parse_script(
    text: str, *, path: str = "<string>", options: EngineOptions | None = None
) -> Script:
    """Parse ``text`` and check it against its engine (gait vocabulary, parameters, events).

    Raises:
        ScriptErrors: every located problem found (syntax problems stop at the first).
    """
    script = parse(text, path=path)
    problems = get_engine(script.engine).validate(script, options or EngineOptions())
    if problems:
        raise ScriptErrors(problems)
    return script


def read_script_text(path: Path) -> str:
    """Read a script file as UTF-8 (a located ScriptError for bytes that are not UTF-8)."""
    try:
        raw = path.read_bytes()
    except OSError as exc:
        raise DataError(f"{path}: cannot read script: {exc.strerror or exc}") from exc
    from animstudio.script.parser import decode_utf8

    return decode_utf8(raw, path=str(path))


def load_script(path: Path, *, options: EngineOptions | None = None) -> Script:
    """:func:`parse_script` on the contents of ``path``."""
    return parse_script(read_script_text(path), path=str(path), options=options)


def generate(script: Script, *, options: EngineOptions | None = None) -> GaitChannels:
    """Run the script's engine."""
    return get_engine(script.engine).generate(script, options or EngineOptions())


def render(script: Script, *, options: EngineOptions | None = None) -> Clip:
    """Script to Clip: run the engine, then pose the script's character."""
    return clip_from_channels(generate(script, options=options))
