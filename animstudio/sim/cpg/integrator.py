"""Fixed-step RK4 over the hybrid system, with contact bookkeeping between steps.

Why RK4 at a fixed step: the stiffest parts are the ground spring/damper (kg = 3e4 N/m,
bg = 3e3 N s/m on a 4-7 kg shank) and the fast neurons (τ = 1/50 s). Explicit RK4 is stable up to
about 0.6 ms here and converged at 0.5 ms (docs/cpg-model.md §3); an implicit method would pay
a 6x6 Jacobian per step for no gain at this stiffness, and a fixed step keeps batches of walkers
in lock-step and results bit-reproducible.

Contact is a discrete state updated after every step (never inside a stage): a foot lands when
its ankle goes below y = 0 while airborne, which anchors its horizontal spring at the landing x;
it takes off only once higher than ``contact_hysteresis_m``, so numeric chatter around y = 0
cannot re-anchor the spring. A landing with the thigh ahead of the hip (x3 > 0 / x5 > 0) is the
beginning of stance (BSP), eq. (1.3).
"""

from __future__ import annotations

import numpy as np
from numba import njit, prange

from animstudio.sim.cpg.dynamics import N_AUX, N_WORK, feet, rhs
from animstudio.sim.cpg.params import I_HYST, I_L1, I_L3

# Columns of a record row.
C_T = 0
C_X = 1  # x1..x6
C_XD = 7  # rates
C_U = 13  # u1..u12, up1, up2
C_AUX = 27  # see dynamics.N_AUX
C_CONTACT_L = C_AUX + N_AUX
C_CONTACT_R = C_CONTACT_L + 1
C_PUSH = C_CONTACT_L + 2
C_PHIC_L = C_CONTACT_L + 3
C_PHIC_R = C_CONTACT_L + 4
C_YL = C_CONTACT_L + 5
C_YR = C_CONTACT_L + 6
C_V = C_CONTACT_L + 7  # v1..v12, vp1, vp2 (for plots of the accommodation variables)
N_CHANNELS = C_V + 14

N_STEP_WORK = 5 * 40 + N_AUX + N_WORK
"""Scratch length of :func:`rk4_step` (5 stage vectors of the 40-state, aux, rhs scratch)."""

STOP_NONE = 0
STOP_AT_BSP = 1
"""Stop right after the ``stop_count``-th BSP (any leg) of this call."""


@njit(cache=True)
def _push_at(t: float, t0: np.ndarray, t1: np.ndarray, f: np.ndarray) -> float:
    s = 0.0
    for i in range(t0.shape[0]):
        if t0[i] <= t < t1[i]:
            s += f[i]
    return s


@njit(cache=True)
def _phic_at(t: float, times: np.ndarray, vals: np.ndarray) -> float:
    # Piecewise constant: vals[k] from times[k] on; 0 before the first breakpoint.
    out = 0.0
    for i in range(times.shape[0]):
        if times[i] <= t:
            out = vals[i]
        else:
            break
    return out


@njit(cache=True)
def rk4_step(
    p: np.ndarray,
    tau: np.ndarray,
    rate: np.ndarray,
    w: np.ndarray,
    y: np.ndarray,
    disc: np.ndarray,
    dt: float,
    push_n: float,
    phic_l: float,
    phic_r: float,
    posture_on: float,
    aux: np.ndarray,
    work: np.ndarray,
) -> None:
    """Advance ``y`` in place by one RK4 step (forces held over the step); ``aux`` at the start.

    ``work`` is a scratch buffer of length :data:`N_STEP_WORK` (no allocation per step).
    """
    n = y.shape[0]
    k1 = work[0:n]
    k2 = work[n : 2 * n]
    k3 = work[2 * n : 3 * n]
    k4 = work[3 * n : 4 * n]
    tmp = work[4 * n : 5 * n]
    scratch = work[5 * n : 5 * n + N_AUX]
    wk = work[5 * n + N_AUX : 5 * n + N_AUX + N_WORK]
    rhs(p, tau, rate, w, y, disc, push_n, phic_l, phic_r, posture_on, k1, aux, wk)
    for i in range(n):
        tmp[i] = y[i] + 0.5 * dt * k1[i]
    rhs(p, tau, rate, w, tmp, disc, push_n, phic_l, phic_r, posture_on, k2, scratch, wk)
    for i in range(n):
        tmp[i] = y[i] + 0.5 * dt * k2[i]
    rhs(p, tau, rate, w, tmp, disc, push_n, phic_l, phic_r, posture_on, k3, scratch, wk)
    for i in range(n):
        tmp[i] = y[i] + dt * k3[i]
    rhs(p, tau, rate, w, tmp, disc, push_n, phic_l, phic_r, posture_on, k4, scratch, wk)
    for i in range(n):
        y[i] += dt / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i])


@njit(cache=True)
def update_contacts(p: np.ndarray, y: np.ndarray, disc: np.ndarray) -> int:
    """Contact bookkeeping after a step. Returns 1/2 for a left/right BSP, 0 otherwise."""
    xl, yl, xr, yr, _, _, _, _ = feet(p, y)
    h = p[I_HYST]
    event = 0
    if disc[0] < 0.5:
        if yl < 0.0:
            disc[0] = 1.0
            disc[1] = xl
            if y[2] > 0.0:
                event = 1
    elif yl > h:
        disc[0] = 0.0
    if disc[2] < 0.5:
        if yr < 0.0:
            disc[2] = 1.0
            disc[3] = xr
            if y[4] > 0.0:
                event = 2
    elif yr > h:
        disc[2] = 0.0
    return event


@njit(cache=True)
def run(
    p: np.ndarray,
    tau: np.ndarray,
    rate: np.ndarray,
    w: np.ndarray,
    y: np.ndarray,
    disc: np.ndarray,
    t_start: float,
    dt: float,
    n_steps: int,
    rec_every: int,
    push_t0: np.ndarray,
    push_t1: np.ndarray,
    push_f: np.ndarray,
    phic_times: np.ndarray,
    phic_l: np.ndarray,
    phic_r: np.ndarray,
    posture_on: float,
    fall_height: float,
    knee_floor: float,
    after_fall_s: float,
    stop_mode: int,
    stop_count: int,
    phic_until_bsp: int,
    k0: int,
    rec: np.ndarray,
    bsp_t: np.ndarray,
    bsp_leg: np.ndarray,
    bsp_y: np.ndarray,
    out: np.ndarray,
) -> None:
    """Integrate ``n_steps`` from ``t_start`` (``y``, ``disc`` updated in place).

    Records the state after every step whose global index ``k0 + k`` is a multiple of
    ``rec_every`` into ``rec`` rows while they last (so runs chained with the right ``k0`` record
    on one grid); BSP events into ``bsp_t``/``bsp_leg``/``bsp_y`` (the state right after landing).
    With ``phic_until_bsp`` = 1 the φc schedule applies only until the first BSP of this run and
    φc = 0 after it (a candidate of the auto-reinit search). The walker has fallen when the hip drops below ``fall_height``; the run then continues for
    ``after_fall_s`` (the animation shows the fall) and stops. A non-finite state stops it too.

    ``out`` receives: [0] steps done, [1] records written, [2] BSPs written, [3] fall time
    (-1 if none), [4] 1.0 if the state became non-finite, [5] end time.
    """
    aux = np.zeros(N_AUX)
    work = np.empty(N_STEP_WORK)
    y_prev = np.empty(y.shape[0])
    d_prev0 = 0.0
    d_prev2 = 0.0
    n_rec = 0
    n_bsp = 0
    fall_t = -1.0
    bad = 0.0
    t = t_start
    k = 0
    done = 0
    while k < n_steps:
        push = _push_at(t, push_t0, push_t1, push_f)
        if phic_until_bsp == 1 and n_bsp > 0:
            pl = 0.0
            pr = 0.0
        else:
            pl = _phic_at(t, phic_times, phic_l)
            pr = _phic_at(t, phic_times, phic_r)
        recording = (k0 + k) % rec_every == 0 and n_rec < rec.shape[0]
        if recording:
            y_prev[:] = y
            d_prev0 = disc[0]
            d_prev2 = disc[2]
        rk4_step(p, tau, rate, w, y, disc, dt, push, pl, pr, posture_on, aux, work)
        if recording:
            # a row is the state at the start of a step with the forces acting on it then
            _record(p, rec[n_rec], t, y_prev, aux, d_prev0, d_prev2, push, pl, pr)
            n_rec += 1
        t = t_start + (k + 1) * dt
        k += 1
        ok = True
        for i in range(y.shape[0]):
            if not np.isfinite(y[i]):
                ok = False
        if not ok:
            bad = 1.0
            break
        ev = update_contacts(p, y, disc)
        if ev > 0 and n_bsp < bsp_t.shape[0]:
            bsp_t[n_bsp] = t
            bsp_leg[n_bsp] = ev
            bsp_y[n_bsp, :] = y
            n_bsp += 1
            if stop_mode == STOP_AT_BSP and n_bsp >= stop_count:
                break
        if fall_t < 0.0 and (y[1] < fall_height or _knee_low(p, y, knee_floor)):
            fall_t = t
        if fall_t >= 0.0 and t - fall_t >= after_fall_s:
            break
    done = k
    out[0] = done
    out[1] = n_rec
    out[2] = n_bsp
    out[3] = fall_t
    out[4] = bad
    out[5] = t


@njit(cache=True, inline="always")
def _knee_low(p: np.ndarray, y: np.ndarray, knee_floor: float) -> bool:
    return min(y[1] - p[I_L1] * np.cos(y[2]), y[1] - p[I_L3] * np.cos(y[4])) < knee_floor


@njit(cache=True)
def _record(
    p: np.ndarray,
    row: np.ndarray,
    t: float,
    y_now: np.ndarray,
    aux: np.ndarray,
    contact_l: float,
    contact_r: float,
    push: float,
    pl: float,
    pr: float,
) -> None:
    row[C_T] = t
    for i in range(12):
        row[C_X + i] = y_now[i]
    for i in range(14):
        row[C_U + i] = y_now[12 + i]
        row[C_V + i] = y_now[26 + i]
    for i in range(N_AUX):
        row[C_AUX + i] = aux[i]
    row[C_CONTACT_L] = contact_l
    row[C_CONTACT_R] = contact_r
    row[C_PUSH] = push
    row[C_PHIC_L] = pl
    row[C_PHIC_R] = pr
    _, yl, _, yr, _, _, _, _ = feet(p, y_now)
    row[C_YL] = yl
    row[C_YR] = yr


@njit(cache=True, parallel=True)
def run_batch(
    p: np.ndarray,
    tau: np.ndarray,
    rate: np.ndarray,
    w: np.ndarray,
    ys: np.ndarray,
    discs: np.ndarray,
    t_starts: np.ndarray,
    dt: float,
    n_steps: int,
    push_t0: np.ndarray,
    push_t1: np.ndarray,
    push_f: np.ndarray,
    phic_times: np.ndarray,
    phic_l: np.ndarray,
    phic_r: np.ndarray,
    posture_on: float,
    fall_height: float,
    knee_floor: float,
    stop_mode: int,
    stop_count: int,
    phic_until_bsp: int,
    bsp_t: np.ndarray,
    bsp_leg: np.ndarray,
    bsp_y: np.ndarray,
    outs: np.ndarray,
) -> None:
    """:func:`run` for B walkers in parallel (no records; BSPs and summary only).

    Per-walker arrays carry a leading batch axis: ``ys (B, N_STATE)``, ``discs (B, 4)``, ``t_starts (B,)``, pushes
    ``(B, K)``, φc schedules ``(B, M)``, ``bsp_* (B, NB[, N_STATE])``, ``outs (B, 6)``. A walker
    stops at its fall (no after-fall time: sweeps only need to know that it fell).
    """
    nb = ys.shape[0]
    for i in prange(nb):
        rec = np.zeros((0, N_CHANNELS))
        run(
            p, tau, rate, w, ys[i], discs[i], t_starts[i], dt, n_steps, 1 << 30,
            push_t0[i], push_t1[i], push_f[i], phic_times[i], phic_l[i], phic_r[i],
            posture_on, fall_height, knee_floor, 0.0, stop_mode, stop_count, phic_until_bsp, 0, rec,
            bsp_t[i], bsp_leg[i], bsp_y[i],
            outs[i],
        )  # fmt: skip
