"""The seed's results reproduced from the model (issue 3 items 1-5). Nothing is tuned here:
every number comes from CpgParams() defaults and the experiment functions."""

from __future__ import annotations

import numpy as np
import pytest

from animstudio.sim.cpg import experiments as ex
from animstudio.sim.cpg.analysis import limit_cycle, section_distance, start_on_cycle
from animstudio.sim.cpg.batch import run_walkers
from animstudio.sim.cpg.model import Model, Push
from animstudio.sim.cpg.params import CpgParams
from animstudio.sim.cpg.reinit import choose_phi_c

pytestmark = pytest.mark.slow
PARAMS = CpgParams()


def test_walking_emerges_and_settles_on_a_limit_cycle() -> None:
    stats, ro = ex.normal_walking(PARAMS, 60.0)
    assert ro.fall_t_s is None
    assert stats.period_max_dev < 0.01  # every one of the last 20 strides within 1 % of the mean
    assert 0.8 <= stats.speed_m_s <= 1.8
    assert 0.9 <= stats.period_s <= 1.4
    assert 0.3 < stats.step_length_m < 0.9


def test_halving_the_step_changes_period_and_speed_below_one_percent() -> None:
    coarse, fine = ex.convergence(PARAMS)
    assert abs(coarse.period_s / fine.period_s - 1) < 0.01
    assert abs(coarse.speed_m_s / fine.speed_m_s - 1) < 0.01


def test_push_threshold_without_posture_controller() -> None:
    sweep = ex.push_sweep(PARAMS, phases=10)
    # the walker survives a real push at every phase, and a 1000 N push at none
    assert sweep.min_n > 100.0
    assert np.all(sweep.force_n < 1000.0 - sweep.resolution_n)
    # the threshold depends on the phase: the least and most robust phases differ by > 50 %
    assert sweep.force_n.max() > 1.5 * sweep.min_n
    # bisection invariant, checked independently: just above the weakest phase's bound it falls
    weakest = int(np.argmin(sweep.force_n))
    period = limit_cycle(PARAMS).stats.period_s
    start = start_on_cycle(PARAMS)
    model = Model.build(PARAMS)
    for force, falls in ((sweep.min_n, False), (sweep.min_n + 2 * sweep.resolution_n, True)):
        push = Push(float(sweep.phases[weakest] * period), -force, ex.PUSH_S)
        res = run_walkers(
            model, [start], period + 6.0, pushes=[[push]], fall_height_m=PARAMS.T,
            knee_floor_m=-np.inf,
        )  # fmt: skip
        assert bool(res.fell[0]) == falls, force


def test_successive_pushes_need_reinitialization() -> None:
    result = ex.successive_pushes(PARAMS)
    assert [abs(p.force_n) for p in result.pushes] == [400.0, 150.0]
    assert result.without_reinit.fall_t_s is not None
    assert result.with_reinit.fall_t_s is None
    chosen = [d.phi_c_rad for d in result.with_reinit.decisions]
    assert max(chosen) > 0.05 * np.pi  # the controller really flexed the knee at some BSP
    # and the walker is back on its cycle at the end
    cycle = limit_cycle(PARAMS)
    ro = result.with_reinit.rollout
    d = section_distance(cycle, ro.bsp_y[-2:], ro.bsp_leg[-2:])
    assert np.all(d < 0.3)
    # torque levels (Fig. 6 discussion): realistic in normal walking, higher while adapting
    normal = ex.normal_torque_levels(PARAMS)
    adapting = ex.adapting_torque_levels(result, PARAMS)
    assert adapting is not None
    assert 0.05 < normal.knee < 0.2
    assert normal.hip < 0.15
    assert normal.ankle < 0.2
    # adapting needs more knee torque than walking: "just over 1.5 times" in the paper; ours is
    # a brief peak where T_BSP and the extensor push together (docs §4.4)
    assert 1.5 * normal.knee < adapting.knee < 2.5 * normal.knee
    assert adapting.hip < 0.15
    assert adapting.ankle < 0.2


def test_a_third_push_of_500_n_is_survived_only_with_reinitialization() -> None:
    result = ex.successive_pushes(PARAMS, ex.SERIES_500, duration_s=10.0)
    assert max(abs(p.force_n) for p in result.pushes) == 500.0
    assert result.without_reinit.fall_t_s is not None
    assert result.with_reinit.fall_t_s is None
    ro = result.with_reinit.rollout
    d = section_distance(limit_cycle(PARAMS), ro.bsp_y[-2:], ro.bsp_leg[-2:])
    assert np.all(d < 0.3)


def test_auto_reinit_leaves_an_unperturbed_walker_alone() -> None:
    model = Model.build(PARAMS)
    decision = choose_phi_c(model, limit_cycle(PARAMS), start_on_cycle(PARAMS), [])
    assert decision.phi_c_rad == 0.0
    assert decision.scores[0] == min(decision.scores)


def test_phi_c_sets_the_landing_knee_angle() -> None:
    # the posture controller really shapes the BSP: the knee lands more flexed for a larger φc
    model = Model.build(PARAMS)
    phis = np.linspace(0.05, 0.25, 5) * np.pi
    res = run_walkers(
        model, [start_on_cycle(PARAMS)] * 5, 3.0, phi_c=phis, phi_c_until_bsp=True, stop_at_bsp=1
    )
    y = res.bsp_y[:, 0]
    knee = np.where(res.bsp_leg[:, 0] == 1, y[:, 2] - y[:, 3], y[:, 4] - y[:, 5])
    assert np.all(res.bsp_leg[:, 0] > 0)
    assert np.all(np.diff(knee) > 0.01 * np.pi)
    # near the paper's values (0.11π-0.20π) the knee lands within 0.03π of φc (Fig. 5)
    assert np.all(np.abs(knee[2:4] - phis[2:4]) < 0.03 * np.pi)
