"""Resample a :class:`~animstudio.core.clip.Clip` to another frame rate (24/25/60 fps pipelines).

Time rule (docs/batch.md): frame ``k`` of a clip is at ``k / fps`` seconds (docs/conventions.md),
and a clip of ``F`` frames lasts ``F / fps`` seconds. Resampling to ``new_fps`` keeps that
duration: the new clip has ``N = floor(F * new_fps / fps + 0.5)`` frames (at least 1), and new
frame ``k`` shows the source at time ``k / new_fps``, i.e. at fractional source frame
``s = k * fps / new_fps``. Where ``s`` lies past the last source frame ``F - 1`` (the last
``new_fps / fps - 1`` frames when upsampling), the last source pose is held: nothing is
extrapolated.

Between source frames ``i = floor(s)`` and ``i + 1`` with ``t = s - i``, rotations are slerped
(shorter arc), the root translation and every curve are interpolated linearly. Segment
boundaries ``b`` map to ``floor(b * new_fps / fps + 0.5)`` so the segments still tile
``[0, N)`` exactly; a segment shorter than one output frame vanishes (and a note says so).
Events keep their kind and label and move to ``min(floor(frame * new_fps / fps + 0.5), N - 1)``.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from animstudio.core import quat
from animstudio.core.clip import Clip, ClipEvent, ClipSegment


def resampled_frame_count(num_frames: int, fps: float, new_fps: float) -> int:
    """Frames of a clip of ``num_frames`` at ``fps`` after resampling to ``new_fps`` (same duration)."""
    if num_frames < 1 or not fps > 0 or not new_fps > 0:
        raise ValueError(
            f"need num_frames >= 1 and positive rates, got {num_frames}, {fps}, {new_fps}"
        )
    return max(1, _round_half_up(num_frames * new_fps / fps))


def source_positions(num_frames: int, fps: float, new_fps: float) -> NDArray[np.float64]:
    """``(N,)`` fractional source frame shown by each new frame, clamped to ``[0, num_frames - 1]``."""
    n = resampled_frame_count(num_frames, fps, new_fps)
    return np.minimum(np.arange(n, dtype=np.float64) * (fps / new_fps), float(num_frames - 1))


def resample_clip(clip: Clip, fps: float) -> Clip:
    """``clip`` shown at ``fps`` frames per second (the module docstring gives the exact rule).

    Args:
        clip: the source clip.
        fps: the new frame rate, > 0. Equal to ``clip.fps``: ``clip`` itself is returned.

    Returns:
        A new clip with the same skeleton, mesh and notes (plus a note for any segment that
        became shorter than one frame), ``round(F * fps / clip.fps)`` frames.
    """
    if not (isinstance(fps, int | float) and math.isfinite(fps) and fps > 0):
        raise ValueError(f"fps must be a positive number, got {fps!r}")
    if fps == clip.fps:
        return clip
    ratio = fps / clip.fps
    pos = source_positions(clip.num_frames, clip.fps, fps)
    n = pos.shape[0]
    lo = np.floor(pos).astype(np.int64)
    hi = np.minimum(lo + 1, clip.num_frames - 1)
    t = pos - lo

    root = _lerp(clip.root_translations, lo, hi, t)
    q0 = clip.local_rotations[lo].astype(np.float64)
    q1 = clip.local_rotations[hi].astype(np.float64)
    rotations = quat.slerp(q0, q1, t[:, None]).astype(np.float32)
    curves = {name: _lerp(values, lo, hi, t) for name, values in clip.curves.items()}

    segments: list[ClipSegment] = []
    notes = list(clip.notes)
    for seg in clip.segments:
        start = min(_round_half_up(seg.start_frame * ratio), n)
        end = (
            n if seg.end_frame == clip.num_frames else min(_round_half_up(seg.end_frame * ratio), n)
        )
        if end > start:
            segments.append(ClipSegment(seg.gait, start, end))
        else:
            notes.append(
                f"segment {seg.gait!r} (frames {seg.start_frame}-{seg.end_frame} at {clip.fps:g} fps) "
                f"is shorter than one frame at {fps:g} fps and was dropped"
            )
    events = tuple(
        ClipEvent(ev.kind, min(_round_half_up(ev.frame * ratio), n - 1), ev.label)
        for ev in clip.events
    )
    return Clip(
        fps=float(fps),
        skeleton=clip.skeleton,
        root_translations=root,
        local_rotations=rotations,
        segments=tuple(segments),
        events=events,
        curves=curves,
        mesh=clip.mesh,
        notes=tuple(notes),
    )


def _round_half_up(x: float) -> int:
    # Python's round() rounds halves to even; a documented, platform-independent rule is clearer.
    return math.floor(x + 0.5)


def _lerp(
    values: NDArray[np.floating],
    lo: NDArray[np.int64],
    hi: NDArray[np.int64],
    t: NDArray[np.float64],
) -> NDArray[np.float64]:
    v = np.asarray(values, dtype=np.float64)
    w = t.reshape((-1,) + (1,) * (v.ndim - 1))
    return (1.0 - w) * v[lo] + w * v[hi]
