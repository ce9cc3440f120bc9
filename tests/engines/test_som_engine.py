"""The som engine: vocabulary from the weights, validation, channels and frame-rate handling."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from animstudio import pipeline
from animstudio.engines import EngineOptions, get_engine
from animstudio.errors import DataError, ScriptErrors
from animstudio.gaitdata.legs import leg_points
from animstudio.som.weights import DEFAULT_WEIGHTS, load_weights, save_weights

HEADER = "engine som\ncharacter humanoid\n"


def test_engine_protocol_and_vocabulary() -> None:
    engine = get_engine("som")
    assert engine.name == "som" and engine.characters == ("humanoid",)
    assert engine.gaits(EngineOptions()) == ("walk", "run", "climb")


def test_vocabulary_comes_from_the_weights_file(tmp_path: Path) -> None:
    w = load_weights(DEFAULT_WEIGHTS)
    import dataclasses

    renamed = dataclasses.replace(w, gait_names=("stroll", "jog", "ascend"))
    path = tmp_path / "renamed.npz"
    save_weights(path, renamed)
    options = EngineOptions(weights=path)
    assert get_engine("som").gaits(options) == ("stroll", "jog", "ascend")
    channels = pipeline.generate(
        pipeline.parse_script(HEADER + "jog 30", options=options), options=options
    )
    default = pipeline.generate(pipeline.parse_script(HEADER + "run 30"))
    np.testing.assert_array_equal(
        channels.angles["right_thigh_deg"], default.angles["right_thigh_deg"]
    )
    with pytest.raises(ScriptErrors, match="unknown gait 'run'"):
        pipeline.parse_script(HEADER + "run 30", options=options)


def test_validation_errors_are_located() -> None:
    text = HEADER + "walk 30 / wlak 20\nrun speed=3 30\npush 300N\nclimb 10"
    with pytest.raises(ScriptErrors) as err:
        pipeline.parse_script(text, path="t.gait")
    messages = str(err.value)
    assert "t.gait:3:11: unknown gait 'wlak' (did you mean 'walk'?)" in messages
    assert "t.gait:4:5: gait 'run' takes no parameters" in messages
    assert "t.gait:5:1: push events need engine cpg" in messages


def test_missing_weights_file_is_a_data_error(tmp_path: Path) -> None:
    with pytest.raises(DataError, match="weights file not found"):
        get_engine("som").gaits(EngineOptions(weights=tmp_path / "none.npz"))


def test_channels_contacts_segments_and_signals() -> None:
    script = pipeline.parse_script(HEADER + "fps 30\nwalk 60 / run 30 / climb 45")
    ch = pipeline.generate(script)
    assert ch.character == "humanoid" and ch.fps == 30 and ch.num_frames == 135
    assert set(ch.angles) == {
        f"{s}_{p}_deg" for s in ("left", "right") for p in ("thigh", "shank", "foot")
    }
    assert set(ch.contacts) == {"left_foot", "right_foot"}
    assert [(s.gait, s.start_frame, s.end_frame) for s in ch.segments] == [
        ("walk", 0, 60),
        ("run", 60, 90),
        ("climb", 90, 135),
    ]
    assert {"left_completion", "right_completion"} <= set(ch.signals)
    assert ch.signals["right_completion"][0] == 0.0
    # Walking has double support, running has flight.
    walk_both = ch.contacts["left_foot"][:60] & ch.contacts["right_foot"][:60]
    run_none = ~ch.contacts["left_foot"][60:90] & ~ch.contacts["right_foot"][60:90]
    assert walk_both.any() and run_none.any()
    root = ch.root_position_m
    assert np.all(root[:, 2] == 0.0) and root[0, 0] == 0.0
    assert np.all(np.diff(root[:, 0]) > 0)  # always travelling forward
    assert root[-1, 1] - root[90, 1] > 0.15  # climbing rises


def test_stance_foot_is_on_the_floor_at_frame_0() -> None:
    ch = pipeline.generate(pipeline.parse_script(HEADER + "walk 10"))
    lowest = []
    for side in ("left", "right"):
        angles = np.array([ch.angles[f"{side}_{p}_deg"][0] for p in ("thigh", "shank", "foot")])
        lowest.append(ch.root_position_m[0, 1] + leg_points(angles).lowest_y())
    assert min(lowest) == pytest.approx(0.0, abs=1e-12)
    assert ch.contacts["right_foot"][0]


@pytest.mark.parametrize("fps", [24, 25, 60])
def test_other_frame_rates_keep_duration_and_frame_count(fps: int) -> None:
    script = pipeline.parse_script(HEADER + f"fps {fps}\nwalk 2s / run 1.5s")
    ch = pipeline.generate(script)
    assert ch.num_frames == script.total_frames and ch.fps == fps
    ref = pipeline.generate(pipeline.parse_script(HEADER + "fps 30\nwalk 2s / run 1.5s"))
    # Output frame k shows the 30 fps motion at k / fps seconds (linear interpolation).
    t30 = np.arange(ch.num_frames) * 30.0 / fps
    inside = t30 <= ref.num_frames - 1
    expected = np.interp(t30[inside], np.arange(ref.num_frames), ref.angles["left_shank_deg"])
    np.testing.assert_allclose(ch.angles["left_shank_deg"][inside], expected, atol=1e-9)
    speed = (ch.root_position_m[-1, 0] - ch.root_position_m[0, 0]) / ((ch.num_frames - 1) / fps)
    speed30 = (ref.root_position_m[-1, 0] - ref.root_position_m[0, 0]) / ((ref.num_frames - 1) / 30)
    assert speed == pytest.approx(speed30, rel=0.05)
    assert any("resampled" in n for n in ch.notes)


def test_long_script_does_not_drift() -> None:
    script = pipeline.parse_script(HEADER + "walk 6000 / run 6000 / climb 6000")
    ch = pipeline.generate(script)
    assert ch.num_frames == 18_000
    # Level walking for 200 s: the hip height stays within its cycle's range (no sinking).
    y = ch.root_position_m[:6000, 1]
    assert np.ptp(y[:36]) + 1e-9 >= np.ptp(y) - 0.01
