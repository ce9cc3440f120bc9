"""Stairs rebuilt from the root motion of climb segments."""

from __future__ import annotations

import numpy as np
import pytest
from preview_synthetic import CLIMB, RISE_M, RUN_M, STEPS, WALK1

from animstudio.core.clip import Clip, ClipSegment
from animstudio.preview.stairs import count_steps, stairs_for_clip


def test_flight_matches_the_climb_it_was_made_from(walk_climb_clip: Clip) -> None:
    (flight,) = stairs_for_clip(walk_climb_clip)
    assert (flight.start_frame, flight.end_frame) == (WALK1, WALK1 + CLIMB)
    assert flight.num_steps == STEPS
    # The segment's root moves through all but the last frame's worth of the climb.
    assert flight.rise_m == pytest.approx(RISE_M, rel=0.02)
    assert flight.run_m == pytest.approx(RUN_M, rel=0.03)
    tops = [b.center[1] + 0.5 * b.size[1] for b in flight.boxes]
    assert np.allclose(np.diff(tops[:STEPS]), flight.rise_m)
    assert tops[-1] == pytest.approx(tops[STEPS - 1])  # the landing is level with the top step
    bottoms = [b.center[1] - 0.5 * b.size[1] for b in flight.boxes]
    assert np.allclose(bottoms, 0.0)
    # Steps stand one after the other along +X, without gaps or overlaps.
    fronts = [b.center[0] - 0.5 * b.size[0] for b in flight.boxes]
    backs = [b.center[0] + 0.5 * b.size[0] for b in flight.boxes]
    assert np.allclose(fronts[1:], backs[:-1])


def test_no_stairs_without_climbing(walk_climb_clip: Clip) -> None:
    clip = walk_climb_clip
    relabelled = Clip(
        fps=clip.fps,
        skeleton=clip.skeleton,
        root_translations=clip.root_translations,
        local_rotations=clip.local_rotations,
        segments=tuple(ClipSegment("walk", s.start_frame, s.end_frame) for s in clip.segments),
    )
    assert stairs_for_clip(relabelled) == ()
    flat_root = clip.root_translations.copy()
    flat_root[:, 1] = flat_root[0, 1]
    flat = Clip(
        fps=clip.fps,
        skeleton=clip.skeleton,
        root_translations=flat_root,
        local_rotations=clip.local_rotations,
        segments=clip.segments,
    )
    assert stairs_for_clip(flat) == ()


@pytest.mark.parametrize("steps", [1, 3, 8])
def test_count_steps_counts_pushes(steps: int) -> None:
    per = 20
    k = np.arange(steps * per)
    within = (k % per) / per
    y = 0.17 * (k // per + 0.5 * (1 - np.cos(np.pi * np.clip(2 * within, 0, 1))))
    assert count_steps(y) == steps


def test_count_steps_of_a_steady_ramp_is_one() -> None:
    assert count_steps(np.linspace(0.0, 1.0, 50)) == 1
