"""Data for the curves panel: joint-angle (and neuron) curves, a playhead and segment boundaries.

uPlot (viser's ``add_uplot``) draws series over one shared, sorted x array. Vertical lines are
drawn as an extra series on their own scale ``"mark"`` fixed to ``[0, 1]``: each line is two
points at the same x, from below the plot to above it, and consecutive lines are joined
*outside* the plotted range where uPlot clips them, so only the verticals show. The x array
therefore holds the frame times plus those line points; the curves are interpolated there
(exactly their value at a frame time, linear between) so they stay unbroken. Values a series
does not have are NaN, which uPlot skips when drawing a line.

Only a window of ``window_s`` seconds around the playhead is sent (the whole clip with
``window_s=None``): a minute of animation at 30 fps is 1800 samples per curve, resent on every
playhead move, where a window keeps each update to a few kilobytes.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any, Literal

import numpy as np
from numpy.typing import NDArray

from animstudio.core.clip import Clip

CurveGroup = Literal["angles", "signals"]

PALETTE = (
    "#1f77b4",
    "#d62728",
    "#2ca02c",
    "#ff7f0e",
    "#9467bd",
    "#8c564b",
    "#e377c2",
    "#17becf",
    "#bcbd22",
    "#7f7f7f",
)
PLAYHEAD_COLOR = "#000000"
BOUNDARY_COLOR = "#9a9a9a"
MARK_SCALE = "mark"
_BELOW, _ABOVE = -0.05, 1.05  # outside the mark scale's [0, 1]: joins there are clipped away


ALL_LIMBS = "all"


def curve_names(clip: Clip, group: CurveGroup, *, limb: str = ALL_LIMBS) -> tuple[str, ...]:
    """The clip's curves of one group: ``angles`` are the ``*_deg`` ones, ``signals`` the rest.

    ``limb`` keeps only the curves whose name starts with ``limb + "_"`` (``left``, ``R2`` ...).
    """
    names = sorted(clip.curves)
    if limb != ALL_LIMBS:
        names = [n for n in names if n.startswith(limb + "_")]
    if group == "angles":
        return tuple(n for n in names if n.endswith("_deg"))
    return tuple(n for n in names if not n.endswith("_deg"))


def limbs(clip: Clip) -> tuple[str, ...]:
    """Choices for filtering the curves by limb: ``all`` then the names' first words.

    The humanoid's curves start ``left_`` / ``right_``, the hexapod's ``L1_`` ... ``R3_``
    (docs/conventions.md); a first word shared by a single curve is not offered.
    """
    heads = [n.split("_", 1)[0] for n in clip.curves if "_" in n]
    return (ALL_LIMBS, *sorted({h for h in heads if heads.count(h) > 1}))


@dataclass(frozen=True, eq=False)
class PlotData:
    """One uPlot payload.

    Attributes:
        data: ``(x, *curves, boundaries, playhead)`` 1-D float64 arrays of equal length;
            ``x`` in seconds, ascending.
        series: the uPlot series options, one per array of ``data``.
    """

    data: tuple[NDArray[np.float64], ...]
    series: tuple[dict[str, Any], ...]


def _vertical_lines(times: Sequence[float]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    # Each line goes bottom->top or top->bottom, alternating, so the joins run outside the plot.
    xs = np.repeat(np.asarray(times, dtype=np.float64), 2)
    ys = np.empty_like(xs)
    ys[0::4], ys[1::4] = _BELOW, _ABOVE
    ys[2::4], ys[3::4] = _ABOVE, _BELOW
    return xs, ys


def plot_data(
    clip: Clip,
    names: Sequence[str],
    *,
    playhead_frame: int,
    window_s: float | None,
    normalize: bool = False,
) -> PlotData:
    """The curves ``names`` of ``clip`` around ``playhead_frame``, with the playhead and boundaries.

    Args:
        clip: the clip whose ``curves`` to plot.
        names: curve names (keys of ``clip.curves``), plotted in this order.
        playhead_frame: the frame shown in the 3D view.
        window_s: seconds of curve shown, centred on the playhead where the clip allows
            (``None``: the whole clip).
        normalize: scale each curve to ``[0, 1]`` over the whole clip, its range in its label
            (for engine signals of mixed units: neuron activity next to a unit index).
    """
    fps = clip.fps
    n = clip.num_frames
    frame = min(max(int(playhead_frame), 0), n - 1)
    if window_s is None or window_s * fps >= n:
        lo, hi = 0, n - 1
    else:
        half = round(0.5 * window_s * fps)
        lo = min(max(frame - half, 0), max(n - 1 - 2 * half, 0))
        hi = min(lo + 2 * half, n - 1)
    t_frames = np.arange(lo, hi + 1, dtype=np.float64) / fps
    t_play = frame / fps
    boundaries = [s.start_frame / fps for s in clip.segments[1:] if lo < s.start_frame <= hi]
    bx, by = _vertical_lines(boundaries)
    px, py = _vertical_lines([t_play])
    x = np.concatenate([t_frames, bx, px])
    kind = np.concatenate([np.zeros(t_frames.size), np.ones(bx.size), np.full(px.size, 2.0)])
    mark_y = np.concatenate([np.full(t_frames.size, np.nan), by, py])
    order = np.argsort(x, kind="stable")
    x, kind, mark_y = x[order], kind[order], mark_y[order]
    all_t = np.arange(n, dtype=np.float64) / fps
    data: list[NDArray[np.float64]] = [x]
    series: list[dict[str, Any]] = [{"label": "time (s)"}]
    for i, name in enumerate(names):
        values = clip.curves[name]
        label = name
        if normalize:
            lo_v, hi_v = float(values.min()), float(values.max())
            span = hi_v - lo_v if hi_v > lo_v else 1.0
            values = (values - lo_v) / span
            label = f"{name} [{lo_v:.3g}, {hi_v:.3g}]"
        data.append(np.interp(x, all_t, values))
        series.append(
            {"label": label, "stroke": PALETTE[i % len(PALETTE)], "width": 1.5, "scale": "y"}
        )
    data.append(np.where(kind == 1, mark_y, np.nan))
    series.append(
        {
            "label": "segment",
            "stroke": BOUNDARY_COLOR,
            "width": 1,
            "dash": [4, 4],
            "scale": MARK_SCALE,
        }
    )
    data.append(np.where(kind == 2, mark_y, np.nan))
    series.append({"label": "playhead", "stroke": PLAYHEAD_COLOR, "width": 2, "scale": MARK_SCALE})
    return PlotData(tuple(data), tuple(series))


def plot_options(unit_label: str) -> dict[str, Any]:
    """Scales and axes shared by every update of a panel (``unit_label`` names the y axis)."""
    return {
        "scales": {
            "x": {"time": False},
            "y": {"auto": True},
            MARK_SCALE: {"auto": False, "range": (0.0, 1.0)},
        },
        # Names only: live values would make the legend jump on every playhead move.
        "legend": {"live": False},
        "axes": (
            {"label": "time (s)"},
            {"scale": "y", "label": unit_label},
        ),
    }
