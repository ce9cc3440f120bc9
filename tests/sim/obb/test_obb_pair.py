"""The OBB neuron pair (seed 002, eq. (1)-(4), Tables 1-2, Figures 3-4), measured from the model."""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest

from animstudio.errors import SimulationError
from animstudio.sim.obb import ObbParams, cycles, h, settle_step, simulate_pair
from animstudio.sim.smer import SmerGraph

STEP_S = 3.0  # seconds per step that reproduce Figure 3 (docs/obb-model.md)


def test_h_is_ten_to_the_number_of_digits() -> None:
    assert (h(1), h(5), h(9), h(77), h(463)) == (10, 10, 10, 100, 1000)


@pytest.mark.parametrize(
    ("r", "weights", "thresholds"),
    [
        ((1, 5), ("0.1", "0.5"), (0, 1)),
        ((1, 3), ("0.1", "0.3"), (0, 1)),
        ((1, 1), ("0.1", "0.1"), (0, 1)),
    ],
)
def test_parameters_match_tables_1_and_2(r, weights, thresholds) -> None:
    p = ObbParams(*r)
    assert p.weights == tuple(Fraction(w) for w in weights)
    assert p.thresholds == tuple(Fraction(t) for t in thresholds)


def test_table_1_settles_to_period_18_s_with_15_s_on() -> None:
    run = simulate_pair(60)  # r = 1,5; M0 = 0.35 / 0.65
    # Self-organising start: the first burst of the r = 1 neuron is 4 steps, not 5.
    assert run.v[:5, 0].tolist() == [True, True, True, True, False]
    flexor = cycles(run.v[:, 0])
    extensor = cycles(run.v[:, 1])
    assert {(c.period, c.on) for c in flexor} == {(6, 5)}
    assert {(c.period, c.on) for c in extensor} == {(6, 1)}
    assert flexor[0].period * STEP_S == 18.0 and flexor[0].on * STEP_S == 15.0
    assert settle_step(run.v[:, 0], period=6, on=5) == 5  # stable from 15 s
    assert not np.any(run.v.all(axis=1)), "flexor and extensor on together"
    np.testing.assert_allclose(run.m.sum(axis=1), 1.0)  # W's columns sum to zero


@pytest.mark.parametrize(
    ("k", "period", "on"), [(5, 6, 5), (4, 5, 4), (3, 4, 3), (2, 3, 2), (1, 2, 1)]
)
def test_r_equal_one_neuron_is_on_k_of_k_plus_one_steps(k: int, period: int, on: int) -> None:
    run = simulate_pair(10 * period, r=(1, k), m0=("0.35", "0.65"))
    assert {(c.period, c.on) for c in cycles(run.v[:, 0])[1:]} == {(period, on)}


def test_duty_0_8_for_12_s_of_the_text_is_the_r_1_4_pair() -> None:
    run = simulate_pair(60, r=(1, 4))
    c = cycles(run.v[:, 0])[-1]
    assert (c.period * STEP_S, c.on * STEP_S, c.duty) == (15.0, 12.0, 0.8)


@pytest.mark.parametrize("request_s", [39.0, 40.0, 42.0, 45.0])
def test_transition_requested_near_40_s_takes_effect_at_51_s(request_s: float) -> None:
    request = int(np.ceil(request_s / STEP_S))
    run = simulate_pair(60, switches=[(request, (1, 3))])
    flexor = cycles(run.v[:, 0])
    old = [c for c in flexor if c.start * STEP_S < 51]
    new = [c for c in flexor if c.start * STEP_S >= 51]
    assert all((c.period, c.on) == (6, 5) for c in old)
    assert new[0].start * STEP_S == 51.0
    assert {(c.period, c.on) for c in new} == {(4, 3)}  # 12 s period, 9 s on: duty 0.75
    assert settle_step(run.v[:, 0], period=4, on=3, after=request) * STEP_S == 51.0


def test_table_2_phases_duty_falls_from_five_sixths_to_one_half() -> None:
    s1, s2 = int(np.ceil(160 / STEP_S)), int(np.ceil(300 / STEP_S))
    run = simulate_pair(140, switches=[(s1, (1, 3)), (s2, (1, 1))])
    duty = {}
    for c in cycles(run.v[:, 0]):
        duty.setdefault(int(run.r[c.start, 1]), set()).add((c.period, c.on))
    assert duty[5] == {(6, 5)} and duty[3] == {(4, 3)} and duty[1] == {(2, 1)}
    # The new patterns start at the r = 1 neuron's first switch-on after the old burst ends.
    assert settle_step(run.v[:, 0], period=4, on=3, after=s1, before=s2) * STEP_S == 177.0
    assert settle_step(run.v[:, 0], period=2, on=1, after=s2) * STEP_S == 309.0


def test_pair_equations_are_the_smer_pair() -> None:
    # After its self-organising start the neural pair fires exactly like SMER nodes r = 1, 5
    # sharing e = 5 resources.
    run = simulate_pair(40)
    graph = SmerGraph(("flexor", "extensor"), np.array([1, 5]), np.array([[0, 1]]), np.array([5]))
    start = settle_step(run.v[:, 0], period=6, on=5)
    _, fired = graph.run(np.array([5]), 40 - start)
    np.testing.assert_array_equal(run.v[start:], fired)


def test_potentials_landing_exactly_on_the_thresholds_stop_the_pair_with_a_clear_error() -> None:
    # 0.5 - 5 x 0.1 = 0 and 0.5 + 5 x 0.1 = 1: both neurons sit exactly on their thresholds and
    # neither is strictly above, so nothing can change any more (exact arithmetic finds it).
    with pytest.raises(SimulationError, match="stopped at step 5"):
        simulate_pair(8, m0=("0.5", "0.5"))


def test_bad_settings_are_simulation_errors() -> None:
    with pytest.raises(SimulationError):
        simulate_pair(10, r=(0, 5))
    with pytest.raises(SimulationError):
        simulate_pair(10, switches=[(5, (1, 3)), (3, (1, 1))])
    with pytest.raises(SimulationError, match="stopped"):
        simulate_pair(10, m0=("-0.5", "0.5"))
