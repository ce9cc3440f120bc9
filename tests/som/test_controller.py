"""The thesis's controller: faithful replay, completion kept across gait changes, never-won units
never win, transition blend continuity, and the walking foot does not slide."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from animstudio import pipeline
from animstudio.gaitdata import TrainingSet
from animstudio.som.controller import run_controller
from animstudio.som.quality import foot_slide_per_step
from animstudio.som.weights import SomWeights

HEADER = "engine som\ncharacter humanoid\nfps 30\n"


def _period(signal: np.ndarray) -> int:
    for lag in range(1, len(signal) // 2):
        if np.allclose(signal[lag:], signal[:-lag], atol=1e-9):
            return lag
    raise AssertionError("no period")


@pytest.mark.parametrize("gait", ["walk", "run", "climb"])
def test_replay_reproduces_the_training_cycle(
    gait: str, shipped: SomWeights, training_set: TrainingSet
) -> None:
    cycle = training_set.outputs[training_set.patterns_of(gait)]
    n = len(cycle)
    channels = pipeline.generate(pipeline.parse_script(HEADER + f"{gait} {4 * n}"))
    right = np.column_stack([channels.angles[f"right_{p}_deg"] for p in ("thigh", "shank", "foot")])
    rms = np.sqrt(np.mean((right - np.tile(cycle[:, :3], (4, 1))) ** 2, axis=0))
    assert np.all(rms < 1e-9), rms
    assert _period(right) == n
    left = np.column_stack([channels.angles[f"left_{p}_deg"] for p in ("thigh", "shank", "foot")])
    assert _period(left) == n
    # The left leg runs half a cycle (to the nearest pattern: n/2 rounded either way) apart.
    errors = {
        s: np.sqrt(np.mean((left - cycle[(np.arange(4 * n) + s) % n, :3]) ** 2))
        for s in {n // 2, (n + 1) // 2}
    }
    assert min(errors.values()) < 1e-9, errors


def test_gait_change_keeps_the_completion(shipped: SomWeights) -> None:
    gaits = np.array([0] * 20 + [1] * 20 + [2] * 20)
    run = run_controller(shipped, gaits)
    outputs = shipped.trained.outputs.reshape(-1, 6)
    fed_back = outputs[run.winner[:-1], 5]  # next completion emitted at frame k
    np.testing.assert_array_equal(run.completion[1:], fed_back)
    assert run.completion[0].tolist() == [0.0, 0.5]
    # At each change the new gait starts where the old one's completion stood (not a restart
    # at 0.0 / 0.5): frame 20 of walk is 20/35 of the way through its cycle.
    assert run.completion[20, 0] == pytest.approx(20 / 35)
    for k in (20, 40):
        assert np.all(run.completion[k] == outputs[run.winner[k - 1], 5])
        assert not np.array_equal(run.completion[k], [0.0, 0.5])


def test_never_won_units_never_win(shipped: SomWeights) -> None:
    gaits = np.repeat(np.arange(3), 200)
    reference = run_controller(shipped, gaits)
    won = shipped.trained.won.ravel()
    assert np.all(won[reference.winner])
    # Put a never-won unit exactly on inputs the controller presents: it must still not win.
    weights = shipped.trained.input_weights.copy().reshape(-1, 2)
    never = np.flatnonzero(~won)
    assert never.size > 0
    weights[never[0]] = (shipped.gait_ids[0], 0.0)
    weights[never[1 % never.size]] = (shipped.gait_ids[1], reference.completion[250, 0])
    trained = dataclasses.replace(shipped.trained, input_weights=weights.reshape(40, 40, 2))
    tampered = run_controller(dataclasses.replace(shipped, trained=trained), gaits)
    np.testing.assert_array_equal(tampered.winner, reference.winner)


@pytest.mark.parametrize(("old", "new"), [(0, 1), (1, 2), (2, 0)])
def test_transition_blend_is_continuous(shipped: SomWeights, old: int, new: int) -> None:
    gaits = np.array([old] * 60 + [new] * 60)
    hard = run_controller(shipped, gaits)
    soft = run_controller(shipped, gaits, blend_frames=10)
    stay = run_controller(shipped, np.full(120, old))  # the old gait, had it gone on
    np.testing.assert_array_equal(soft.angles_deg[:60], hard.angles_deg[:60])
    # After the blend the output is the hard switch's again (the feedback follows the new gait).
    np.testing.assert_array_equal(soft.angles_deg[70:], hard.angles_deg[70:])
    np.testing.assert_array_equal(soft.completion, hard.completion)
    # During the blend: the cross-fade from the old gait's continuation to the new gait.
    w = (np.arange(10) + 1.0) / 11.0
    expected = (1 - w)[:, None, None] * stay.angles_deg[60:70] + w[:, None, None] * hard.angles_deg[
        60:70
    ]
    np.testing.assert_allclose(soft.angles_deg[60:70], expected, atol=1e-12)
    # So the first blended frame is 1/11 of the way to the new pose: the pop shrinks 11-fold.
    pop_hard = np.abs(hard.angles_deg[60] - stay.angles_deg[60])
    pop_soft = np.abs(soft.angles_deg[60] - stay.angles_deg[60])
    assert pop_hard.max() > 5.0
    np.testing.assert_allclose(pop_soft, pop_hard / 11.0, atol=1e-9)


def test_every_gait_change_enters_the_new_cycle(
    shipped: SomWeights, training_set: TrainingSet
) -> None:
    # From any completion the output layer can feed back, the chain of winners reaches the new
    # gait's training cycle within 3 frames (no stuck loops on stale units).
    outputs = shipped.trained.outputs.reshape(-1, 6)
    fed_back = sorted(set(outputs[shipped.trained.won.ravel(), 5].tolist()) | {0.0, 0.5})
    for g, name in enumerate(shipped.gait_names):
        cycle = set(run_controller(shipped, np.full(200, g)).winner[100:].ravel().tolist())
        assert len(cycle) == int(shipped.cycle_frames[g])
        for c in fed_back:
            run = run_controller(shipped, np.full(4, g), start_completions=(c, c))
            assert int(run.winner[3, 0]) in cycle, (name, c)


def test_blend_from_the_script_changes_only_the_transition() -> None:
    hard = pipeline.generate(pipeline.parse_script(HEADER + "walk 45 / run 45"))
    soft = pipeline.generate(pipeline.parse_script(HEADER + "blend 8\nwalk 45 / run 45"))
    a, b = hard.angles["right_thigh_deg"], soft.angles["right_thigh_deg"]
    np.testing.assert_array_equal(a[:45], b[:45])
    np.testing.assert_array_equal(a[53:], b[53:])
    assert not np.array_equal(a[45:53], b[45:53])


def test_walking_stance_foot_slides_less_than_2_cm_per_step() -> None:
    script = pipeline.parse_script(HEADER + "walk 330")
    channels = pipeline.generate(script)
    clip = pipeline.render(script)
    slides = {
        side: foot_slide_per_step(clip, channels.contacts[f"{side}_foot"], side)
        for side in ("left", "right")
    }
    for side, s in slides.items():
        assert len(s) >= 8, (side, s)
        assert s.max() < 0.02, (side, s.max())


def test_slide_metric_sees_a_sliding_foot() -> None:
    # The metric must fail a foot that slides: drag the whole character 3 cm per frame while
    # the controller says the foot is planted.
    script = pipeline.parse_script(HEADER + "walk 150")
    channels = pipeline.generate(script)
    dragged = dataclasses.replace(
        channels,
        root_position_m=channels.root_position_m + np.outer(np.arange(150) * 0.03, [1, 0, 0]),
    )
    from animstudio.rig import clip_from_channels

    slides = foot_slide_per_step(
        clip_from_channels(dragged), channels.contacts["right_foot"], "right"
    )
    assert slides.min() > 0.1


def _plain_controller(weights: SomWeights, gaits: np.ndarray) -> np.ndarray:
    # The thesis's loop written out frame by frame, searching the pattern-winner units.
    mask = weights.trained.pattern_winner.ravel()
    flat = weights.trained.input_weights.reshape(-1, 2)
    outputs = weights.trained.outputs.reshape(-1, 6)
    units = np.flatnonzero(mask)
    c = [0.0, 0.5]
    winners = np.empty((len(gaits), 2), dtype=np.int64)
    for k, g in enumerate(gaits):
        for leg in range(2):
            x = (weights.gait_ids[g], c[leg])
            d = (flat[units, 0] - x[0]) ** 2 + (flat[units, 1] - x[1]) ** 2
            winners[k, leg] = units[int(np.argmin(d))]
            c[leg] = outputs[winners[k, leg], 5]
    return winners


def test_tiled_chains_equal_the_plain_frame_by_frame_loop(shipped: SomWeights) -> None:
    rng = np.random.Generator(np.random.PCG64(7))
    lengths = rng.integers(1, 90, size=30)
    gaits = np.repeat(rng.integers(0, 3, size=30), lengths)
    fast = run_controller(shipped, gaits)
    np.testing.assert_array_equal(fast.winner, _plain_controller(shipped, gaits))
    outputs = shipped.trained.outputs.reshape(-1, 6)
    np.testing.assert_array_equal(fast.angles_deg, outputs[fast.winner, :3])
