"""Gait analysis on rollouts: strides, the limit cycle, distance from it.

A stride is the time between two successive beginnings of stance (BSP, eq. 1.3) of the same
leg; speed is the hip's advance over strides divided by their duration; step length is the
forward distance between the two ankles at a BSP.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from animstudio.errors import SimulationError
from animstudio.sim.cpg.model import CpgState, Model, Rollout, init, rollout
from animstudio.sim.cpg.params import CpgParams

SETTLE_S = 40.0
"""Simulated time after which the walker from the stated initial condition is on its cycle."""
# Poincaré-section coordinates compared between BSPs: hip velocity (2), link angles (4), link
# rates (4), and the hip neurons' accommodation v (4) for the CPG's phase. Rates are scaled by
# 0.1 s so a 0.1 rad angle error weighs like a 1 rad/s rate error.
_SECTION = np.array([6, 7, 2, 3, 4, 5, 8, 9, 10, 11, 26, 27, 32, 33])
_SCALE = np.array([1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 0.1, 0.1, 0.1, 0.1, 0.5, 0.5, 0.5, 0.5])


@dataclass(frozen=True)
class StrideStats:
    """Gait figures over the last ``strides`` strides of the left leg.

    Attributes:
        period_s: mean stride period; period_cv: its coefficient of variation (std / mean);
        period_max_dev: largest |period - mean| / mean over those strides.
        speed_m_s: mean forward hip speed; stride_length_m: hip advance per stride;
        step_length_m: mean ankle-to-ankle distance at BSP.
    """

    strides: int
    period_s: float
    period_cv: float
    period_max_dev: float
    speed_m_s: float
    stride_length_m: float
    step_length_m: float


def stride_stats(ro: Rollout, params: CpgParams, *, strides: int = 20) -> StrideStats:
    """Stride figures of a rollout (raises SimulationError if it has too few strides)."""
    left = ro.bsp_leg == 1
    t = ro.bsp_t_s[left]
    ys = ro.bsp_y[left]
    if t.shape[0] < strides + 1:
        raise SimulationError(f"only {max(0, t.shape[0] - 1)} strides, {strides} needed")
    t = t[-(strides + 1) :]
    ys = ys[-(strides + 1) :]
    periods = np.diff(t)
    mean = float(periods.mean())
    advance = np.diff(ys[:, 0])
    xl = ys[:, 0] + params.l1 * np.sin(ys[:, 2]) + params.l2 * np.sin(ys[:, 3])
    xr = ys[:, 0] + params.l3 * np.sin(ys[:, 4]) + params.l4 * np.sin(ys[:, 5])
    return StrideStats(
        strides=strides,
        period_s=mean,
        period_cv=float(periods.std() / mean),
        period_max_dev=float(np.max(np.abs(periods - mean)) / mean),
        speed_m_s=float(advance.sum() / periods.sum()),
        stride_length_m=float(advance.mean()),
        step_length_m=float(np.mean(xl - xr)),
    )


@dataclass(frozen=True, eq=False)
class LimitCycle:
    """The settled gait: Poincaré points at the left (``section[0]``) and right BSP, ``(2, 14)``."""

    section: NDArray[np.float64]
    stats: StrideStats
    settled: Rollout


@functools.lru_cache(maxsize=8)
def limit_cycle(params: CpgParams) -> LimitCycle:
    """Simulate the stated initial condition for :data:`SETTLE_S` and read off the cycle.

    Raises:
        SimulationError: the walker falls or has not settled (stride periods vary > 1 %).
    """
    model = Model.build(params)
    # the start from rest crouches deeply before it walks: judge it by the paper's fall (x2 < T)
    ro = rollout(
        model, init(params), SETTLE_S, record_every=1 << 20, fall_height_m=params.T,
        knee_floor_m=-np.inf,
    )  # fmt: skip
    if ro.fall_t_s is not None:
        raise SimulationError(f"the walker falls at {ro.fall_t_s:.2f} s from the initial condition")
    stats = stride_stats(ro, params, strides=10)
    if stats.period_max_dev > 0.01:
        raise SimulationError(f"no limit cycle: stride periods vary by {stats.period_max_dev:.1%}")
    section = np.stack([ro.bsp_y[ro.bsp_leg == leg][-1][_SECTION] for leg in (1, 2)])
    return LimitCycle(section=section, stats=stats, settled=ro)


def section_distance(
    cycle: LimitCycle, bsp_y: NDArray[np.float64], legs: NDArray[np.int64]
) -> NDArray[np.float64]:
    """Scaled distance of BSP states ``(n, 40)`` (legs 1/2) from the cycle's Poincaré points."""
    ref = cycle.section[np.asarray(legs) - 1]
    return np.sqrt(np.sum(((bsp_y[:, _SECTION] - ref) * _SCALE) ** 2, axis=1))


def start_on_cycle(params: CpgParams) -> CpgState:
    """The settled walker at a left BSP, moved to x = 0 and t = 0 (steady walking from t = 0)."""
    cyc = limit_cycle(params)
    model = Model.build(params)
    state = cyc.settled.final
    for _ in range(3):  # at most: a right BSP, then the left one
        ro = rollout(model, state, 3.0, record_every=1 << 20, stop_at_bsp=1)
        state = ro.final
        if ro.bsp_leg.size and ro.bsp_leg[-1] == 1:
            break
    y, disc = state.copy_arrays()
    x0 = y[0]
    y[0] -= x0
    disc[1] -= x0  # the ground-spring anchors move with the body
    disc[3] -= x0
    return CpgState(0.0, y, disc)
