"""What an animator wrote: the parsed gait script (docs/script-language.md).

Everything keeps its :class:`~animstudio.errors.SourceSpan`, so any later stage (engine
validation, simulation) can point back at the script line that caused a problem.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Literal

from animstudio.errors import SourceSpan

EngineName = Literal["som", "cpg", "obb"]
CharacterName = Literal["humanoid", "hexapod"]
ReinitMode = Literal["auto", "off"]
PushDirection = Literal["backward", "forward"]

ENGINES: tuple[EngineName, ...] = ("som", "cpg", "obb")
CHARACTERS: tuple[CharacterName, ...] = ("humanoid", "hexapod")

MAX_DURATION_S = 3600.0
"""Longest script accepted (1 hour); beyond it a duration is almost surely a typo."""


@dataclass(frozen=True)
class Setting:
    """A header line ``name value`` as written; ``span`` points at the value."""

    name: str
    value: str
    span: SourceSpan


@dataclass(frozen=True)
class Segment:
    """``gait [key=value ...] duration``: play ``gait`` for ``frames`` frames from ``start_frame``.

    Attributes:
        gait: the gait name as written (checked against the engine's vocabulary by the engine).
        frames: duration in frames at the script's fps (seconds are converted when parsing).
        start_frame: first frame of the segment in the whole script.
        params: expert parameters (``obb r=1,5 90`` gives ``{"r": "1,5"}``), values unparsed:
            the engine that reads them validates them.
        span: where the gait name stands; ``duration_span`` where the duration stands;
            ``param_spans`` where each parameter stands.
    """

    gait: str
    frames: int
    start_frame: int
    span: SourceSpan
    duration_span: SourceSpan
    params: Mapping[str, str] = field(default_factory=dict)
    param_spans: Mapping[str, SourceSpan] = field(default_factory=dict)

    @property
    def end_frame(self) -> int:
        return self.start_frame + self.frames


@dataclass(frozen=True)
class PushEvent:
    """``push 350N [backward|forward] [0.1s]``: a horizontal force on the hip starting at ``frame``.

    ``frame`` is the script time at which the line stands (the end of the preceding segments).
    """

    frame: int
    force_n: float
    direction: PushDirection
    duration_s: float
    span: SourceSpan

    @property
    def signed_force_n(self) -> float:
        """Force along +X (the direction of travel): a backward push is negative."""
        return -self.force_n if self.direction == "backward" else self.force_n

    @property
    def label(self) -> str:
        return f"push {self.force_n:g} N {self.direction} for {self.duration_s:g} s"


Event = PushEvent


@dataclass(frozen=True)
class Script:
    """A parsed gait script.

    Attributes:
        path: the file name errors are reported against (``<string>`` for text).
        engine: ``som`` (Kohonen controller), ``cpg`` (biped simulation), ``obb`` (hexapod).
        character: ``humanoid`` or ``hexapod``.
        fps: frames per second of the output and of frame durations.
        blend_frames: Kohonen engine: frames over which a gait change is cross-faded
            (0, the default, is the thesis's hard switch).
        reinit: cpg engine: ``auto`` chooses the posture controller's knee angle after a push,
            ``off`` disables the posture controller (phi_c = 0).
        seed: seed for anything random an engine does.
        settings: the header lines as written (for locating errors about them).
        segments: in script order, contiguous from frame 0.
        events: in script order.
    """

    path: str
    engine: EngineName
    character: CharacterName
    fps: int
    segments: tuple[Segment, ...]
    events: tuple[Event, ...] = ()
    blend_frames: int = 0
    reinit: ReinitMode = "auto"
    seed: int = 0
    settings: tuple[Setting, ...] = ()

    @property
    def total_frames(self) -> int:
        return self.segments[-1].end_frame if self.segments else 0

    @property
    def duration_s(self) -> float:
        return self.total_frames / self.fps

    def setting_span(self, name: str) -> SourceSpan | None:
        """Where setting ``name`` was written, if it was."""
        for s in self.settings:
            if s.name == name:
                return s.span
        return None
