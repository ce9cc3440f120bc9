"""The obb engine end to end: validation, generation, feet, transitions, USD."""

from __future__ import annotations

from functools import cache
from pathlib import Path

import numpy as np
import pytest

from animstudio.core.fk import joint_positions
from animstudio.engines import EngineOptions, get_engine
from animstudio.engines.obb import FOOT_LIFT_M, SPEED_RAMP_S, STEP_S, STRIDE_M
from animstudio.errors import ScriptErrors
from animstudio.pipeline import generate, parse_script, render
from animstudio.script import parse
from animstudio.sim.hexapod import LEGS

SCRIPT = "character hexapod\nwave 120\ntetrapod 90\ntripod 60\nobb r=1,3 60\n"


def problems(text: str) -> list[str]:
    script = parse(text, path="h.gait")
    return [str(e) for e in get_engine("obb").validate(script, EngineOptions())]


@cache
def rendered():
    script = parse_script(SCRIPT, path="h.gait")
    return generate(script), render(script)


def test_engine_declares_its_vocabulary() -> None:
    engine = get_engine("obb")
    assert engine.name == "obb" and engine.characters == ("hexapod",)
    assert engine.gaits(EngineOptions()) == ("wave", "tetrapod", "tripod", "obb")
    assert problems(SCRIPT) == []


def test_biped_gait_is_an_error_listing_the_valid_gaits() -> None:
    (msg,) = problems("character hexapod\nwalk 30\n")
    assert msg.startswith("h.gait:2:1:")
    for gait in ("wave", "tetrapod", "tripod", "obb"):
        assert f"'{gait}'" in msg


@pytest.mark.parametrize(
    ("line", "fragment"),
    [
        ("obb r=2,5 30", "always 1"),
        ("obb r=1,12 30", "between 1 and 9"),
        ("obb r=1 30", "two integers"),
        ("obb r=a,b 30", "two integers"),
    ],
)
def test_bad_reversibility_is_located_at_the_parameter(line: str, fragment: str) -> None:
    (msg,) = problems(f"character hexapod\n{line}\n")
    assert msg.startswith("h.gait:2:5:") and fragment in msg


def test_obb_without_r_and_params_on_named_gaits_are_errors() -> None:
    assert "needs its reversibilities" in problems("character hexapod\nobb 30\n")[0]
    assert "takes no parameters" in problems("character hexapod\nwave r=1,5 30\n")[0]


def test_push_events_need_engine_cpg() -> None:
    (msg,) = problems("character hexapod\nwave 30\npush 300N\nwave 30\n")
    assert msg.startswith("h.gait:3:1:") and "push events need engine cpg" in msg
    with pytest.raises(ScriptErrors):
        parse_script("character hexapod\nwave 30\npush 300N\nwave 30\n")


def test_channels_have_contacts_signals_and_segments() -> None:
    ch, _ = rendered()
    assert ch.character == "hexapod" and ch.fps == 30 and ch.num_frames == 330
    assert set(ch.contacts) == set(LEGS)
    assert [s.gait for s in ch.segments] == ["wave", "tetrapod", "tripod", "obb"]
    for leg in LEGS:
        assert {f"{leg}_swing_neuron", f"{leg}_stance_neuron"} <= set(ch.signals)
    assert len(ch.notes) == 2  # the two class changes


def _stance_runs(contact: np.ndarray) -> list[tuple[int, int]]:
    edges = np.flatnonzero(np.diff(np.concatenate([[0], contact.astype(np.int8), [0]])))
    return list(zip(edges[::2].tolist(), edges[1::2].tolist(), strict=True))


def test_stance_feet_do_not_slide_on_the_clips_fk() -> None:
    ch, clip = rendered()
    pos = joint_positions(clip)
    worst = 0.0
    for leg in LEGS:
        foot = pos[:, clip.skeleton.index(f"{leg}_foot")]
        for a, b in _stance_runs(ch.contacts[leg]):
            worst = max(worst, float(np.abs(foot[a:b] - foot[a]).max()))
        assert np.all(foot[ch.contacts[leg], 1] < 1e-4)  # stance feet on the ground
    assert worst < 0.01


def test_body_advances_one_stride_per_steady_stance() -> None:
    ch, clip = rendered()
    x = clip.root_translations[:, 0]
    assert np.all(np.diff(x) > 0)
    # In steady walking (past the speed ramp) the body covers one stride while a foot is down:
    # the stance feet, fixed on the ground, are what carries it.
    travels = []
    for leg in LEGS:
        for a, b in _stance_runs(ch.contacts[leg]):
            seg = clip.segment_at(a)
            if a == 0 or b >= clip.num_frames or seg is None or clip.segment_at(b) != seg:
                continue
            if a < seg.start_frame + (SPEED_RAMP_S + 3 * STEP_S) * ch.fps:
                continue
            travels.append(x[b] - x[a])
    assert len(travels) > 30  # stances from all four segments
    np.testing.assert_allclose(travels, STRIDE_M, atol=1e-9)


def test_no_leg_teleports() -> None:
    ch, clip = rendered()
    pos = joint_positions(clip)
    # Fastest possible swing: the tripod covers (stride at 0.4 m/s x 2 steps) in one step on a
    # half-cosine, peak speed pi/2 x distance / STEP_S; allow the arc height on top.
    fastest = np.pi / 2 * (0.4 * 2 * STEP_S + 0.03) / STEP_S + np.pi * FOOT_LIFT_M / STEP_S
    for leg in LEGS:
        foot = pos[:, clip.skeleton.index(f"{leg}_foot")]
        step = np.linalg.norm(np.diff(foot, axis=0), axis=1)
        assert step.max() < fastest / ch.fps, leg
    # Joint angles are continuous too (no flips at gait changes).
    for name, a in ch.angles.items():
        assert np.abs(np.diff(a)).max() < 20.0, name


def test_footfall_pattern_changes_within_a_few_cycles() -> None:
    ch, _ = rendered()
    swing = np.stack([~ch.contacts[leg] for leg in LEGS], axis=1)
    frames_per_step = round(STEP_S * ch.fps)
    tetra = {frozenset({"L3", "R2"}), frozenset({"L2", "R1"}), frozenset({"L1", "R3"})}
    tri = {frozenset({"L1", "R2", "L3"}), frozenset({"R1", "L2", "R3"})}
    for seg, groups in zip(ch.segments[1:3], (tetra, tri), strict=True):
        first = seg.start_frame  # 120 and 210 are step boundaries at 30 fps
        seen = [
            frozenset(LEGS[n] for n in np.flatnonzero(swing[f]))
            for f in range(first, seg.end_frame, frames_per_step)
        ]
        assert set(seen) == groups


def test_hexapod_script_renders_to_a_usd_stage_that_reads_back(tmp_path: Path) -> None:
    from animstudio.export.usd import write_usd
    from animstudio.export.usd_read import read_clip

    _, clip = rendered()
    out = tmp_path / "hexapod.usda"
    write_usd(out, clip)
    from pxr import Usd, UsdValidation

    ctx = UsdValidation.ValidationContext(
        UsdValidation.ValidationRegistry().GetOrLoadAllValidators()
    )
    assert [e.GetMessage() for e in ctx.Validate(Usd.Stage.Open(str(out)))] == []
    back = read_clip(out)
    assert back.skeleton.joint_names == clip.skeleton.joint_names
    np.testing.assert_allclose(joint_positions(back), joint_positions(clip), atol=1e-4)


def test_plots_write_pngs_and_reject_unknown_kinds(tmp_path: Path) -> None:
    from animstudio.errors import UnknownName
    from animstudio.plots import obb as plots

    script = parse_script(SCRIPT, path="h.gait")
    for kind in plots.KINDS:
        out = tmp_path / f"{kind}.png"
        plots.plot(script, kind, out, options=EngineOptions())
        assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    with pytest.raises(UnknownName, match="footfall"):
        plots.plot(script, "stick", tmp_path / "x.png", options=EngineOptions())
    assert not (tmp_path / "x.png").exists()


@pytest.mark.parametrize(
    "text",
    [
        "fps 24\ncharacter hexapod\nwave 100\ntripod 37\ntetrapod 50\n",  # steps of 4.8 frames
        "fps 60\ncharacter hexapod\ntripod 100\nwave 3\ntetrapod 2\nwave 90\n",  # sub-step segments
        "character hexapod\nobb r=1,9 200\nobb r=1,1 100\n",
    ],
)
def test_other_frame_rates_and_short_segments_keep_feet_planted(text: str) -> None:
    script = parse_script(text, path="x.gait")
    ch = generate(script)
    clip = render(script)
    assert clip.num_frames == script.total_frames
    pos = joint_positions(clip)
    for leg in LEGS:
        foot = pos[:, clip.skeleton.index(f"{leg}_foot")]
        for a, b in _stance_runs(ch.contacts[leg]):
            assert np.abs(foot[a:b] - foot[a]).max() < 0.01
        assert (~ch.contacts[leg]).any() and ch.contacts[leg].any()  # every leg steps


def test_body_speed_ramps_without_jumps_even_across_short_segments() -> None:
    from animstudio.engines.obb import SPEED_RAMP_S, body_x

    plan = [(0.0, 0.08), (4.0, 0.2), (4.2, 0.4), (7.0, 0.1)]  # 4.0-4.2 s is shorter than the ramp
    t = np.linspace(-1.0, 9.0, 100_001)
    v = np.gradient(body_x(t, plan), t)
    assert body_x(np.zeros(1), plan)[0] == 0.0
    np.testing.assert_allclose(v[t < 4.0], 0.08, atol=1e-9)
    np.testing.assert_allclose(v[(t > 4.2 + SPEED_RAMP_S + 0.01) & (t < 7.0)], 0.4, atol=1e-9)
    np.testing.assert_allclose(v[t > 7.0 + SPEED_RAMP_S + 0.01], 0.1, atol=1e-9)
    assert np.abs(np.diff(v)).max() < 1e-3  # continuous: largest change over 0.1 ms


def test_settings_of_other_engines_are_located_errors() -> None:
    (msg,) = problems("character hexapod\nblend 5\nwave 30\n")
    assert msg.startswith("h.gait:2:7:") and "engine som" in msg
