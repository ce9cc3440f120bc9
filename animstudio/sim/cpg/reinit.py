"""Reinitialization: choose the posture controller's knee angle φc step by step.

``reinit auto`` (the product default) decides φc at every beginning of stance (BSP) for a few
steps after each push, and again right after each push ends: it simulates every candidate φc
ahead in parallel batches — φc acting until the next BSP, then the best of a few follow-up
values for the next one or two landings, with the pushes that have already begun — and keeps
the candidate whose walker comes back to the limit cycle fastest
(smallest summed Poincaré distance over the following BSPs; a fall is worst, a later fall
less bad). Pushes that have not begun yet are unknown to it, as to a walker. ``reinit off``
keeps φc = 0 throughout: the paper's normal walking.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import NDArray

from animstudio.sim.cpg.analysis import LimitCycle, limit_cycle, section_distance
from animstudio.sim.cpg.batch import BatchResult, run_walkers
from animstudio.sim.cpg.model import (
    DT_S,
    FALL_HEIGHT_M,
    CpgState,
    Model,
    Push,
    Rollout,
    init,
    rollout,
)

ReinitMode = Literal["auto", "off"]

PHI_C_CANDIDATES_RAD: NDArray[np.float64] = np.linspace(0.0, 0.3 * np.pi, 16)
"""0 to 0.3π (the knee range x_k) in 0.02π steps; the paper's values were 0.11π-0.20π."""
HORIZON_S = 4.0
"""Look-ahead of a candidate: about two strides."""
SCORED_BSPS = 6
"""BSPs after a decision whose distance from the cycle is summed."""
ACTIVE_STEPS = 6
"""Decisions continue for at least this many steps after the end of a push ..."""
ON_CYCLE = 0.3
"""... and after that until a landing is this close to the cycle (scaled Poincaré distance)."""
FOLLOW_UP_RAD: NDArray[np.float64] = np.linspace(0.0, 0.3 * np.pi, 8)
"""φc values tried for the landing after the candidate's (the second look-ahead level)."""
BEAM = 8
"""(candidate, follow-up) pairs taken one landing further (the third look-ahead level)."""
_FALL = 1e6
"""Score of a fall (minus how long the walker lasted): worse than any walk."""


@dataclass(frozen=True)
class Decision:
    """φc chosen at ``t_s`` for the next landing, with every candidate's score (lower = better)."""

    t_s: float
    phi_c_rad: float
    candidates_rad: tuple[float, ...]
    scores: tuple[float, ...]


@dataclass(frozen=True, eq=False)
class Walk:
    """A whole simulated script: the chained rollout, the φc decisions, the fall (if any)."""

    rollout: Rollout
    decisions: tuple[Decision, ...]
    fall_t_s: float | None


def _score(
    cycle: LimitCycle,
    t_s: float,
    res_bsp_y: NDArray[np.float64],
    legs: NDArray[np.int64],
    fall: float,
) -> float:
    if not np.isnan(fall):
        # every fall is worse than any walk; among falls the later one is less bad
        return _FALL - (fall - t_s)
    mask = legs > 0
    d = section_distance(cycle, res_bsp_y[mask][:SCORED_BSPS], legs[mask][:SCORED_BSPS])
    missing = SCORED_BSPS - d.shape[0]
    return float(d.sum() + 10.0 * max(0, missing))


def choose_phi_c(
    model: Model,
    cycle: LimitCycle,
    state: CpgState,
    known_pushes: Sequence[Push],
    *,
    candidates: NDArray[np.float64] = PHI_C_CANDIDATES_RAD,
    follow_up: NDArray[np.float64] = FOLLOW_UP_RAD,
    beam: int = BEAM,
    dt: float = DT_S,
) -> Decision:
    """Pick φc for the next landing by a three-landing look-ahead (parallel batches).

    Every candidate is simulated to its landing; from each landing every ``follow_up`` value is
    tried for the landing after it (then φc = 0) over :data:`HORIZON_S`. A candidate scores the
    best of its follow-ups: the controller will decide again at that landing, so judging a
    candidate by φc = 0 afterwards would reject first steps that need one more corrected step.
    The ``beam`` best (candidate, follow-up) pairs are then taken one landing further and every
    ``follow_up`` value is tried for the third landing: after a hard push a walker may need
    three corrected steps, and a two-landing look-ahead sees every candidate fall (docs §4, 5).
    """
    n = candidates.shape[0]
    m = follow_up.shape[0]
    pushes = list(known_pushes)

    def batch(starts: list[CpgState], phi: NDArray[np.float64], stop: int) -> BatchResult:
        return run_walkers(
            model, starts, HORIZON_S, pushes=[pushes] * len(starts), phi_c=phi,
            phi_c_until_bsp=True, dt=dt, fall_height_m=FALL_HEIGHT_M, stop_at_bsp=stop,
        )  # fmt: skip

    def landed(res: BatchResult, i: int) -> bool:
        return not res.fell[i] and res.bsp_leg[i, 0] != 0

    def tails(res: BatchResult, k: int, base: float, t0: float) -> list[float]:
        # walkers k*m .. k*m+m-1 of ``res`` are one start's follow-ups, started at t0
        return [
            base
            + _score(
                cycle, t0, res.bsp_y[k * m + j], res.bsp_leg[k * m + j], res.fall_t_s[k * m + j]
            )
            for j in range(m)
        ]

    first = batch([state] * n, candidates, 1)
    scores = np.full(n, np.inf)
    alive = []
    for i in range(n):
        if landed(first, i):
            alive.append(i)
        else:
            fall = first.fall_t_s[i] if first.fell[i] else first.end_t_s[i]
            scores[i] = _FALL - (fall - state.t_s)
    if alive:
        second = batch(
            [first.final_state(i) for i in alive for _ in range(m)],
            np.tile(follow_up, len(alive)),
            0,
        )
        pairs: list[tuple[float, int, int, float]] = []  # (score, candidate, follow-up, d0)
        for a, i in enumerate(alive):
            d0 = section_distance(cycle, first.bsp_y[i, :1], first.bsp_leg[i, :1])[0]
            child = tails(second, a, d0, float(first.end_t_s[i]))
            scores[i] = min(child)
            pairs += [(child[j], i, j, d0) for j in range(m)]
        pairs.sort()
        top = pairs[:beam]
        if top and beam > 0:
            mid = batch(
                [first.final_state(i) for _, i, _, _ in top],
                np.array([follow_up[j] for _, _, j, _ in top]), 1,
            )  # fmt: skip
            deep = [k for k in range(len(top)) if landed(mid, k)]
            if deep:
                third = batch(
                    [mid.final_state(k) for k in deep for _ in range(m)],
                    np.tile(follow_up, len(deep)), 0,
                )  # fmt: skip
                for a, k in enumerate(deep):
                    _, i, _, d0 = top[k]
                    d1 = section_distance(cycle, mid.bsp_y[k, :1], mid.bsp_leg[k, :1])[0]
                    scores[i] = min(scores[i], min(tails(third, a, d0 + d1, float(mid.end_t_s[k]))))
    best = int(np.argmin(scores))  # ties go to the smallest φc (candidates ascend from 0)
    return Decision(state.t_s, float(candidates[best]), tuple(candidates.tolist()), tuple(scores))


def _concat(parts: list[Rollout]) -> Rollout:
    return Rollout(
        records=np.concatenate([p.records for p in parts]),
        bsp_t_s=np.concatenate([p.bsp_t_s for p in parts]),
        bsp_leg=np.concatenate([p.bsp_leg for p in parts]),
        bsp_y=np.concatenate([p.bsp_y for p in parts]),
        fall_t_s=next((p.fall_t_s for p in parts if p.fall_t_s is not None), None),
        final=parts[-1].final,
    )


def simulate_walk(
    model: Model,
    duration_s: float,
    pushes: Sequence[Push] = (),
    *,
    reinit: ReinitMode = "auto",
    start: CpgState | None = None,
    record_every: int = 20,
    dt: float = DT_S,
    after_fall_s: float = 1.5,
) -> Walk:
    """Simulate ``duration_s`` from ``start`` (default: the stated initial condition).

    After a fall the simulation runs ``after_fall_s`` more and ends (the caller holds the pose).
    """
    state = start if start is not None else init(model.params)
    t_end = state.t_s + duration_s
    pushes = sorted(pushes, key=lambda p: p.t_s)
    if reinit == "off":
        ro = rollout(
            model, state, duration_s, dt=dt, record_every=record_every, pushes=pushes,
            after_fall_s=after_fall_s,
        )  # fmt: skip
        return Walk(ro, (), ro.fall_t_s)
    cycle = limit_cycle(model.params)
    push_ends = sorted(p.t_s + p.duration_s for p in pushes)
    parts: list[Rollout] = []
    decisions: list[Decision] = []
    remaining = 0
    while state.t_s < t_end - 0.5 * dt:
        t = state.t_s
        phi = 0.0
        if remaining > 0:
            known = [p for p in pushes if p.t_s <= t + 0.5 * dt]
            decision = choose_phi_c(model, cycle, state, known, dt=dt)
            decisions.append(decision)
            phi = decision.phi_c_rad
        stop = min([e for e in push_ends if e > t + 0.5 * dt] + [t_end])
        seg = rollout(
            model, state, stop - t, dt=dt, record_every=record_every, pushes=pushes,
            phi_c=([t], [phi], [phi]), stop_at_bsp=1 if remaining > 0 else 0, phi_c_until_bsp=True,
            after_fall_s=after_fall_s,
        )  # fmt: skip
        parts.append(seg)
        state = seg.final
        if seg.fall_t_s is not None:
            rest = min(after_fall_s - (state.t_s - seg.fall_t_s), t_end - state.t_s)
            if rest > 0.5 * dt:
                parts.append(
                    rollout(model, state, rest, dt=dt, record_every=record_every, pushes=pushes)
                )
            break
        ended_at_push = any(abs(state.t_s - e) < 0.5 * dt for e in push_ends)
        if ended_at_push:
            remaining = ACTIVE_STEPS
        elif seg.bsp_leg.size:
            # keep reinitializing while the walker is still off its cycle at this landing
            off = section_distance(cycle, seg.bsp_y[-1:], seg.bsp_leg[-1:])[0] > ON_CYCLE
            remaining = max(remaining - 1, 1 if off and remaining > 0 else 0)
    ro = _concat(parts)
    return Walk(ro, tuple(decisions), ro.fall_t_s)
