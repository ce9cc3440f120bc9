"""Frame-rate resampling: frame counts, exact reproduction on the grid, slerp, segments, events."""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from animstudio.core import quat
from animstudio.core.clip import Clip, ClipEvent, ClipSegment
from animstudio.core.resample import resample_clip, resampled_frame_count, source_positions
from animstudio.core.skeleton import Skeleton

SKEL = Skeleton(("root", "a", "b"), (-1, 0, 1), [[0, 1, 0], [0, -0.4, 0], [0, -0.4, 0]])


def _clip(frames: int, fps: float, segments: tuple[int, ...] = (), seed: int = 0) -> Clip:
    """A clip whose pose is an analytic function of time, so any resampling can be checked."""
    t = np.arange(frames) / fps
    angle = 1.2 * np.sin(2.0 * np.pi * 0.7 * t)  # rad, about +Z, slow enough for linear checks
    rot = np.stack([quat.about_z(angle), quat.about_x(0.5 * angle), quat.identity((frames,))], 1)
    root = np.stack([1.3 * t, 0.9 + 0.0 * t, -0.2 * t], 1)
    bounds = (0, *segments, frames)
    segs = tuple(ClipSegment(f"g{i}", a, b) for i, (a, b) in enumerate(itertools.pairwise(bounds)))
    return Clip(
        fps=fps,
        skeleton=SKEL,
        root_translations=root,
        local_rotations=rot,
        segments=segs if segments else (),
        events=(ClipEvent("push", frames // 2, "push 100 N backward"),),
        curves={"angle_deg": np.degrees(angle)},
    )


@pytest.mark.parametrize(
    ("frames", "fps", "new_fps", "expected"),
    [
        (300, 30, 24, 240),
        (300, 30, 25, 250),
        (300, 30, 60, 600),
        (7, 30, 24, 6),
        (1, 30, 24, 1),
        (3, 60, 25, 1),
    ],
)
def test_frame_count_rule(frames: int, fps: float, new_fps: float, expected: int) -> None:
    # N = floor(F * new / old + 0.5): 7 * 0.8 = 5.6 -> 6; 3 * 25/60 = 1.25 -> 1.
    assert resampled_frame_count(frames, fps, new_fps) == expected
    out = resample_clip(_clip(frames, fps), new_fps)
    assert out.num_frames == expected and out.fps == new_fps


def test_same_rate_is_identity() -> None:
    clip = _clip(20, 30.0)
    assert resample_clip(clip, 30) is clip


def test_upsampling_keeps_source_frames_and_slerps_between() -> None:
    clip = _clip(90, 30.0)
    up = resample_clip(clip, 60)
    # Even frames are source frames exactly.
    assert np.allclose(up.local_rotations[0:180:2], clip.local_rotations, atol=1e-6)
    assert np.allclose(up.root_translations[0:180:2], clip.root_translations)
    # The final frame (source position 89.5) holds the last pose.
    assert np.allclose(up.local_rotations[-1], clip.local_rotations[-1])
    assert np.allclose(up.curves["angle_deg"][0:180:2], clip.curves["angle_deg"])


def test_rotation_is_slerped_not_lerped() -> None:
    # 170 degrees about +Z in one frame; 4x upsampling asks for t = 0.25, 0.5, 0.75 in between.
    rot = np.stack([quat.identity((3,)), np.stack([quat.about_z(np.radians(170.0))] * 3)])
    clip = Clip(fps=30.0, skeleton=SKEL, root_translations=np.zeros((2, 3)), local_rotations=rot)
    up = resample_clip(clip, 120)
    assert up.num_frames == 8
    angles = np.degrees(2 * np.arctan2(up.local_rotations[:5, 0, 3], up.local_rotations[:5, 0, 0]))
    assert np.allclose(angles, [0.0, 42.5, 85.0, 127.5, 170.0], atol=1e-3)  # nlerp: 36.6 at t=0.25
    assert np.allclose(up.local_rotations[4:], up.local_rotations[4])  # past the end: held


def test_downsampling_samples_the_motion_at_the_new_times() -> None:
    clip = _clip(300, 30.0)
    down = resample_clip(clip, 24)
    truth = _clip(240, 24.0)  # the same analytic motion sampled at 24 fps
    assert np.allclose(down.root_translations, truth.root_translations, atol=1e-9)  # linear: exact
    # Rotations: interpolating between 1/30 s samples errs by at most (max angular acceleration)
    # * h^2 / 8 = 1.2 * (2 pi 0.7)^2 / (8 * 30^2) = 3.2e-3 rad, plus float32 rounding of the clip
    # (arccos of a float32 dot near 1 resolves ~5e-4 rad).
    bound = 1.2 * (2 * np.pi * 0.7) ** 2 / (8 * 30**2) + 5e-4
    dot = np.abs(np.sum(down.local_rotations.astype(float) * truth.local_rotations, axis=-1))
    err = np.max(2 * np.arccos(np.clip(dot, -1, 1)))
    assert 1e-3 < err < bound  # > 1e-3: the comparison really sees interpolated frames
    # Curves are linear between samples: same h^2 / 8 bound on the 68.75 degree sine.
    curve_bound = np.degrees(1.2) * (2 * np.pi * 0.7) ** 2 / (8 * 30**2) + 1e-9
    curve_err = np.max(np.abs(down.curves["angle_deg"] - truth.curves["angle_deg"]))
    assert 0.05 < curve_err < curve_bound
    assert down.events == (ClipEvent("push", 120, "push 100 N backward"),)


def test_segments_tile_and_short_segment_is_dropped_with_a_note() -> None:
    # g1 = [12, 13) maps to [floor(9.6 + 0.5), floor(10.4 + 0.5)) = [10, 10): empty at 24 fps.
    clip = _clip(31, 30.0, segments=(12, 13, 20))
    down = resample_clip(clip, 24)
    assert [(s.gait, s.start_frame, s.end_frame) for s in down.segments] == [
        ("g0", 0, 10),
        ("g2", 10, 16),
        ("g3", 16, 25),
    ]
    assert any("'g1'" in n and "dropped" in n for n in down.notes)


@settings(max_examples=60, deadline=None)
@given(
    frames=st.integers(1, 400),
    fps=st.sampled_from([24, 25, 30, 60]),
    new_fps=st.sampled_from([24, 25, 30, 60]),
    cuts=st.lists(st.floats(0, 1), max_size=5),
)
def test_properties(frames: int, fps: int, new_fps: int, cuts: list[float]) -> None:
    bounds = tuple(sorted({int(c * frames) for c in cuts} - {0, frames}))
    clip = _clip(frames, float(fps), segments=bounds)
    out = resample_clip(clip, new_fps)
    # Duration preserved to within half an output frame.
    assert abs(out.duration_s - clip.duration_s) <= 0.5 / new_fps + 1e-12
    pos = source_positions(frames, fps, new_fps)
    assert pos[0] == 0 and np.all(np.diff(pos) >= 0) and pos[-1] <= frames - 1
    if clip.segments:
        assert out.segments[0].start_frame == 0 and out.segments[-1].end_frame == out.num_frames
    assert np.allclose(np.linalg.norm(out.local_rotations, axis=-1), 1.0, atol=1e-5)


def test_bad_fps_is_refused() -> None:
    with pytest.raises(ValueError, match="positive"):
        resample_clip(_clip(5, 30.0), 0)
