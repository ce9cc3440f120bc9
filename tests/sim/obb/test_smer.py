"""SMER graph dynamics against hand-worked cases and the seed's coupling rules (section 2.1)."""

from __future__ import annotations

import itertools
from math import gcd

import numpy as np
import pytest

from animstudio.errors import SimulationError
from animstudio.sim.smer import SmerConfigError, SmerGraph, check_live, find_cycle


def pair(r_i: int, r_j: int, e: int) -> SmerGraph:
    return SmerGraph(("i", "j"), np.array([r_i, r_j]), np.array([[0, 1]]), np.array([e]))


def firing_string(graph: SmerGraph, held: int, steps: int) -> str:
    _, fired = graph.run(np.array([held]), steps)
    return "".join("".join(graph.names[k] for k in np.flatnonzero(row)) for row in fired)


def test_figure_1_node_i_sink_once_node_j_three_times() -> None:
    # Worked by hand: i holds all 3 and operates, handing 3 to j; j (r = 1) then operates three
    # times handing one back each time, after which i holds 3 again: 4 orientations per cycle.
    g = pair(3, 1, 3)
    assert firing_string(g, 3, 12) == "ijjjijjjijjj"
    transient, period = check_live(g, np.array([3]))
    assert (transient, period) == (0, 4)


def test_figure_1_from_a_split_start_j_uses_up_its_two_first() -> None:
    # i holds 1, j holds 2: j operates twice, then i holds 3 and the regular cycle follows.
    assert firing_string(pair(3, 1, 3), 1, 8) == "jjijjjij"


@pytest.mark.parametrize(("r_i", "r_j"), [(2, 3), (3, 5), (4, 6), (2, 4), (1, 5)])
def test_operation_ratio_is_r_j_over_r_i(r_i: int, r_j: int) -> None:
    # Per cycle, i operates r_j / g times and j r_i / g times (Barbosa et al.).
    g = gcd(r_i, r_j)
    e = r_i + r_j - g
    graph = pair(r_i, r_j, e)
    held = next(h for h in range(e + 1) if _rule2(h, e, r_i, r_j))
    transient, period = check_live(graph, np.array([held]))
    _, fired = graph.run(np.array([held]), transient + period)
    counts = fired[transient:].sum(axis=0)
    assert counts.tolist() == [r_j // g, r_i // g]
    assert not np.any(fired.all(axis=1)), "neighbours operated in the same step"


def _rule2(h: int, e: int, r_i: int, r_j: int) -> bool:
    g = gcd(r_i, r_j)
    return g * (h // g) + g * ((e - h) // g) == r_i + r_j - g


def test_rule_1_below_range_is_a_clear_error() -> None:
    with pytest.raises(SmerConfigError, match=r"3 <= e <= 3"):
        pair(3, 1, 2).check(np.array([2]))


def test_rule_1_above_range_is_a_clear_error() -> None:
    with pytest.raises(SmerConfigError, match="max"):
        pair(3, 1, 4).check(np.array([4]))


def test_rule_2_bad_split_is_a_clear_error() -> None:
    # r = 2, 2: e = 2 split 1/1 gives f = 0, not 2; neither node could ever operate.
    with pytest.raises(SmerConfigError, match="f_ij = 0"):
        pair(2, 2, 2).check(np.array([1]))


def test_config_errors_are_simulation_errors_and_value_errors() -> None:
    assert issubclass(SmerConfigError, SimulationError)
    assert issubclass(SmerConfigError, ValueError)


def test_exhaustive_pairs_rules_met_means_live_and_exclusive() -> None:
    # Every pair with r <= 5, every e in range, every split meeting rule 2: periodic, exclusive;
    # every split breaking rule 2 deadlocks at once (so the check is exactly the right one).
    for r_i, r_j in itertools.product(range(1, 6), repeat=2):
        for e in range(max(r_i, r_j), r_i + r_j):
            for h in range(e + 1):
                graph = pair(r_i, r_j, e)
                if _rule2(h, e, r_i, r_j):
                    check_live(graph, np.array([h]))
                    _, fired = graph.run(np.array([h]), 3 * (r_i + r_j))
                    assert fired.any(axis=1).all() and not fired.all(axis=1).any()
                else:
                    with pytest.raises(SimulationError):
                        find_cycle(graph, np.array([h]))


def test_cyclic_orientation_on_a_triangle_deadlocks_at_run_time() -> None:
    # Pairwise rules hold on each edge (r = 1, e = 1) but a -> b -> c -> a leaves no sink.
    tri = SmerGraph(
        ("a", "b", "c"), np.ones(3, dtype=np.int64), np.array([[0, 1], [1, 2], [2, 0]]), np.ones(3)
    )
    held = np.array([0, 0, 0])  # each edge's resource at its second node: a cycle of waits
    tri.check(held)
    with pytest.raises(SimulationError, match="deadlock"):
        tri.step(held)
    with pytest.raises(SimulationError, match="deadlock"):
        check_live(tri, held)


def test_acyclic_triangle_runs_edge_reversal() -> None:
    tri = SmerGraph(
        ("a", "b", "c"), np.ones(3, dtype=np.int64), np.array([[0, 1], [1, 2], [2, 0]]), np.ones(3)
    )
    held = np.array([1, 1, 0])  # a holds a-b, b holds b-c, a holds c-a: a is the only sink
    _, fired = tri.run(held, 6)
    assert ["abc"[int(np.flatnonzero(r)[0])] for r in fired] == list("abcabc")


def test_bad_graph_shapes_are_rejected() -> None:
    with pytest.raises(SmerConfigError):
        SmerGraph(("a", "b"), np.array([0, 1]), np.array([[0, 1]]), np.array([1]))
    with pytest.raises(SmerConfigError):
        SmerGraph(("a", "b"), np.array([1, 1]), np.array([[0, 0]]), np.array([1]))
    with pytest.raises(SmerConfigError):
        SmerGraph(("a", "b"), np.array([1, 1]), np.array([[0, 1], [1, 0]]), np.array([1, 1]))
