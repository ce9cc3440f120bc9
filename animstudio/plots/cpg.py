"""Figures of the ``cpg`` engine, after seed 001's Figures 4-6.

* ``stick``: stick figure of the walk (Fig. 4), the hip's x at each push dotted;
* ``neurons``: posture-controller activity f(u_p)·g(y) and knee angles per leg, φc and the
  pushes over time (Fig. 5);
* ``torque``: left knee active torque per body weight (Nm/N) with push times dotted (Fig. 6).

``plot(script, kind, out_path, options=...)`` is what ``animstudio plot`` calls;
``python -m animstudio.plots.cpg DIR`` renders the paper's successive-push experiment into DIR.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from matplotlib.figure import Figure
from numpy.typing import NDArray

from animstudio.engines import EngineOptions
from animstudio.engines.cpg import simulate
from animstudio.errors import lookup
from animstudio.export.atomic import write_with
from animstudio.script.model import Script
from animstudio.sim.cpg import integrator as ig
from animstudio.sim.cpg.params import CpgParams
from animstudio.sim.cpg.reinit import Walk

KINDS: tuple[str, ...] = ("stick", "neurons", "torque")
STICK_EVERY_S = 0.04
"""Time between two drawn postures of the stick figure."""
STICK_WINDOW_S = 8.0
"""Stretch of a push-free walk the stick figure shows."""


def _save(fig: Figure, out_path: Path) -> None:
    write_with(Path(out_path), lambda tmp: fig.savefig(tmp, dpi=110, format="png"))


def _push_list(records: NDArray[np.float64]) -> list[tuple[float, float, float]]:
    """``(start time s, force N, hip x m)`` of every push, read from the recorded force."""
    force = records[:, ig.C_PUSH]
    on = np.flatnonzero((force != 0.0) & (np.concatenate([[0.0], force[:-1]]) == 0.0))
    return [(records[i, ig.C_T], force[i], records[i, ig.C_X]) for i in on]


def stick_figure(walk: Walk, params: CpgParams, title: str) -> Figure:
    """Fig. 4: both legs drawn every :data:`STICK_EVERY_S`, pushes as dotted hip positions.

    Long walks show the stretch around the pushes (from 2 s before the first to 4 s after the
    last) or, without pushes, the first :data:`STICK_WINDOW_S`, so the figure stays legible.
    """
    rec = walk.rollout.records
    pushes = _push_list(rec)
    t = rec[:, ig.C_T]
    if pushes:
        t0, t1 = pushes[0][0] - 2.0, pushes[-1][0] + 4.0
    else:
        t0, t1 = t[0], t[0] + STICK_WINDOW_S
    if walk.fall_t_s is not None:
        t1 = max(t1, walk.fall_t_s + 2.0)
    rec = rec[(t >= t0) & (t <= t1)]
    step = max(1, round(STICK_EVERY_S / (rec[1, ig.C_T] - rec[0, ig.C_T])))
    span = float(np.ptp(rec[:, ig.C_X])) + 1.0
    width = min(16.0, max(6.0, 1.6 * span))
    height = max(2.5, width * 1.2 / span + 1.3)  # equal aspect: 1.2 m of height over the span
    fig = Figure(figsize=(width, height), layout="constrained")
    ax = fig.subplots()
    for row in rec[::step]:
        x1, x2, x3, x4, x5, x6 = row[ig.C_X : ig.C_X + 6]
        for th, sh, l_th, l_sh, colour in (
            (x3, x4, params.l1, params.l2, "tab:blue"),
            (x5, x6, params.l3, params.l4, "tab:orange"),
        ):
            knee = (x1 + l_th * np.sin(th), x2 - l_th * np.cos(th))
            ankle = (knee[0] + l_sh * np.sin(sh), knee[1] - l_sh * np.cos(sh))
            ax.plot([x1, knee[0], ankle[0]], [x2, knee[1], ankle[1]], color=colour, lw=0.6)
    for i, (tp, f, x) in enumerate(pushes):
        ax.axvline(x, color="k", ls=":", lw=1.2)
        y = 0.93 + 0.08 * (i % 2)  # staggered: pushes a step apart would overlap
        ax.text(x, y, f"{abs(f):.0f} N at {tp:.2f} s", ha="center", va="bottom", fontsize=7)
    if walk.fall_t_s is not None:
        ax.set_title(f"{title} — fell at {walk.fall_t_s:.2f} s", color="tab:red")
    else:
        ax.set_title(title)
    ax.axhline(0.0, color="0.4", lw=0.8)
    ax.set_aspect("equal")
    ax.set_xlabel(
        f"x (m), {rec[0, ig.C_T]:.1f}-{rec[-1, ig.C_T]:.1f} s   blue: left leg, orange: right leg"
    )
    ax.set_ylabel("height (m)")
    ax.set_ylim(-0.1, 1.12)
    return fig


def neurons_figure(walk: Walk, title: str) -> Figure:
    """Fig. 5: posture-neuron activity while swinging, knee angles, φc and pushes per leg."""
    rec = walk.rollout.records
    t = rec[:, ig.C_T]
    fig = Figure(figsize=(10, 8), layout="constrained")
    axes = fig.subplots(6, 1, sharex=True)
    for k, (side, p, yc, th, sh, phi) in enumerate(
        (
            ("left", 12, ig.C_YL, 2, 3, ig.C_PHIC_L),
            ("right", 13, ig.C_YR, 4, 5, ig.C_PHIC_R),
        )
    ):
        activity = np.maximum(rec[:, ig.C_U + p], 0.0) * (rec[:, yc] > 0.0)
        axes[2 * k].plot(t, activity, color="tab:purple", lw=1)
        axes[2 * k].set_ylabel(f"f(u_p{k + 1})·g(y)\n{side}", fontsize=8)
        knee = (rec[:, ig.C_X + th] - rec[:, ig.C_X + sh]) / np.pi
        axes[2 * k + 1].plot(t, knee, color="k", lw=1)
        axes[2 * k + 1].plot(t, rec[:, phi] / np.pi, color="tab:red", lw=1, ls="--")
        axes[2 * k + 1].set_ylabel(f"{side} knee\n(π rad)", fontsize=8)
    axes[4].step(t, np.maximum(rec[:, ig.C_PHIC_L], rec[:, ig.C_PHIC_R]) / np.pi, where="post")
    axes[4].set_ylabel("φc (π rad)", fontsize=8)
    axes[5].plot(t, -rec[:, ig.C_PUSH], color="tab:green", lw=1)
    axes[5].set_ylabel("backward\npush (N)", fontsize=8)
    axes[5].set_xlabel("time (s)   dashed: φc commanded")
    fig.suptitle(title)
    return fig


def torque_figure(walk: Walk, params: CpgParams, title: str) -> Figure:
    """Fig. 6: left knee active torque (CPG + T_BSP) per body weight, pushes dotted."""
    rec = walk.rollout.records
    t = rec[:, ig.C_T]
    torque = (rec[:, ig.C_AUX + 1] + rec[:, ig.C_AUX + 6]) / params.body_weight_n
    fig = Figure(figsize=(10, 3.2), layout="constrained")
    ax = fig.subplots()
    ax.plot(t, torque, color="k", lw=0.8)
    for tp, _, _ in _push_list(rec):
        ax.axvline(tp, color="tab:red", ls=":", lw=1.2)
    ax.axhline(0.1, color="0.6", lw=0.6, ls="--")
    ax.axhline(-0.1, color="0.6", lw=0.6, ls="--")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("left knee torque\n(Nm / N body weight)")
    ax.set_title(title)
    return fig


def _figure(walk: Walk, kind: str, params: CpgParams, title: str) -> Figure:
    if kind == "stick":
        return stick_figure(walk, params, title)
    if kind == "neurons":
        return neurons_figure(walk, title)
    return torque_figure(walk, params, title)


def plot(script: Script, kind: str, out_path: Path, *, options: EngineOptions) -> None:
    """Draw figure ``kind`` (one of :data:`KINDS`) of ``script`` into the PNG ``out_path``."""
    lookup("plot kind for engine cpg", kind, KINDS)
    params = CpgParams()
    walk, _ = simulate(script, params)
    title = f"{Path(script.path).name}: reinit {script.reinit}"
    _save(_figure(walk, kind, params, title), out_path)


def render_paper_figures(out_dir: Path) -> list[Path]:
    """The successive-push experiment (docs/cpg-model.md §4) as cpg_{stick,neurons,torque}.png."""
    from animstudio.sim.cpg.experiments import SERIES_500, successive_pushes

    params = CpgParams()
    result = successive_pushes(params, SERIES_500, duration_s=10.0)
    paths = []
    for kind in KINDS:
        path = Path(out_dir) / f"cpg_{kind}.png"
        pushes = ", ".join(f"{abs(p.force_n):.0f} N" for p in result.pushes)
        title = f"successive backward pushes ({pushes}), reinit auto"
        _save(_figure(result.with_reinit, kind, params, title), path)
        paths.append(path)
    path = Path(out_dir) / "cpg_stick_off.png"
    _save(stick_figure(result.without_reinit, params, "same pushes, reinit off (φc = 0)"), path)
    paths.append(path)
    return paths


if __name__ == "__main__":  # pragma: no cover - developer entry point for docs/figures
    for p in render_paper_figures(Path(sys.argv[1] if len(sys.argv) > 1 else "docs/figures")):
        print(p)
