"""Stairs for ``climb`` segments, derived from how the character's root moves while climbing.

A clip does not store the terrain, so the preview rebuilds it from the motion: during a climb
segment the root rises by the flight's total height and advances by its total run. The number
of steps comes from the upward pushes in the root's vertical velocity (one per foot placed on
a new step, :func:`count_steps`); the step rise and run are the totals divided by it. Each step is a
solid box standing on the floor level the flight started from, and the top landing reaches to
where the root next goes down (or to the end of the clip).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from animstudio.core.clip import Clip

CLIMB_GAITS = frozenset({"climb"})
"""Segment gait names that climb stairs."""

LANDING_MARGIN_M = 0.6
"""How far the top landing extends beyond the root's last position on it (the feet reach ahead)."""

PUSH_FRACTION = 0.3
"""Frames rising faster than this fraction of the fastest rise belong to a push."""

STAIR_WIDTH_M = 1.0
"""Across the direction of travel (Z); wide enough for both feet."""


@dataclass(frozen=True)
class StepBox:
    """One axis-aligned box: ``center`` and ``size`` ``(3,)`` metres (X forward, Y up, Z right)."""

    center: tuple[float, float, float]
    size: tuple[float, float, float]


@dataclass(frozen=True)
class StairFlight:
    """The stairs one climb segment goes up.

    Attributes:
        start_frame, end_frame: the climb segment's frames ``[start, end)``.
        num_steps: steps counted from the root's vertical pushes (>= 1).
        rise_m: height of each step.
        run_m: depth of each step along +X.
        boxes: ``num_steps`` step boxes followed by the top landing.
    """

    start_frame: int
    end_frame: int
    num_steps: int
    rise_m: float
    run_m: float
    boxes: tuple[StepBox, ...]


def count_steps(root_y: NDArray[np.float64]) -> int:
    """Steps climbed in a climb segment's root height curve ``(N,)`` (at least 1).

    The hip rises in pushes, one per foot placed on a new step, with a pause between while the
    other foot swings. A push is a run of frames whose vertical velocity exceeds
    ``PUSH_FRACTION`` of the largest; the push period is the median spacing of the pushes'
    fastest frames, and the segment climbs one step per period. (Counting pushes directly
    would count the half push a segment boundary cuts as a whole step.)
    """
    n = root_y.shape[0]
    if n < 3:
        return 1
    vy = np.gradient(root_y)
    top = float(vy.max())
    if top <= 0.0:
        return 1
    pushing = np.concatenate([[False], vy > PUSH_FRACTION * top, [False]])
    edges = np.flatnonzero(np.diff(pushing.astype(np.int8)))
    peaks = [a + int(np.argmax(vy[a:b])) for a, b in zip(edges[0::2], edges[1::2], strict=True)]
    if len(peaks) < 2:
        return 1
    period = float(np.median(np.diff(peaks)))
    return max(1, round(n / period))


def stairs_for_clip(clip: Clip, *, floor_y: float | None = None) -> tuple[StairFlight, ...]:
    """One :class:`StairFlight` per climb segment of ``clip`` that rises.

    Args:
        clip: the clip; its ``segments`` name the gaits.
        floor_y: height of the ground the clip starts on (default 0, the world floor).

    Returns:
        The flights in segment order; a climb segment whose root does not rise gets none.
    """
    root = clip.root_translations
    ground = 0.0 if floor_y is None else float(floor_y)
    flights: list[StairFlight] = []
    level = ground
    for seg in clip.segments:
        if seg.gait not in CLIMB_GAITS:
            continue
        end = min(seg.end_frame, clip.num_frames - 1)
        y = root[seg.start_frame : end + 1, 1]
        rise_total = float(y[-1] - y[0])
        run_total = float(root[end, 0] - root[seg.start_frame, 0])
        if rise_total <= 1e-3 or run_total <= 1e-3:
            continue
        n = count_steps(y)
        rise, run = rise_total / n, run_total / n
        x0 = float(root[seg.start_frame, 0])
        z = float(np.mean(root[seg.start_frame : end + 1, 2]))
        boxes = []
        for i in range(1, n + 1):
            # Riser i stands i runs past the root's position at the start of the climb: where the
            # som engine's feet land (its climb puts the heel of the foot stepping onto step i
            # about one run ahead of the hip that is still below it).
            top = level + i * rise
            x_front = x0 + i * run
            boxes.append(
                StepBox(
                    center=(x_front + 0.5 * run, 0.5 * (top + ground), z),
                    size=(run, top - ground, STAIR_WIDTH_M),
                )
            )
        landing_start = x0 + (n + 1) * run
        landing_end = _landing_end(root, end, float(y[-1]), rise) + LANDING_MARGIN_M
        top = level + n * rise
        if landing_end > landing_start:
            boxes.append(
                StepBox(
                    center=(0.5 * (landing_start + landing_end), 0.5 * (top + ground), z),
                    size=(landing_end - landing_start, top - ground, STAIR_WIDTH_M),
                )
            )
        flights.append(StairFlight(seg.start_frame, seg.end_frame, n, rise, run, tuple(boxes)))
        level = top
    return tuple(flights)


def _landing_end(root: NDArray[np.float64], from_frame: int, top_y: float, rise: float) -> float:
    # The landing carries the character while its root stays at the top height; dropping by
    # more than half a step means it went down again.
    tolerance = max(0.5 * rise, 0.05)
    below = np.nonzero(root[from_frame:, 1] < top_y - tolerance)[0]
    last = root.shape[0] - 1 if below.size == 0 else from_frame + int(below[0]) - 1
    return float(root[max(last, from_frame), 0])
