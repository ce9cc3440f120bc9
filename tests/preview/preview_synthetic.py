"""A small walk-climb-walk clip on the real humanoid rig, from hand-made gait channels.

The preview tests use it where they need a clip independent of the motion engines (scene
building, stairs, curves, playback): the channels are a plain sinusoidal gait with the root
climbing ``STEPS`` steps of ``RISE_M`` x ``RUN_M`` during the middle segment, one step per half
gait cycle, so the stairs the preview derives can be checked against known values.
"""

from __future__ import annotations

import numpy as np

from animstudio.core.channels import GaitChannels
from animstudio.core.clip import Clip, ClipSegment
from animstudio.rig import clip_from_channels
from animstudio.rig.proportions import STANDING_HIP_HEIGHT_M

FPS = 30
WALK1, CLIMB, WALK2 = 60, 90, 45
STEPS = 6
RISE_M = 0.17
RUN_M = 0.28
CYCLE_FRAMES = 30  # one gait cycle = two steps
SPEED_MPS = 1.2


def synthetic_clip(*, phase_deg: float = 0.0, signals: bool = False) -> Clip:
    """The clip; ``phase_deg`` shifts the leg swing (to tell two versions apart)."""
    n = WALK1 + CLIMB + WALK2
    k = np.arange(n, dtype=np.float64)
    phase = 2 * np.pi * k / CYCLE_FRAMES + np.radians(phase_deg)
    angles = {
        "left_thigh_deg": 20 * np.sin(phase),
        "right_thigh_deg": 20 * np.sin(phase + np.pi),
        "left_shank_deg": 20 * np.sin(phase) - 15 * (1 + np.sin(phase - 1.0)),
        "right_shank_deg": 20 * np.sin(phase + np.pi) - 15 * (1 + np.sin(phase + np.pi - 1.0)),
        "left_foot_deg": -24 + 10 * np.sin(phase),
        "right_foot_deg": -24 + 10 * np.sin(phase + np.pi),
    }
    x = np.empty(n)
    y = np.full(n, STANDING_HIP_HEIGHT_M - 0.03)
    x[:WALK1] = SPEED_MPS * k[:WALK1] / FPS
    # Climb: one step up per half cycle, the rise concentrated in the first half of each step
    # (the push), the run spread evenly.
    step_frames = CLIMB // STEPS
    c = np.arange(CLIMB, dtype=np.float64)
    within = (c % step_frames) / step_frames
    push = np.clip(within * 2, 0, 1)
    steps_done = np.floor(c / step_frames) + 0.5 * (1 - np.cos(np.pi * push))
    x0 = x[WALK1 - 1] + SPEED_MPS / FPS
    x[WALK1 : WALK1 + CLIMB] = x0 + RUN_M * c / step_frames
    y[WALK1 : WALK1 + CLIMB] += RISE_M * steps_done
    top = y[WALK1 + CLIMB - 1]
    x_end = x[WALK1 + CLIMB - 1] + SPEED_MPS / FPS
    x[WALK1 + CLIMB :] = x_end + SPEED_MPS * np.arange(WALK2) / FPS
    y[WALK1 + CLIMB :] = top
    root = np.stack([x, y, np.zeros(n)], axis=1)
    sig = {"neuron_1": np.sin(phase), "neuron_2": np.cos(phase)} if signals else {}
    channels = GaitChannels(
        fps=FPS,
        character="humanoid",
        angles=angles,
        root_position_m=root,
        segments=(
            ClipSegment("walk", 0, WALK1),
            ClipSegment("climb", WALK1, WALK1 + CLIMB),
            ClipSegment("walk", WALK1 + CLIMB, n),
        ),
        signals=sig,
    )
    return clip_from_channels(channels)
