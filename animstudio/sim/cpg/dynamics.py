"""Right-hand side of the coupled system (1.4): CPG (2.1)-(2.2), posture controller (2.3)-(2.4),
body P(x)ẍ = Q (Appendix A) with ground reaction, passive and active torques.

State vector ``y`` (N_STATE = 40): ``x1..x6`` (hip x, hip height, left thigh, left shank, right
thigh, right shank; angles from the downward vertical, positive = distal end ahead), their rates,
``u`` (14), ``v`` (14). Discrete contact state ``disc`` (4): left/right contact flag (0/1) and
the x of the anchor of each foot's horizontal ground spring (set at touch-down).

The kernels are numba-compiled with ``cache=True``; every function here is also callable from
plain Python (numba falls back to the interpreter only for debugging via NUMBA_DISABLE_JIT).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from animstudio.sim.cpg.params import (
    I_A,
    I_ALPHA,
    I_ANKLE_GATE,
    I_B,
    I_BB,
    I_BG,
    I_BP,
    I_BSP_GATE,
    I_BSP_REPLACES,
    I_DELTA,
    I_FB,
    I_G,
    I_GAMMA,
    I_HIP_GATE,
    I_KG,
    I_KP,
    I_L1,
    I_L2,
    I_L3,
    I_L4,
    I_M1,
    I_M2,
    I_M3,
    I_M4,
    I_M5,
    I_P1,
    I_P2,
    I_P3,
    I_P4,
    I_P5,
    I_P6,
    I_PE1,
    I_PE2,
    I_PP1,
    I_PP2,
    I_PV1,
    I_PV2,
    I_T,
    I_XH,
    I_XK,
    N_NEURONS,
)  # fmt: skip

N_AUX = 16
"""Auxiliary outputs of :func:`rhs`: [0-5] hip_l, knee_l, ankle_l, hip_r, knee_r, ankle_r:
active torques Tr1..Tr6 of the appendix *without* the range stops (the neurons' torques, Nm;
knee positive = extension); [6-7] T_BSP left/right (Nm); [8-11] ground Fx/Fy left, Fx/Fy right
(N); [12-15] range-stop torques Th_l, Tk_l, Th_r, Tk_r (Nm), also active in the appendix."""


@njit(cache=True, inline="always")
def _pos(z: float) -> float:
    # f(z) = max(0, z) of the seed
    return z if z > 0.0 else 0.0


@njit(cache=True, inline="always")
def _step(z: float) -> float:
    # g(z) = 1 for z > 0 else 0
    return 1.0 if z > 0.0 else 0.0


@njit(cache=True)
def feet(
    p: np.ndarray, y: np.ndarray
) -> tuple[float, float, float, float, float, float, float, float]:
    """Ankle positions and velocities (1.2): ``xl, yl, xr, yr, dxl, dyl, dxr, dyr``."""
    l1, l2, l3, l4 = p[I_L1], p[I_L2], p[I_L3], p[I_L4]
    s3, c3, s4, c4 = np.sin(y[2]), np.cos(y[2]), np.sin(y[3]), np.cos(y[3])
    s5, c5, s6, c6 = np.sin(y[4]), np.cos(y[4]), np.sin(y[5]), np.cos(y[5])
    xl = y[0] + l1 * s3 + l2 * s4
    yl = y[1] - l1 * c3 - l2 * c4
    xr = y[0] + l3 * s5 + l4 * s6
    yr = y[1] - l3 * c5 - l4 * c6
    dxl = y[6] + l1 * c3 * y[8] + l2 * c4 * y[9]
    dyl = y[7] + l1 * s3 * y[8] + l2 * s4 * y[9]
    dxr = y[6] + l3 * c5 * y[10] + l4 * c6 * y[11]
    dyr = y[7] + l3 * s5 * y[10] + l4 * s6 * y[11]
    return xl, yl, xr, yr, dxl, dyl, dxr, dyr


@njit(cache=True)
def _solve_spd(
    m: np.ndarray, q: np.ndarray, lo: np.ndarray, z: np.ndarray, out: np.ndarray
) -> None:
    # P(x) is symmetric positive definite (a mass matrix): Cholesky without pivoting is exact
    # and cheaper than a general LU for 6x6. Matrices are flat row-major (6*6,) work buffers so
    # the hot loop never allocates.
    n = 6
    for i in range(n):
        for j in range(i + 1):
            s = m[i * n + j]
            for k in range(j):
                s -= lo[i * n + k] * lo[j * n + k]
            if i == j:
                lo[i * n + i] = np.sqrt(s)
            else:
                lo[i * n + j] = s / lo[j * n + j]
    for i in range(n):
        s = q[i]
        for k in range(i):
            s -= lo[i * n + k] * z[k]
        z[i] = s / lo[i * n + i]
    for i in range(n - 1, -1, -1):
        s = z[i]
        for k in range(i + 1, n):
            s -= lo[k * n + i] * out[k]
        out[i] = s / lo[i * n + i]


N_WORK = 14 + 36 + 36 + 6 + 6 + 6
"""Length of the scratch buffer :func:`rhs` needs."""


@njit(cache=True)
def rhs(
    p: np.ndarray,
    tau: np.ndarray,
    rate: np.ndarray,
    w: np.ndarray,
    y: np.ndarray,
    disc: np.ndarray,
    push_n: float,
    phic_l: float,
    phic_r: float,
    posture_on: float,
    dy: np.ndarray,
    aux: np.ndarray,
    wk: np.ndarray,
) -> None:
    """Write dy/dt into ``dy`` and the torques/forces into ``aux`` (see N_AUX).

    Args:
        push_n: horizontal force on the hip, +x forward (N).
        phic_l, phic_r: posture-controller equilibrium knee angles φc (rad).
        posture_on: 1.0 to apply T_BSP, 0.0 to disable the posture controller entirely.
        wk: scratch buffer of length :data:`N_WORK`.
    """
    m1, m2, m3, m4, m5 = p[I_M1], p[I_M2], p[I_M3], p[I_M4], p[I_M5]
    l1, l2, l3, l4 = p[I_L1], p[I_L2], p[I_L3], p[I_L4]
    g = p[I_G]
    x3, x4, x5, x6 = y[2], y[3], y[4], y[5]
    d3, d4, d5, d6 = y[8], y[9], y[10], y[11]
    s3, c3, s4, c4 = np.sin(x3), np.cos(x3), np.sin(x4), np.cos(x4)
    s5, c5, s6, c6 = np.sin(x5), np.cos(x5), np.sin(x6), np.cos(x6)
    i1 = m2 * l1 * l1 / 12.0
    i2 = m3 * l2 * l2 / 12.0
    i3 = m4 * l3 * l3 / 12.0
    i4 = m5 * l4 * l4 / 12.0

    # --- ground reaction (Appendix A): springs anchored at touch-down, damping only downward
    xl, yl, xr, yr, dxl, dyl, dxr, dyr = feet(p, y)
    kg, bg = p[I_KG], p[I_BG]
    fg1 = fg2 = fg3 = fg4 = 0.0
    if disc[0] > 0.5 and yl < 0.0:
        fg1 = -kg * (xl - disc[1]) - bg * dxl
        fg2 = -kg * yl + bg * _pos(-dyl)
    if disc[2] > 0.5 and yr < 0.0:
        fg3 = -kg * (xr - disc[3]) - bg * dxr
        fg4 = -kg * yr + bg * _pos(-dyr)

    # --- neurons (2.1)-(2.3); u0 switched off below hip height T (2.2)
    u = y[12 : 12 + N_NEURONS]
    v = y[12 + N_NEURONS : 12 + 2 * N_NEURONS]
    u0 = p[I_GAMMA] if y[1] >= p[I_T] else 0.0
    fu = wk[0:N_NEURONS]
    for i in range(N_NEURONS):
        fu[i] = _pos(u[i])
    e = p[I_FB] * (_pos(-x3) - _pos(-x5))  # E = f(-x3) - f(-x5), E' = -E
    a, bb = p[I_A], p[I_BB]
    for i in range(N_NEURONS):
        s = 0.0
        for j in range(N_NEURONS):
            s += w[j, i] * fu[j]
        fb = 0.0
        if i == 0 or i == 7:
            fb = e
        elif i == 1 or i == 6:
            fb = -e
        dy[12 + i] = (u[i] - v[i] - u[i] ** 3 / 3.0 + s + u0 + fb) / tau[i]
        dy[12 + N_NEURONS + i] = rate[i] * (u[i] + a - bb * v[i])

    # --- active torques (Appendix A); range stops restoring [docs §2.4]
    th_l = 0.0
    ex = x3 - x5 - p[I_XH]
    gate_l = _step(u[0]) if p[I_HIP_GATE] > 0.5 else 1.0
    gate_r = _step(u[6]) if p[I_HIP_GATE] > 0.5 else 1.0
    if ex > 0.0 and gate_l > 0.0:
        th_l = min(0.0, -(p[I_PE1] * ex + p[I_PV1] * (d3 - d5)))
    th_r = 0.0
    ex = x5 - x3 - p[I_XH]
    if ex > 0.0 and gate_r > 0.0:
        th_r = min(0.0, -(p[I_PE1] * ex + p[I_PV1] * (d5 - d3)))
    tk_l = 0.0
    ex = x3 - x4 - p[I_XK]
    if ex > 0.0:
        tk_l = max(0.0, p[I_PE2] * ex + p[I_PV2] * (d3 - d4))
    tk_r = 0.0
    ex = x5 - x6 - p[I_XK]
    if ex > 0.0:
        tk_r = max(0.0, p[I_PE2] * ex + p[I_PV2] * (d5 - d6))
    hip_l = p[I_P1] * fu[0] - p[I_P2] * fu[1] + th_l
    knee_l = p[I_P3] * fu[2] - p[I_P4] * fu[3] + tk_l
    if p[I_ANKLE_GATE] > 0.5:
        ankle_l = p[I_P5] * fu[4] - p[I_P6] * fu[5] * _step(-yl)
        ankle_r = p[I_P5] * fu[10] - p[I_P6] * fu[11] * _step(-yr)
    else:
        ankle_l = (p[I_P5] * fu[4] - p[I_P6] * fu[5]) * _step(-yl)
        ankle_r = (p[I_P5] * fu[10] - p[I_P6] * fu[11]) * _step(-yr)
    hip_r = p[I_P1] * fu[6] - p[I_P2] * fu[7] + th_r
    knee_r = p[I_P3] * fu[8] - p[I_P4] * fu[9] + tk_r

    # --- posture modulation torque (2.4): while p fires and the foot swings, a PD (damping sign
    # restored) drives the knee to φc from either side, clamped to ±δ by f_m (docs §2.4: the
    # printed gate g(x3 - x4 - φc) with the antagonist -α f(u_p) only reaches φc + α f/pp1, about
    # φc + 0.08π, so no small φc is possible; bsp_literal_gate = 1 and α > 0 give that reading).
    # φc = 0 is the paper's normal walking "without posture modulation": no T_BSP. T_BSP is added
    # to the CPG knee torque as Appendix A prints q3, q4; with pp1, pp2, δ scaled like the CPG
    # gains it can hold the knee against the extensor ("coactivation", §2.4).
    # bsp_replaces_cpg = 1 withholds the CPG knee torque in that window (the earlier reading).
    delta = p[I_DELTA]
    bsp_l = 0.0
    bsp_r = 0.0
    if posture_on > 0.5:
        if phic_l > 0.0 and u[12] > 0.0 and yl > 0.0:
            k = x3 - x4 - phic_l
            t_l = p[I_PP1] * k + p[I_PP2] * (d3 - d4)
            if p[I_BSP_GATE] > 0.5 and k <= 0.0:
                t_l = 0.0
            bsp_l = min(delta, max(-delta, t_l - p[I_ALPHA] * fu[12]))
            if p[I_BSP_REPLACES] > 0.5:
                knee_l = tk_l
        if phic_r > 0.0 and u[13] > 0.0 and yr > 0.0:
            k = x5 - x6 - phic_r
            t_r = p[I_PP1] * k + p[I_PP2] * (d5 - d6)
            if p[I_BSP_GATE] > 0.5 and k <= 0.0:
                t_r = 0.0
            bsp_r = min(delta, max(-delta, t_r - p[I_ALPHA] * fu[13]))
            if p[I_BSP_REPLACES] > 0.5:
                knee_r = tk_r

    # --- passive torques: knee hyper-extension stop (one-sided damping) and joint viscosity
    b = p[I_B]
    hx = x4 - x3
    stop_l = (p[I_KP] * hx + p[I_BP] * _pos(d4 - d3)) if hx > 0.0 else 0.0
    hx = x6 - x5
    stop_r = (p[I_KP] * hx + p[I_BP] * _pos(d6 - d5)) if hx > 0.0 else 0.0
    trp1 = stop_l - b * (d3 - d5) - b * (d3 - d4)
    trp2 = -stop_l - b * (d4 - d3) - b * d4
    trp3 = stop_r - b * (d5 - d3) - b * (d5 - d6)
    trp4 = -stop_r - b * (d6 - d5) - b * d6

    # --- P(x) ẍ = Q (Appendix A)
    mt = m1 + m2 + m3 + m4 + m5
    a3 = (0.5 * m2 + m3) * l1
    a4 = 0.5 * m3 * l2
    a5 = (0.5 * m4 + m5) * l3
    a6 = 0.5 * m5 * l4
    mm = wk[14:50]
    lo = wk[50:86]
    q = wk[86:92]
    acc = wk[92:98]
    zz = wk[98:104]
    for i in range(36):
        mm[i] = 0.0
    mm[0] = mt
    mm[7] = mt
    mm[2] = mm[12] = a3 * c3
    mm[8] = mm[13] = a3 * s3
    mm[3] = mm[18] = a4 * c4
    mm[9] = mm[19] = a4 * s4
    mm[4] = mm[24] = a5 * c5
    mm[10] = mm[25] = a5 * s5
    mm[5] = mm[30] = a6 * c6
    mm[11] = mm[31] = a6 * s6
    mm[14] = 0.25 * m2 * l1 * l1 + m3 * l1 * l1 + i1
    mm[15] = mm[20] = 0.5 * m3 * l1 * l2 * np.cos(x3 - x4)
    mm[21] = 0.25 * m3 * l2 * l2 + i2
    mm[28] = 0.25 * m4 * l3 * l3 + m5 * l3 * l3 + i3
    mm[29] = mm[34] = 0.5 * m5 * l3 * l4 * np.cos(x5 - x6)
    mm[35] = 0.25 * m5 * l4 * l4 + i4
    q[0] = a3 * s3 * d3 * d3 + a4 * s4 * d4 * d4 + a5 * s5 * d5 * d5 + a6 * s6 * d6 * d6
    q[0] += fg1 + fg3 + push_n
    q[1] = -a3 * c3 * d3 * d3 - a4 * c4 * d4 * d4 - a5 * c5 * d5 * d5 - a6 * c6 * d6 * d6
    q[1] += fg2 + fg4 - mt * g
    q[2] = 0.5 * m3 * l1 * l2 * np.sin(x4 - x3) * d4 * d4 + fg1 * l1 * c3 + fg2 * l1 * s3
    q[2] += -a3 * g * s3 + trp1 + hip_l - knee_l - hip_r - bsp_l
    q[3] = 0.5 * m3 * l1 * l2 * np.sin(x3 - x4) * d3 * d3 + fg1 * l2 * c4 + fg2 * l2 * s4
    q[3] += -a4 * g * s4 + trp2 + knee_l - ankle_l + bsp_l
    q[4] = 0.5 * m5 * l3 * l4 * np.sin(x6 - x5) * d6 * d6 + fg3 * l3 * c5 + fg4 * l3 * s5
    q[4] += -a5 * g * s5 + trp3 + hip_r - knee_r - hip_l - bsp_r
    q[5] = 0.5 * m5 * l3 * l4 * np.sin(x5 - x6) * d5 * d5 + fg3 * l4 * c6 + fg4 * l4 * s6
    q[5] += -a6 * g * s6 + trp4 + knee_r - ankle_r + bsp_r
    _solve_spd(mm, q, lo, zz, acc)
    for i in range(6):
        dy[i] = y[6 + i]
        dy[6 + i] = acc[i]

    aux[0] = hip_l - th_l
    aux[1] = knee_l - tk_l
    aux[2] = ankle_l
    aux[3] = hip_r - th_r
    aux[4] = knee_r - tk_r
    aux[5] = ankle_r
    aux[6] = bsp_l
    aux[7] = bsp_r
    aux[8] = fg1
    aux[9] = fg2
    aux[10] = fg3
    aux[11] = fg4
    aux[12] = th_l
    aux[13] = tk_l
    aux[14] = th_r
    aux[15] = tk_r
