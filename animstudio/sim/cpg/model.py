"""The simulator in the house shape: ``init(params) -> CpgState``, ``step(...)``, ``rollout(...)``.

Everything heavy runs in the numba kernels of :mod:`animstudio.sim.cpg.integrator`; this module
holds the value types and argument checking around them.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from animstudio.errors import SimulationError
from animstudio.sim.cpg import integrator as ig
from animstudio.sim.cpg.dynamics import N_AUX
from animstudio.sim.cpg.params import N_STATE, CpgParams, time_constants, weights

DT_S = 5e-4
"""Default RK4 step: converged (halving it changes period and speed < 0.1 %) and ~20 % below
the explicit-stability limit set by the ground spring/damper (docs/cpg-model.md §3)."""
FALL_HEIGHT_M = 0.6
"""Product fall detector: hip below 0.6 m (walking, also recovering from pushes, keeps it above
0.84 m; a stumbling walker that crouches lower does not get up again) ..."""
KNEE_FLOOR_M = 0.1
"""... or a knee below 0.1 m (kneeling: the hip can stay high while the walker is down)."""


@dataclass(frozen=True, eq=False)
class CpgState:
    """Walker state at time ``t_s``: ``y (40,)`` continuous, ``disc (4,)`` contact bookkeeping."""

    t_s: float
    y: NDArray[np.float64]
    disc: NDArray[np.float64]

    def __post_init__(self) -> None:
        if self.y.shape != (N_STATE,) or self.disc.shape != (4,):
            raise ValueError(f"state shapes must be ({N_STATE},) and (4,)")

    def copy_arrays(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        return self.y.astype(np.float64, copy=True), self.disc.astype(np.float64, copy=True)

    @property
    def hip_height_m(self) -> float:
        return float(self.y[1])


@dataclass(frozen=True)
class Drive:
    """Inputs held over one :func:`step`: hip push (N, +x forward), φc per leg (rad)."""

    push_n: float = 0.0
    phi_c_left_rad: float = 0.0
    phi_c_right_rad: float = 0.0
    posture: bool = True


@dataclass(frozen=True)
class Push:
    """A horizontal force ``force_n`` (+x forward) on the hip during ``[t_s, t_s + duration_s)``."""

    t_s: float
    force_n: float
    duration_s: float = 0.1


@dataclass(frozen=True)
class Model:
    """Parameters plus the packed arrays the kernels read (build once, reuse)."""

    params: CpgParams
    packed: NDArray[np.float64]
    tau: NDArray[np.float64]
    rate: NDArray[np.float64]
    w: NDArray[np.float64]

    @staticmethod
    def build(params: CpgParams | None = None) -> Model:
        prm = params or CpgParams()
        tau, rate = time_constants()
        return Model(prm, prm.packed(), tau, rate, weights())


def init(params: CpgParams | None = None) -> CpgState:
    """Appendix B initial condition: standing straight (x2 = l1 + l2), all at rest, u1 = u1_init.

    The seed's initial condition is exactly left/right symmetric (both legs would do the same
    and the walker sinks); a small potential on the left hip flexor starts with a left swing.
    """
    prm = params or CpgParams()
    y = np.zeros(N_STATE)
    y[1] = prm.l1 + prm.l2
    y[12] = prm.u1_init
    return CpgState(0.0, y, np.zeros(4))


def step(model: Model, state: CpgState, dt: float, drive: Drive) -> CpgState:
    """One RK4 step plus contact bookkeeping (slow: for tests and debugging; use rollout)."""
    y, disc = state.copy_arrays()
    aux = np.zeros(N_AUX)
    work = np.empty(ig.N_STEP_WORK)
    ig.rk4_step(
        model.packed, model.tau, model.rate, model.w, y, disc, dt, drive.push_n,
        drive.phi_c_left_rad, drive.phi_c_right_rad, 1.0 if drive.posture else 0.0, aux, work,
    )  # fmt: skip
    ig.update_contacts(model.packed, y, disc)
    return CpgState(state.t_s + dt, y, disc)


@dataclass(frozen=True, eq=False)
class Rollout:
    """A simulated stretch of time.

    Attributes:
        records: ``(N, integrator.N_CHANNELS)`` rows on the global record grid (column layout in
            :mod:`animstudio.sim.cpg.integrator`, ``C_*``).
        bsp_t_s, bsp_leg: beginning-of-stance times and legs (1 left, 2 right).
        bsp_y: ``(nB, 40)`` state right after each BSP.
        fall_t_s: time the hip dropped below the fall height, or ``None``.
        final: the state at the end.
    """

    records: NDArray[np.float64]
    bsp_t_s: NDArray[np.float64]
    bsp_leg: NDArray[np.int64]
    bsp_y: NDArray[np.float64]
    fall_t_s: float | None
    final: CpgState

    def column(self, index: int) -> NDArray[np.float64]:
        return self.records[:, index]

    @property
    def t_s(self) -> NDArray[np.float64]:
        return self.records[:, ig.C_T]


def _pushes_arrays(pushes: Sequence[Push]) -> tuple[NDArray[np.float64], ...]:
    t0 = np.array([p.t_s for p in pushes], dtype=np.float64)
    t1 = np.array([p.t_s + p.duration_s for p in pushes], dtype=np.float64)
    f = np.array([p.force_n for p in pushes], dtype=np.float64)
    return t0, t1, f


def rollout(
    model: Model,
    state: CpgState,
    duration_s: float,
    *,
    dt: float = DT_S,
    record_every: int = 20,
    pushes: Sequence[Push] = (),
    phi_c: tuple[Sequence[float], Sequence[float], Sequence[float]] = ((), (), ()),
    posture: bool = True,
    fall_height_m: float = FALL_HEIGHT_M,
    knee_floor_m: float = KNEE_FLOOR_M,
    after_fall_s: float = 0.0,
    stop_at_bsp: int = 0,
    phi_c_until_bsp: bool = False,
) -> Rollout:
    """Integrate from ``state`` for ``duration_s`` (or until the ``stop_at_bsp``-th BSP).

    Args:
        record_every: record the state every this many steps of the global step grid
            (``round(t / dt)``), so chained rollouts share one grid.
        phi_c: ``(times_s, left_rad, right_rad)``: piecewise-constant φc per leg (0 before).
        posture: ``False`` removes T_BSP entirely (the posture controller is off).
        fall_height_m, knee_floor_m: the fall detector (hip or a knee below these heights).
        after_fall_s: keep simulating this long after a fall (the animation shows the fall).
        phi_c_until_bsp: φc applies only up to the first BSP of this rollout, then 0.

    Raises:
        SimulationError: the state became non-finite (a step too large for the stiffness).
    """
    if not (dt > 0 and duration_s >= 0 and record_every >= 1):
        raise SimulationError(
            f"bad rollout settings: dt={dt}, duration={duration_s}, every={record_every}"
        )
    n = round(duration_s / dt)
    k0 = round(state.t_s / dt)
    first = (-k0) % record_every
    n_rec = 0 if n <= first else (n - 1 - first) // record_every + 1
    rec = np.zeros((n_rec, ig.N_CHANNELS))
    n_bsp_max = int(duration_s / 0.2) + 4
    bsp_t = np.zeros(n_bsp_max)
    bsp_leg = np.zeros(n_bsp_max, dtype=np.int64)
    bsp_y = np.zeros((n_bsp_max, N_STATE))
    out = np.zeros(6)
    y, disc = state.copy_arrays()
    pt0, pt1, pf = _pushes_arrays(pushes)
    times = np.asarray(phi_c[0], dtype=np.float64)
    left = np.asarray(phi_c[1], dtype=np.float64)
    right = np.asarray(phi_c[2], dtype=np.float64)
    if not (times.shape == left.shape == right.shape) or np.any(np.diff(times) < 0):
        raise SimulationError("phi_c schedule: times, left and right must match and times ascend")
    ig.run(
        model.packed, model.tau, model.rate, model.w, y, disc, state.t_s, dt, n, record_every,
        pt0, pt1, pf, times, left, right, 1.0 if posture else 0.0, fall_height_m, knee_floor_m, after_fall_s,
        ig.STOP_AT_BSP if stop_at_bsp > 0 else ig.STOP_NONE, stop_at_bsp,
        1 if phi_c_until_bsp else 0, k0, rec, bsp_t, bsp_leg, bsp_y, out,
    )  # fmt: skip
    if out[4] > 0.5:
        raise SimulationError(
            f"the simulation became non-finite at t = {out[5]:.3f} s (step {dt:g} s too large?)"
        )
    nb = int(out[2])
    fall = float(out[3]) if out[3] >= 0.0 else None
    return Rollout(
        records=rec[: int(out[1])],
        bsp_t_s=bsp_t[:nb].copy(),
        bsp_leg=bsp_leg[:nb].copy(),
        bsp_y=bsp_y[:nb].copy(),
        fall_t_s=fall,
        final=CpgState(float(out[5]), y, disc),
    )
