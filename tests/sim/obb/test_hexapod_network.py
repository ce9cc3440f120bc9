"""The hexapod OBB network: gaits, phase relations, duty factors and transitions (from the model)."""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest

from animstudio.errors import SimulationError
from animstudio.sim.hexapod import GAITS, LEGS, Gait, leg_cycles, obb_gait, simulate, smer_graph
from animstudio.sim.smer import check_live

L = {leg: n for n, leg in enumerate(LEGS)}


def steady(gait: Gait, steps: int = 60):
    run = simulate([(0, gait)], steps)
    return run, leg_cycles(run.swing)


def swing_steps(run, leg: str) -> np.ndarray:
    return np.flatnonzero(run.swing[:, L[leg]])


def duty_factor(run, leg: str, a: int, b: int) -> Fraction:
    """Fraction of steps [a, b) the foot is on the ground (its swing node not operating)."""
    return Fraction(int((~run.swing[a:b, L[leg]]).sum()), b - a)


@pytest.mark.parametrize("name", ["wave", "tetrapod", "tripod"])
def test_network_equals_the_plain_smer_graph(name: str) -> None:
    gait = GAITS[name]
    graph, held = smer_graph(gait)
    transient, period = check_live(graph, held)  # both coupling rules hold; no deadlock
    assert transient == 0 and period == gait.period
    run = simulate([(0, gait)], 40)
    _, fired = graph.run(held, 40)
    np.testing.assert_array_equal(fired[:, 6:], run.swing)
    np.testing.assert_array_equal(fired[:, :6], run.stance)


def test_wave_is_metachronal_back_to_front_with_duty_five_sixths() -> None:
    run, cyc = steady(GAITS["wave"])
    assert {p for leg in cyc for _, p in leg} == {6}
    first = {leg: int(swing_steps(run, leg)[0]) for leg in LEGS}
    # Back to front on each side, one leg at a time, the right side half a cycle after the left.
    assert first["L3"] < first["L2"] < first["L1"]
    assert first["R3"] < first["R2"] < first["R1"]
    assert sorted(first.values()) == list(range(6))
    assert (first["R3"] - first["L3"]) % 6 == 3
    for leg in LEGS:
        assert duty_factor(run, leg, 0, 60) == Fraction(5, 6)
    assert run.swing.sum(axis=1).max() == 1  # five feet always down


def test_tetrapod_moves_diagonal_pairs_with_duty_two_thirds() -> None:
    run, cyc = steady(GAITS["tetrapod"])
    assert {p for leg in cyc for _, p in leg} == {3}
    groups = {frozenset(LEGS[n] for n in np.flatnonzero(row)) for row in run.swing}
    assert groups == {frozenset({"L3", "R2"}), frozenset({"L2", "R1"}), frozenset({"L1", "R3"})}
    first = {leg: int(swing_steps(run, leg)[0]) for leg in LEGS}
    assert first["L3"] < first["L2"] < first["L1"]  # still back to front
    for leg in LEGS:
        assert duty_factor(run, leg, 0, 60) == Fraction(2, 3)
    assert run.swing.sum(axis=1).tolist() == [2] * 60  # four feet always down


def test_tripod_alternates_l1_r2_l3_with_r1_l2_r3_at_duty_one_half() -> None:
    run, cyc = steady(GAITS["tripod"])
    assert {p for leg in cyc for _, p in leg} == {2}
    groups = {frozenset(LEGS[n] for n in np.flatnonzero(row)) for row in run.swing}
    assert groups == {frozenset({"L1", "R2", "L3"}), frozenset({"R1", "L2", "R3"})}
    for leg in LEGS:
        assert duty_factor(run, leg, 0, 60) == Fraction(1, 2)


@pytest.mark.parametrize(
    ("base", "k", "period"),
    # The paper's reversibilities in each class: (1,3) in the tetrapod class gives 4 steps (3/4),
    # not the textbook 2/3; in the wave class the ring keeps 6 steps whatever k <= 5.
    [
        ("tetrapod", 3, 4),
        ("tetrapod", 1, 3),
        ("wave", 3, 6),
        ("wave", 1, 6),
        ("tripod", 5, 6),
        ("tripod", 3, 4),
    ],
)
def test_paper_reversibilities_in_each_class(base: str, k: int, period: int) -> None:
    gait = obb_gait(k, like=GAITS[base])
    assert gait.period == period
    run = simulate([(0, gait)], 80)
    cyc = leg_cycles(run.swing)
    assert {p for leg in cyc for _, p in leg[2:]} == {period}


def test_reversibility_change_acts_at_each_legs_next_swing_and_keeps_the_class() -> None:
    wave = GAITS["wave"]
    run = simulate([(0, wave), (14, obb_gait(3, like=wave))], 40)
    for leg in LEGS:
        lifts = swing_steps(run, leg)
        first_new = lifts[lifts >= 14][0]
        assert np.all(run.k[:first_new, L[leg]] == 5)
        assert np.all(run.k[first_new:, L[leg]] == 3)
    # The order of the legs (the class) is unchanged: still one leg at a time, back to front.
    assert run.swing.sum(axis=1).max() == 1
    assert not run.reinit_steps


def test_class_change_reinitialises_and_the_new_pattern_appears_within_one_cycle() -> None:
    run = simulate([(0, GAITS["wave"]), (20, GAITS["tetrapod"]), (35, GAITS["tripod"])], 60)
    assert run.reinit_steps == (20, 35)
    tetra = {frozenset({"L3", "R2"}), frozenset({"L2", "R1"}), frozenset({"L1", "R3"})}
    tri = {frozenset({"L1", "R2", "L3"}), frozenset({"R1", "L2", "R3"})}
    groups = [frozenset(LEGS[n] for n in np.flatnonzero(row)) for row in run.swing]
    assert set(groups[20:35]) == tetra  # from the switch step on, only tetrapod groups swing
    assert set(groups[35:60]) == tri
    # No leg swings twice in a row across a switch (its foot gets at least one stance step).
    for leg in LEGS:
        assert np.all(np.diff(swing_steps(run, leg)) >= 2)


def test_schedule_errors() -> None:
    with pytest.raises(SimulationError):
        simulate([], 10)
    with pytest.raises(SimulationError):
        simulate([(3, GAITS["wave"])], 10)
    with pytest.raises(SimulationError):
        Gait("bad", ("L1",) * 6, 1, 5)
