"""Figures of the ``obb`` engine: neuron waveforms (seed 002 Figures 3-4) and footfall diagrams.

``plot(script, kind, out_path, options=...)`` is what ``animstudio plot`` calls. The seed's own
pair experiments (Table 1 and Table 2 at 3 s per step) are drawn by :func:`pair_figure`;
``python -m animstudio.plots.obb DIR`` renders them into ``DIR`` (docs/figures).
"""

from __future__ import annotations

import sys
from collections.abc import Sequence
from pathlib import Path

import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure

from animstudio.core.channels import GaitChannels
from animstudio.engines import EngineOptions
from animstudio.errors import lookup
from animstudio.export.atomic import write_with
from animstudio.script.model import Script
from animstudio.sim.hexapod import LEGS
from animstudio.sim.obb import PairRun, simulate_pair

KINDS: tuple[str, ...] = ("neurons", "footfall")
PAPER_STEP_S = 3.0
"""Seconds per step that reproduce Figure 3 (period 18 s, 15 s on; docs/obb-model.md)."""


def _save(fig: Figure, out_path: Path) -> None:
    write_with(Path(out_path), lambda tmp: fig.savefig(tmp, dpi=110, format="png"))


def _segments(ax: Axes, channels: GaitChannels, *, labels: bool) -> None:
    for seg in channels.segments:
        t0 = seg.start_frame / channels.fps
        if seg.start_frame > 0:
            ax.axvline(t0, color="tab:red", lw=1.0, ls="--")
        if labels:
            t1 = seg.end_frame / channels.fps
            ax.text(
                0.5 * (t0 + t1),
                1.02,
                seg.gait,
                transform=ax.get_xaxis_transform(),
                ha="center",
                va="bottom",
            )


def neurons_figure(channels: GaitChannels, title: str) -> Figure:
    """Stance and swing neuron outputs of every leg over time, segment boundaries dashed."""
    t = np.arange(channels.num_frames) / channels.fps
    fig = Figure(figsize=(11, 8), layout="constrained")
    ax_r, *axes = fig.subplots(len(LEGS) + 1, 1, sharex=True, height_ratios=[0.8] + [1] * len(LEGS))
    # Top: the swing reversibility each leg runs with (eq. (3): it changes leg by leg).
    for leg in LEGS:
        ax_r.step(t, channels.signals[f"{leg}_extensor_r"], where="post", lw=1, label=leg)
    ax_r.set_ylabel("r swing", rotation=0, ha="right", va="center")
    ax_r.legend(loc="upper right", ncols=6, fontsize=7)
    ax_r.set_ylim(0, 10.5)
    _segments(ax_r, channels, labels=True)
    for ax, leg in zip(axes, LEGS, strict=True):
        stance = channels.signals[f"{leg}_stance_neuron"]
        swing = channels.signals[f"{leg}_swing_neuron"]
        ax.fill_between(
            t, 1.2, 1.2 + stance, step="post", color="tab:blue", lw=0, label="stance (r = 1)"
        )
        ax.fill_between(t, 0.0, swing, step="post", color="tab:orange", lw=0, label="swing (r = k)")
        ax.set_yticks([0.5, 1.7], ["swing", "stance"])
        ax.set_ylabel(leg, rotation=0, ha="right", va="center", fontweight="bold")
        ax.set_ylim(-0.1, 2.3)
        _segments(ax, channels, labels=False)
    axes[-1].set_xlabel("time (s)")
    axes[0].legend(loc="upper left", ncols=2, fontsize=7)
    fig.suptitle(title)
    return fig


def footfall_figure(channels: GaitChannels, title: str) -> Figure:
    """Stance (dark bar) / swing (gap) per leg over time; hind-to-front rows per side."""
    t = np.arange(channels.num_frames + 1) / channels.fps
    fig = Figure(figsize=(11, 4.2), layout="constrained")
    ax = fig.subplots()
    order = ("R1", "R2", "R3", "L1", "L2", "L3")
    for row, leg in enumerate(order):
        c = np.asarray(channels.contacts[leg], dtype=bool)
        edges = np.flatnonzero(np.diff(np.concatenate([[False], c, [False]]).astype(np.int8)))
        spans = [(t[a], t[b] - t[a]) for a, b in zip(edges[::2], edges[1::2], strict=True)]
        ax.broken_barh(spans, (row - 0.35, 0.7), color="black")
    ax.set_yticks(range(len(order)), order)
    ax.set_ylim(-0.6, len(order) - 0.4)
    ax.set_xlim(0, t[-1])
    ax.set_xlabel("time (s)   (bars: foot on the ground; gaps: swing)")
    _segments(ax, channels, labels=True)
    fig.suptitle(title)
    return fig


def plot(script: Script, kind: str, out_path: Path, *, options: EngineOptions) -> None:
    """Draw figure ``kind`` (one of :data:`KINDS`) of ``script`` into the PNG ``out_path``."""
    from animstudio.engines.obb import ENGINE

    lookup("plot kind for engine obb", kind, KINDS)
    channels = ENGINE.generate(script, options)
    name = Path(script.path).name
    if kind == "neurons":
        fig = neurons_figure(channels, f"{name}: OBB neuron outputs per leg")
    else:
        fig = footfall_figure(channels, f"{name}: footfall (stance/swing) per leg")
    _save(fig, out_path)


def pair_figure(
    run: PairRun, *, step_s: float, title: str, switch_times_s: Sequence[float] = ()
) -> Figure:
    """The seed's Figures 3/4: potentials and outputs of one OBB pair over time."""
    t = np.arange(run.num_steps) * step_s
    fig = Figure(figsize=(10, 5.5), layout="constrained")
    ax_m, ax_f, ax_e = fig.subplots(3, 1, sharex=True, height_ratios=[2, 1, 1])
    ax_m.step(t, run.m[:, 0], where="post", label=f"M flexor (r = {run.r[0, 0]}…)")
    ax_m.step(t, run.m[:, 1], where="post", label=f"M extensor (r = {run.r[0, 1]}…)")
    ax_m.set_ylabel("membrane potential")
    ax_m.legend(loc="upper right", fontsize=8)
    for ax, col, name in ((ax_f, 0, "flexor v (r = 1)"), (ax_e, 1, "extensor v (r = k)")):
        ax.fill_between(
            t, 0, run.v[:, col], step="post", color="tab:blue" if col == 0 else "tab:orange"
        )
        ax.set_ylabel(name, rotation=0, ha="right", va="center")
        ax.set_yticks([0, 1])
    for ax in (ax_m, ax_f, ax_e):
        for s in switch_times_s:
            ax.axvline(s, color="tab:red", ls="--", lw=1)
    changes = np.flatnonzero(np.any(run.r[1:] != run.r[:-1], axis=1)) + 1
    for c in [0, *changes.tolist()]:
        ax_m.text(t[c], 1.12, f"r = {run.r[c, 0]},{run.r[c, 1]}", fontsize=8, va="bottom")
    ax_e.set_xlabel(f"time (s), {step_s:g} s per step")
    ax_e.set_xticks(np.arange(0, t[-1] + step_s, 6 * step_s if t[-1] < 150 else 60))
    fig.suptitle(title)
    return fig


def render_paper_figures(out_dir: Path) -> list[Path]:
    """Table 1 (Figure 3) and Table 2 (Figure 4) runs at 3 s per step, into ``out_dir``."""
    s = PAPER_STEP_S
    fig3 = pair_figure(
        simulate_pair(int(120 / s)),
        step_s=s,
        title="Table 1: r = 1,5, M0 = 0.35 / 0.65 — stable period 18 s, r = 1 neuron on 15 s",
    )
    switches = [(int(np.ceil(160 / s)), (1, 3)), (int(np.ceil(300 / s)), (1, 1))]
    fig4 = pair_figure(
        simulate_pair(int(400 / s), switches=switches),
        step_s=s,
        title="Table 2: r = 1,5 → 1,3 at 160 s → 1,1 at 300 s (requests dashed)",
        switch_times_s=(160.0, 300.0),
    )
    out = [Path(out_dir) / "obb_pair_table1.png", Path(out_dir) / "obb_pair_table2.png"]
    for fig, path in zip((fig3, fig4), out, strict=True):
        _save(fig, path)
    return out


if __name__ == "__main__":
    render_paper_figures(Path(sys.argv[1] if len(sys.argv) > 1 else "docs/figures"))
