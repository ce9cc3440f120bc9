"""Fixtures shared across test areas. Keep this small and generic."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import pytest

from animstudio.core.channels import GaitChannels
from animstudio.core.clip import Clip, ClipEvent, ClipSegment


def make_humanoid_channels(
    num_frames: int = 90,
    fps: float = 30.0,
    *,
    start_m: tuple[float, float] = (0.0, 0.0),
    speed_mps: float = 1.3,
    period_s: float = 1.1,
) -> GaitChannels:
    """Walk-like humanoid channels from sinusoids (thesis-sized angles), two segments, one event.

    ``start_m`` is the root's (x, z) at frame 0: put it far away to test float precision.
    """
    t = np.arange(num_frames) / fps
    phase = 2.0 * np.pi * t / period_s
    angles: dict[str, np.ndarray] = {}
    contacts: dict[str, np.ndarray] = {}
    for side, offset in (("left", 0.0), ("right", np.pi)):
        p = phase + offset
        angles[f"{side}_thigh_deg"] = 8.0 + 20.0 * np.sin(p)
        angles[f"{side}_shank_deg"] = -12.0 + 25.0 * np.sin(p - 0.9)
        angles[f"{side}_foot_deg"] = -24.0 + 18.0 * np.sin(p - 1.6)
        contacts[f"{side}_foot"] = np.sin(p - 0.3) < 0.2
    root = np.stack(
        [
            start_m[0] + speed_mps * t,
            0.91 + 0.02 * np.cos(2.0 * phase),
            start_m[1] + 0.01 * np.sin(phase),
        ],
        axis=1,
    )
    half = max(1, num_frames // 2)
    segments = (
        (ClipSegment("walk", 0, half), ClipSegment("run", half, num_frames))
        if num_frames > 1
        else (ClipSegment("walk", 0, 1),)
    )
    return GaitChannels(
        fps=fps,
        character="humanoid",
        angles=angles,
        root_position_m=root,
        contacts=contacts,
        segments=segments,
        events=(ClipEvent("push", num_frames // 3, "push 100 N backward for 0.1 s"),),
        signals={"phase_rad": np.mod(phase, 2.0 * np.pi)},
        notes=("synthetic test clip",),
    )


@pytest.fixture
def synthetic_humanoid_clip() -> Callable[..., Clip]:
    """Factory ``make(num_frames=90, fps=30.0, **kwargs) -> Clip`` posing synthetic channels.

    Keyword arguments go to :func:`make_humanoid_channels` (``start_m``, ``speed_mps``, ...).
    """
    from animstudio.rig.humanoid import clip_from_channels

    def make(num_frames: int = 90, fps: float = 30.0, **kwargs: object) -> Clip:
        return clip_from_channels(make_humanoid_channels(num_frames, fps, **kwargs))  # type: ignore[arg-type]

    return make


@pytest.fixture
def synthetic_humanoid_channels() -> Callable[..., GaitChannels]:
    """Factory ``make(num_frames=90, fps=30.0, **kwargs) -> GaitChannels`` (walk-like sinusoids)."""
    return make_humanoid_channels
