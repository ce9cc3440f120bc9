"""The cpg engine end to end: validation, generation from the biped simulation, falls."""

from __future__ import annotations

from functools import cache
from pathlib import Path

import numpy as np
import pytest

from animstudio.core.channels import GaitChannels
from animstudio.engines import EngineOptions, get_engine
from animstudio.pipeline import generate, load_script, parse_script, render
from animstudio.rig.proportions import ANKLE_HEIGHT_M, SHANK_M, THIGH_M
from animstudio.script import parse

ROOT = Path(__file__).resolve().parents[2]


def problems(text: str) -> list[str]:
    script = parse(text, path="c.gait")
    return [str(e) for e in get_engine("cpg").validate(script, EngineOptions())]


@cache
def pushed(reinit: str, text: str) -> GaitChannels:
    return generate(parse_script(f"engine cpg\nreinit {reinit}\n{text}", path="p.gait"))


# The paper's successive pushes (docs/cpg-model.md §5): 400 N at 2.1 s, 150 N at 2.7 s.
SERIES = "walk 63\npush 400N\nwalk 18\npush 150N\nwalk 159\n"


def test_engine_declares_its_vocabulary() -> None:
    engine = get_engine("cpg")
    assert engine.name == "cpg" and engine.characters == ("humanoid",)
    assert engine.gaits(EngineOptions()) == ("walk",)
    assert problems("engine cpg\nwalk 30\npush 350N\nwalk 30\n") == []


def test_located_errors() -> None:
    assert problems("engine cpg\nwalk 30\nrun 30\n") == [
        "c.gait:3:1: unknown gait 'run' for engine cpg: valid gaits are 'walk'"
    ]
    (msg,) = problems("engine cpg\nwalk speed=2 30\n")
    assert msg.startswith("c.gait:2:6:") and "takes no parameters" in msg
    (msg,) = problems("engine cpg\nblend 5\nwalk 30\n")
    assert msg.startswith("c.gait:2:") and "som" in msg


def test_walk_channels_are_sampled_at_the_frame_rate() -> None:
    ch = generate(load_script(ROOT / "scripts_gait" / "cpg_push.gait"))
    n = 540
    assert ch.num_frames == n and ch.fps == 30.0 and ch.character == "humanoid"
    for name in ("left_thigh_deg", "left_shank_deg", "left_foot_deg", "right_foot_deg"):
        assert ch.angles[name].shape == (n,)
    # walking forward at a human speed, scaled to the character's leg
    speed = (ch.root_position_m[-1, 0] - ch.root_position_m[0, 0]) / (n / 30)
    assert 0.8 < speed < 1.8
    # legs alternate: each foot is in contact about 55-70 % of the time, never both in the air
    for side in ("left_foot", "right_foot"):
        assert 0.5 < ch.contacts[side].mean() < 0.75
    assert np.all(ch.contacts["left_foot"] | ch.contacts["right_foot"])
    # feet on the floor in stance: ankle at the character's ankle height (ground springs sink ~2 cm)
    for side in ("left", "right"):
        th = np.radians(ch.angles[f"{side}_thigh_deg"])
        sh = np.radians(ch.angles[f"{side}_shank_deg"])
        ankle_y = ch.root_position_m[:, 1] - THIGH_M * np.cos(th) - SHANK_M * np.cos(sh)
        stance = ch.contacts[f"{side}_foot"]
        assert np.all(np.abs(ankle_y[stance] - ANKLE_HEIGHT_M) < 0.035)
        assert ankle_y[~stance].max() > ANKLE_HEIGHT_M + 0.05  # the swing foot lifts
    assert [e.kind for e in ch.events] == ["push"]
    for name in (
        "neuron_1",
        "neuron_12",
        "posture_p1",
        "left_knee_torque_nm",
        "phi_c_rad",
        "push_force_n",
    ):
        assert name in ch.signals
    assert ch.signals["push_force_n"].min() == -350.0
    assert ch.notes == ()


@pytest.mark.slow
def test_a_fall_is_reported_shown_and_held() -> None:
    ch = pushed("off", "walk 90\npush 700N\nwalk 240\n")
    (fall,) = [e for e in ch.events if e.kind == "fall"]
    assert ch.notes and ch.notes[0].startswith("walker fell at ") and ch.notes[0] == fall.label
    assert 3.0 < fall.frame / 30 < 9.0  # after the push at 3 s
    hip = ch.root_position_m[:, 1]
    assert hip[fall.frame] < 0.8 * hip[0]
    assert hip[fall.frame :].max() < 0.9 * hip[0]  # and it does not get up again
    # the last pose is held once the body is down
    assert np.all(ch.root_position_m[-10:] == ch.root_position_m[-1])
    assert np.all(ch.angles["left_thigh_deg"][-10:] == ch.angles["left_thigh_deg"][-1])


@pytest.mark.slow
def test_reinit_auto_recovers_where_off_falls() -> None:
    off = pushed("off", SERIES)
    auto = pushed("auto", SERIES)
    assert any(e.kind == "fall" for e in off.events)
    assert not any(e.kind == "fall" for e in auto.events)
    assert auto.signals["phi_c_rad"].max() > 0.0 and off.signals["phi_c_rad"].max() == 0.0


def test_render_to_clip() -> None:
    clip = render(parse_script("engine cpg\nfps 24\nwalk 48\n", path="r.gait"))
    assert clip.num_frames == 48 and clip.fps == 24
    assert "left_knee_torque_nm" in clip.curves


def test_plots_render_png_and_reject_unknown_kinds(tmp_path: Path) -> None:
    from animstudio.errors import UnknownName
    from animstudio.plots import KINDS_BY_ENGINE, plot

    assert KINDS_BY_ENGINE["cpg"] == ("stick", "neurons", "torque")
    script = parse_script("engine cpg\nwalk 30\npush 200N\nwalk 30\n", path="p.gait")
    for kind in KINDS_BY_ENGINE["cpg"]:
        out = tmp_path / f"{kind}.png"
        plot(script, kind, out)
        assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    with pytest.raises(
        UnknownName, match=r"did you mean 'stick'\? valid kinds: 'stick', 'neurons'"
    ):
        plot(script, "stik", tmp_path / "x.png")
    assert not (tmp_path / "x.png").exists()
