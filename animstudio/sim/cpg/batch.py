"""Many walkers at once: the same model from per-walker states, pushes and φc schedules.

Used by ``reinit auto`` (candidate φc values simulated ahead) and by push sweeps (bisection of
the largest survivable push over gait phases). Walkers run in parallel numba threads.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from animstudio.errors import SimulationError
from animstudio.sim.cpg import integrator as ig
from animstudio.sim.cpg.model import DT_S, FALL_HEIGHT_M, KNEE_FLOOR_M, CpgState, Model, Push
from animstudio.sim.cpg.params import N_STATE


@dataclass(frozen=True, eq=False)
class BatchResult:
    """Per walker: BSPs ``(B, nB)`` (leg 0 = unused slot), their states, fall time (NaN: none)."""

    bsp_t_s: NDArray[np.float64]
    bsp_leg: NDArray[np.int64]
    bsp_y: NDArray[np.float64]
    fall_t_s: NDArray[np.float64]
    final_y: NDArray[np.float64]
    final_disc: NDArray[np.float64]
    end_t_s: NDArray[np.float64]

    def final_state(self, i: int) -> CpgState:
        """Walker ``i``'s state at its end."""
        return CpgState(float(self.end_t_s[i]), self.final_y[i].copy(), self.final_disc[i].copy())

    @property
    def fell(self) -> NDArray[np.bool_]:
        return ~np.isnan(self.fall_t_s)


def _pad(rows: Sequence[Sequence[float]], width: int) -> NDArray[np.float64]:
    out = np.full((len(rows), width), np.inf)  # t0 = inf: a padding push never acts
    for i, r in enumerate(rows):
        out[i, : len(r)] = r
    return out


def run_walkers(
    model: Model,
    starts: Sequence[CpgState],
    duration_s: float,
    *,
    pushes: Sequence[Sequence[Push]] | None = None,
    phi_c: Sequence[float] | NDArray[np.float64] | None = None,
    phi_c_until_bsp: bool = False,
    posture: bool = True,
    dt: float = DT_S,
    fall_height_m: float = FALL_HEIGHT_M,
    knee_floor_m: float = KNEE_FLOOR_M,
    stop_at_bsp: int = 0,
) -> BatchResult:
    """Simulate ``len(starts)`` walkers for ``duration_s`` each, each from its own start time.

    Args:
        pushes: per walker, its pushes (``None``: none).
        phi_c: per walker, one φc for both legs from its start (``None``: 0).
        phi_c_until_bsp: that φc acts only until the walker's first BSP, then 0.
        stop_at_bsp: stop each walker at its n-th BSP (0: run the full duration).
    """
    nb = len(starts)
    if nb == 0:
        raise SimulationError("run_walkers needs at least one walker")
    t_starts = np.array([s.t_s for s in starts], dtype=np.float64)
    ys = np.stack([s.y for s in starts]).astype(np.float64)
    discs = np.stack([s.disc for s in starts]).astype(np.float64)
    pl = [list(p) for p in pushes] if pushes is not None else [[] for _ in range(nb)]
    if len(pl) != nb:
        raise SimulationError("pushes must have one entry per walker")
    k = max(1, max(len(p) for p in pl))
    pt0 = _pad([[q.t_s for q in p] for p in pl], k)
    pt1 = _pad([[q.t_s + q.duration_s for q in p] for p in pl], k)
    pf = np.nan_to_num(_pad([[q.force_n for q in p] for p in pl], k), posinf=0.0)
    values = np.zeros(nb) if phi_c is None else np.asarray(phi_c, dtype=np.float64)
    if values.shape != (nb,):
        raise SimulationError("phi_c must have one value per walker")
    times = t_starts[:, None] - 1.0
    n_steps = round(duration_s / dt)
    n_bsp = int(duration_s / 0.2) + 4
    bsp_t = np.zeros((nb, n_bsp))
    bsp_leg = np.zeros((nb, n_bsp), dtype=np.int64)
    bsp_y = np.zeros((nb, n_bsp, N_STATE))
    outs = np.zeros((nb, 6))
    ig.run_batch(
        model.packed, model.tau, model.rate, model.w, ys, discs, t_starts, dt, n_steps,
        pt0, pt1, pf, times, values[:, None].copy(), values[:, None].copy(),
        1.0 if posture else 0.0, fall_height_m, knee_floor_m,
        ig.STOP_AT_BSP if stop_at_bsp > 0 else ig.STOP_NONE, stop_at_bsp,
        1 if phi_c_until_bsp else 0, bsp_t, bsp_leg, bsp_y, outs,
    )  # fmt: skip
    counts = outs[:, 2].astype(np.int64)
    for i in range(nb):
        bsp_leg[i, counts[i] :] = 0
    fall = np.where(outs[:, 3] >= 0.0, outs[:, 3], np.nan)
    fall = np.where(outs[:, 4] > 0.5, outs[:, 5], fall)  # a blow-up counts as a fall
    return BatchResult(bsp_t, bsp_leg, bsp_y, fall, ys, discs, outs[:, 5].copy())
