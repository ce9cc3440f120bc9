"""The curves panel's uPlot payload: curves, playhead and segment boundaries."""

from __future__ import annotations

import numpy as np
import pytest

from animstudio.core.clip import Clip
from animstudio.preview.curves import curve_names, limbs, plot_data


def _marks(data: tuple[np.ndarray, ...], index: int) -> np.ndarray:
    x, ys = data[0], data[index]
    return x[~np.isnan(ys)]


def test_groups_split_angles_from_engine_signals(walk_climb_clip: Clip) -> None:
    angles = curve_names(walk_climb_clip, "angles")
    signals = curve_names(walk_climb_clip, "signals")
    assert "left_thigh_deg" in angles and all(n.endswith("_deg") for n in angles)
    assert signals == ("neuron_1", "neuron_2")
    assert curve_names(walk_climb_clip, "angles", limb="left") == tuple(
        n for n in angles if n.startswith("left_")
    )
    assert limbs(walk_climb_clip) == ("all", "left", "neuron", "right")


@pytest.mark.parametrize("frame", [0, 37, 100, 194])
def test_payload_is_aligned_and_exact_at_frame_times(walk_climb_clip: Clip, frame: int) -> None:
    clip = walk_climb_clip
    names = curve_names(clip, "angles")
    pd = plot_data(clip, names, playhead_frame=frame, window_s=4.0)
    assert len(pd.data) == len(pd.series) == len(names) + 3
    x = pd.data[0]
    assert all(a.shape == x.shape for a in pd.data)
    assert np.all(np.diff(x) >= 0)
    # The window is 4 s (121 frames) and contains the playhead.
    frame_times = np.unique(x)
    assert frame_times[0] <= frame / clip.fps <= frame_times[-1]
    assert frame_times[-1] - frame_times[0] == pytest.approx(4.0)
    for i, name in enumerate(names, start=1):
        at_frames = np.round(x * clip.fps).astype(int)
        exact = np.isclose(x * clip.fps, at_frames)
        assert np.allclose(pd.data[i][exact], clip.curves[name][at_frames[exact]])
        assert not np.any(np.isnan(pd.data[i]))
    # The playhead is one vertical line at the frame's time.
    assert np.allclose(_marks(pd.data, -1), frame / clip.fps)
    assert _marks(pd.data, -1).size == 2


def test_segment_boundaries_in_the_window_are_drawn(walk_climb_clip: Clip) -> None:
    clip = walk_climb_clip
    names = curve_names(clip, "angles")
    whole = plot_data(clip, names, playhead_frame=0, window_s=None)
    starts = [s.start_frame / clip.fps for s in clip.segments[1:]]
    assert np.allclose(np.unique(_marks(whole.data, -2)), starts)
    assert whole.series[-2]["label"] == "segment"
    near_start = plot_data(clip, names, playhead_frame=0, window_s=1.0)
    assert _marks(near_start.data, -2).size == 0  # no boundary in the first second


def test_vertical_lines_join_outside_the_plotted_range(walk_climb_clip: Clip) -> None:
    clip = walk_climb_clip
    pd = plot_data(clip, curve_names(clip, "angles"), playhead_frame=0, window_s=None)
    ys = pd.data[-2][~np.isnan(pd.data[-2])]
    # Every line spans below 0 to above 1, and consecutive lines meet on the same side.
    assert np.all((ys < 0) | (ys > 1))
    assert np.all(np.sign(ys[0::2] - 0.5) != np.sign(ys[1::2] - 0.5))
    assert np.all(np.sign(ys[1:-1:2] - 0.5) == np.sign(ys[2::2] - 0.5))


def test_signals_can_be_scaled_to_their_range(walk_climb_clip: Clip) -> None:
    clip = walk_climb_clip
    pd = plot_data(clip, ("neuron_1",), playhead_frame=0, window_s=None, normalize=True)
    assert pd.data[1].min() == pytest.approx(0.0, abs=1e-6)
    assert pd.data[1].max() == pytest.approx(1.0, abs=1e-6)
    lo, hi = clip.curves["neuron_1"].min(), clip.curves["neuron_1"].max()
    assert pd.series[1]["label"] == f"neuron_1 [{lo:.3g}, {hi:.3g}]"
