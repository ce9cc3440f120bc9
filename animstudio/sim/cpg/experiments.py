"""The seed's experiments as functions (tests and docs call these; nothing is tuned here).

* :func:`normal_walking` — walking emerges from the stated initial condition (issue item 1);
* :func:`convergence` — the same walk at ``dt`` and ``dt / 2`` (integrator choice);
* :func:`push_sweep` — largest survivable 0.1 s backward push over gait phases, φc = 0 (item 2);
* :func:`successive_pushes` — the paper's series with and without reinitialization (item 3);
* :func:`torque_levels` — active torques per body weight, normal vs adapting (item 4).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from animstudio.sim.cpg import integrator as ig
from animstudio.sim.cpg.analysis import StrideStats, limit_cycle, start_on_cycle, stride_stats
from animstudio.sim.cpg.batch import run_walkers
from animstudio.sim.cpg.model import DT_S, Model, Push, Rollout, init, rollout
from animstudio.sim.cpg.params import CpgParams
from animstudio.sim.cpg.reinit import Walk, simulate_walk

PUSH_S = 0.1
"""Duration of every push in the paper's experiments."""
SERIES: tuple[tuple[float, float], ...] = ((2.1, 400.0), (2.7, 150.0))
"""The successive backward pushes ``(start s, force N)`` from a left BSP at t = 0: 400 N, then
150 N 0.6 s later, within one stride (docs/cpg-model.md §4)."""
SERIES_500: tuple[tuple[float, float], ...] = (*SERIES, (4.5, 500.0))
""":data:`SERIES` and a third push of 500 N at 4.5 s, the issue's "up to 500 N" (docs §4)."""


def normal_walking(
    params: CpgParams, duration_s: float = 60.0, *, dt: float = DT_S
) -> tuple[StrideStats, Rollout]:
    """Walk ``duration_s`` from the stated initial condition; figures over the last 20 strides."""
    ro = rollout(
        Model.build(params), init(params), duration_s, dt=dt, record_every=1 << 30,
        fall_height_m=params.T, knee_floor_m=-np.inf,
    )  # fmt: skip
    return stride_stats(ro, params, strides=20), ro


def convergence(
    params: CpgParams, dt: float = DT_S, duration_s: float = 30.0
) -> tuple[StrideStats, StrideStats]:
    """The settled walk at ``dt`` and at ``dt / 2`` (strides 10 over the last part of each)."""
    out = []
    for step in (dt, dt / 2):
        ro = rollout(
            Model.build(params), init(params), duration_s, dt=step, record_every=1 << 30,
            fall_height_m=params.T, knee_floor_m=-np.inf,
        )  # fmt: skip
        out.append(stride_stats(ro, params, strides=10))
    return out[0], out[1]


@dataclass(frozen=True, eq=False)
class PushSweep:
    """Largest survived push per phase: ``phases (P,)`` in strides after a left BSP, ``force_n``."""

    phases: NDArray[np.float64]
    force_n: NDArray[np.float64]
    resolution_n: float

    @property
    def min_n(self) -> float:
        return float(self.force_n.min())


def push_sweep(
    params: CpgParams,
    *,
    phases: int = 10,
    max_force_n: float = 1000.0,
    iterations: int = 8,
    horizon_s: float = 6.0,
) -> PushSweep:
    """Bisection, all phases in parallel, for the largest 0.1 s backward push survived at φc = 0.

    A fall is the paper's: the hip below T (2.2) within ``horizon_s`` after the push.
    Survival is assumed monotonic in the force (true in every sweep we looked at: §5).
    """
    model = Model.build(params)
    start = start_on_cycle(params)
    period = limit_cycle(params).stats.period_s
    ph = np.arange(phases) / phases
    lo = np.zeros(phases)
    hi = np.full(phases, max_force_n)
    for _ in range(iterations):
        mid = 0.5 * (lo + hi)
        pushes = [
            [Push(float(p * period), -float(f), PUSH_S)] for p, f in zip(ph, mid, strict=True)
        ]
        res = run_walkers(
            model, [start] * phases, float(period + horizon_s), pushes=pushes,
            fall_height_m=params.T, knee_floor_m=-np.inf,
        )  # fmt: skip
        lo = np.where(res.fell, lo, mid)
        hi = np.where(res.fell, mid, hi)
    return PushSweep(ph, lo, max_force_n / 2**iterations)


@dataclass(frozen=True, eq=False)
class SeriesResult:
    pushes: tuple[Push, ...]
    with_reinit: Walk
    without_reinit: Walk


def successive_pushes(
    params: CpgParams, series: tuple[tuple[float, float], ...] = SERIES, duration_s: float = 8.0
) -> SeriesResult:
    """The series of backward pushes with ``reinit auto`` and with ``reinit off`` (φc = 0)."""
    model = Model.build(params)
    start = start_on_cycle(params)
    pushes = tuple(Push(t, -f, PUSH_S) for t, f in series)
    auto = simulate_walk(model, duration_s, pushes, reinit="auto", start=start, record_every=10)
    off = simulate_walk(model, duration_s, pushes, reinit="off", start=start, record_every=10)
    return SeriesResult(pushes, auto, off)


@dataclass(frozen=True)
class TorqueLevels:
    """Peak |active torque| per body weight (Nm/N) of each joint over a stretch of walking.

    ``knee``, ``hip``, ``ankle``: the neurons' torques (knee: CPG + T_BSP), the muscle-like part
    the paper's Fig. 6 discusses. ``knee_stop``, ``hip_stop``: peaks of the range-stop torques
    Tk, Th (appendix), brief impacts at the ends of the joint ranges, reported apart.
    """

    knee: float
    hip: float
    ankle: float
    knee_stop: float
    hip_stop: float


def torque_levels(records: NDArray[np.float64], params: CpgParams) -> TorqueLevels:
    """Peaks over ``records`` (both legs)."""
    a = records[:, ig.C_AUX :] / params.body_weight_n

    def peak(*cols: NDArray[np.float64]) -> float:
        return float(np.abs(np.concatenate(cols)).max())

    return TorqueLevels(
        knee=peak(a[:, 1] + a[:, 6], a[:, 4] + a[:, 7]),
        hip=peak(a[:, 0], a[:, 3]),
        ankle=peak(a[:, 2], a[:, 5]),
        knee_stop=peak(a[:, 13], a[:, 15]),
        hip_stop=peak(a[:, 12], a[:, 14]),
    )


def normal_torque_levels(params: CpgParams, duration_s: float = 5.0) -> TorqueLevels:
    """Torque peaks over ``duration_s`` of steady walking."""
    ro = rollout(Model.build(params), start_on_cycle(params), duration_s, record_every=1)
    return torque_levels(ro.records, params)


def adapting_torque_levels(
    result: SeriesResult, params: CpgParams, after_s: float = 2.0
) -> TorqueLevels | None:
    """Torque peaks with reinit from the first push to ``after_s`` after the last (None: fell)."""
    walk = result.with_reinit
    if walk.fall_t_s is not None:
        return None
    rec = walk.rollout.records
    t0 = result.pushes[0].t_s
    t1 = result.pushes[-1].t_s + after_s
    window = rec[(rec[:, ig.C_T] >= t0) & (rec[:, ig.C_T] <= t1)]
    return torque_levels(window, params)
