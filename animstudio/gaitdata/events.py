"""Gait events (heel strike, toe-off) detected from sagittal leg angles and the hip path.

The reference trials carry no foot-switch or force-plate events, so events are detected from the
kinematics. Segment lengths other than the thigh are not published for the trials; the foot is
modelled with the character's proportions scaled to the subject's thigh
(:func:`animstudio.gaitdata.legs.leg_points` with ``scale = L_thigh / THIGH_M``): ankle, toe
joint and a heel point ``ANKLE_HEIGHT_M`` below the ankle in the standing foot pose.

* **Heel strike (initial contact)**, in two stages. (1) The stride: the coordinate-based method of
  Zeni, Richards & Higginson (2008, *Gait & Posture* 27:710-714), the instant the foot is
  furthest ahead of the hip, ``a(t) = L_thigh sin Q + L_shank sin F`` (ankle centre relative to
  the hip). (2) The contact itself: the foot is still travelling then (a runner's leg is already
  swinging back, a walker's heel is still 1-2 cm up), so the event is the first instant after it
  at which the foot's lowest point (heel or toe joint) comes within ``CONTACT_M`` of the height
  it settles at in the following ``SETTLE_S`` — linear interpolation between frames.
* **Toe-off** — the toe joint starts rising faster than ``TOE_LIFT_M_S`` for the last time before
  the swing's highest toe position (linear interpolation between frames). Zeni's "toe furthest
  behind the hip" was tried first: in the running trial it comes 0.1 s after the toe has visibly
  left the belt, because a runner's leg keeps travelling backwards in early swing.

docs/training-data.md compares the events found with the ones SOURCES.md states.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.signal import find_peaks

from animstudio.gaitdata.legs import leg_points
from animstudio.rig.proportions import SHANK_M, THIGH_M

MIN_STRIDE_S = 0.4
"""Two heel strikes of the same foot are never closer than this (fastest sprint strides ~0.55 s)."""

CONTACT_M = 0.01
"""Initial contact: the foot's lowest point is within this of its settled stance height."""

SETTLE_S = 0.2
"""The stance height is the lowest the foot gets within this long after the foot-forward peak."""

TOE_LIFT_M_S = 0.1
"""Toe-off: the toe joint starts rising faster than this (m/s) and keeps rising to the swing."""


@dataclass(frozen=True)
class GaitEvents:
    """Events of one foot, in (fractional) frames of the trial, ascending.

    Attributes:
        foot_forward: ``(H,) float64`` Zeni's foot-furthest-ahead instants (stage 1).
        heel_strikes: ``(H,) float64`` initial contacts.
        toe_offs: ``(H - 1,) float64`` toe-off within each stride
            ``[heel_strikes[i], heel_strikes[i + 1])``.
    """

    foot_forward: NDArray[np.float64]
    heel_strikes: NDArray[np.float64]
    toe_offs: NDArray[np.float64]


def ankle_ahead_of_hip(
    thigh_deg: NDArray[np.float64], shank_deg: NDArray[np.float64], thigh_length_m: float
) -> NDArray[np.float64]:
    """``(F,)`` horizontal distance (m) of the ankle centre ahead of the hip (Zeni's signal)."""
    q = np.radians(thigh_deg)
    f = np.radians(shank_deg)
    return thigh_length_m * (np.sin(q) + SHANK_M / THIGH_M * np.sin(f))


def _refine(signal: NDArray[np.float64], index: int) -> float:
    # Vertex of the parabola through three samples: sub-frame timing keeps the cycle period
    # from being quantised to whole 1/30 s frames before resampling.
    if index <= 0 or index >= len(signal) - 1:
        return float(index)
    y0, y1, y2 = signal[index - 1], signal[index], signal[index + 1]
    denom = y0 - 2.0 * y1 + y2
    if denom == 0.0:
        return float(index)
    return float(index + 0.5 * (y0 - y2) / denom)


def _crossing(values: NDArray[np.float64], k: int, level: float) -> float:
    # Fractional frame between k - 1 and k at which the line through the samples meets ``level``.
    y0, y1 = values[k - 1], values[k]
    return float(k - 1 + (level - y0) / (y1 - y0)) if y1 != y0 else float(k)


def _contact(lowest: NDArray[np.float64], forward: int, settle: int) -> float:
    floor = float(np.min(lowest[forward : forward + settle + 1]))
    level = floor + CONTACT_M
    if lowest[forward] <= level:
        return float(forward)
    k = forward + int(np.argmax(lowest[forward:] <= level))
    return _crossing(lowest, k, level)


def _toe_off(toe_y: NDArray[np.float64], fps: float, start: float, end: float) -> float:
    lo, hi = int(np.ceil(start)), int(np.floor(end))
    window = toe_y[lo : hi + 1]
    speed = np.gradient(window) * fps
    # The swing's highest toe position, looked for after the stride's lowest toe position and
    # before the last fifth of the stride (the toe is high again at the next contact, when the
    # foot is dorsiflexed for heel strike).
    cut = max(1, int(0.8 * len(window)))
    low = int(np.argmin(window[:cut]))
    apex = low + int(np.argmax(window[low : max(low + 1, cut)]))
    # From the last instant the toe starts rising faster than TOE_LIFT_M_S before the apex it
    # climbs without stopping, i.e. it has left the ground. (A height threshold fails on the
    # stair trial, whose toe creeps up 1.6 cm while the foot is still planted.)
    rising = np.nonzero((speed[:apex] <= TOE_LIFT_M_S) & (speed[1 : apex + 1] > TOE_LIFT_M_S))[0]
    if rising.size == 0:
        raise ValueError(f"the toe never lifts between frames {start:.1f} and {end:.1f}")
    k = int(rising[-1]) + 1
    return lo + _crossing(speed, k, TOE_LIFT_M_S)


def detect_events(
    angles_deg: NDArray[np.float64],
    hip_y_m: NDArray[np.float64],
    *,
    thigh_length_m: float,
    fps: float,
) -> GaitEvents:
    """Heel strikes and toe-offs of one leg (module docstring: the method).

    Args:
        angles_deg: ``(F, 3)`` thesis Q, F, Y per frame (degrees).
        hip_y_m: ``(F,)`` hip height.
        thigh_length_m: the subject's thigh length.
        fps: frame rate of the arrays.

    Returns:
        The events; extrema at the first or last frame are not events (they may be cut off).

    Raises:
        ValueError: a stride in which the toe never lifts off.
    """
    a = ankle_ahead_of_hip(angles_deg[:, 0], angles_deg[:, 1], thigh_length_m)
    # Within MIN_STRIDE_S only the largest maximum counts, so wobbles during loading never
    # become a second contact. No prominence test: a trial may start a few frames before an
    # event, and a prominence measured against the cut-off edge would reject it. The height
    # margin is a quarter, not a half, of the range because the stair trial's last contact
    # (onto the landing) is a short step: the foot lands only 0.03 m ahead of the hip.
    lo, hi = float(a.min()), float(a.max())
    distance = max(1, int(MIN_STRIDE_S * fps))
    peaks, _ = find_peaks(a, height=lo + 0.25 * (hi - lo), distance=distance)
    points = leg_points(angles_deg, scale=thigh_length_m / THIGH_M)
    lowest = hip_y_m + points.lowest_y()
    toe_y = hip_y_m + points.toe[:, 1]
    settle = max(1, round(SETTLE_S * fps))
    strikes = np.array([_contact(lowest, int(p), settle) for p in peaks], dtype=np.float64)
    offs = np.array(
        [_toe_off(toe_y, fps, s, e) for s, e in itertools.pairwise(strikes)],
        dtype=np.float64,
    )
    return GaitEvents(
        foot_forward=np.array([_refine(a, int(p)) for p in peaks], dtype=np.float64),
        heel_strikes=strikes,
        toe_offs=offs,
    )
