"""The gait-script language: ``parse(text)`` -> :class:`Script` (docs/script-language.md)."""

from animstudio.script.model import PushEvent, Script, Segment, Setting
from animstudio.script.parser import parse

__all__ = ["PushEvent", "Script", "Segment", "Setting", "parse"]
