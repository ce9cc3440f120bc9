"""The ``obb`` engine: a hexapod walked by the OBB/SMER network of seed 002.

Gaits: ``wave``, ``tetrapod``, ``tripod`` (:data:`animstudio.sim.hexapod.GAITS`) and the expert form
``obb r=1,k`` (the paper's flexor/extensor reversibilities; it keeps the running gait class and
changes the swing reversibility, eq. (3)-(4)). One network step lasts :data:`STEP_S`; a leg
swings for exactly one step (the swing node operates once), so swing time is the same in every
gait and the stance time is what changes, as in insects.

Feet: a stance foot stays at a fixed world point; a swing foot lifts on a half-sine arc and lands
where it will be centred under its hip over the coming stance (the network's next lift-off is
known). The body moves along +X at ``STRIDE_M / stance time`` of the current gait, its speed
ramped linearly over :data:`SPEED_RAMP_S` at gait changes; joint angles come from the rig's leg IK, so stance feet do
not slide.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from animstudio.core.channels import GaitChannels
from animstudio.core.clip import ClipSegment
from animstudio.engines import EngineOptions
from animstudio.errors import ScriptError
from animstudio.rig import hexapod as rig
from animstudio.script.model import Script, Segment
from animstudio.script.parser import check_gaits
from animstudio.sim.hexapod import GAITS, LEGS, MAX_K, Gait, NetworkRun, obb_gait, simulate

STEP_S = 0.2
"""Duration of one network step = the swing duration (s)."""
STRIDE_M = 0.08
"""Body travel during one nominal stance (m)."""
FOOT_LIFT_M = 0.035
"""Peak foot height in swing (m)."""
SPEED_RAMP_S = 0.4
"""Time over which the body speed moves to a new gait's speed (s)."""
GAIT_NAMES: tuple[str, ...] = ("wave", "tetrapod", "tripod", "obb")


def parse_r(text: str) -> int:
    """The ``k`` of ``r=1,k``; raises ``ValueError`` with a user-facing message."""
    parts = text.split(",")
    if len(parts) != 2 or not all(p.strip().isdigit() for p in parts):
        raise ValueError(
            f"r={text!r}: expected two integers 'r=1,k' (flexor, extensor reversibility)"
        )
    flexor, k = (int(p) for p in parts)
    if flexor != 1:
        raise ValueError(
            f"r={text}: the flexor (stance) reversibility is always 1 in the seed's network"
        )
    if not 1 <= k <= MAX_K:
        raise ValueError(f"r={text}: the extensor reversibility must be between 1 and {MAX_K}")
    return k


def _segment_errors(seg: Segment) -> list[ScriptError]:
    errors = []
    for key, span in seg.param_spans.items():
        if seg.gait != "obb":
            errors.append(
                ScriptError(span, f"gait {seg.gait} takes no parameters (only 'obb r=1,k' does)")
            )
        elif key != "r":
            errors.append(
                ScriptError(
                    span, f"unknown parameter '{key}' for gait obb (valid: 'r', as in 'obb r=1,5')"
                )
            )
    if seg.gait == "obb":
        if "r" not in seg.params:
            errors.append(
                ScriptError(seg.span, "gait obb needs its reversibilities, e.g. 'obb r=1,5 90'")
            )
        else:
            try:
                parse_r(seg.params["r"])
            except ValueError as exc:
                errors.append(ScriptError(seg.param_spans.get("r", seg.span), str(exc)))
    return errors


@dataclass(frozen=True)
class _ObbEngine:
    name: str = "obb"
    characters: tuple[str, ...] = ("hexapod",)

    def gaits(self, options: EngineOptions) -> tuple[str, ...]:
        return GAIT_NAMES

    def validate(self, script: Script, options: EngineOptions) -> list[ScriptError]:
        errors = check_gaits(script, GAIT_NAMES, engine_label="obb")
        if script.character not in self.characters:
            span = script.setting_span("character") or script.setting_span("engine")
            if span is not None:
                errors.append(
                    ScriptError(span, f"engine obb animates the hexapod, not a {script.character}")
                )
        for seg in script.segments:
            if seg.gait in GAIT_NAMES:
                errors.extend(_segment_errors(seg))
        for setting, engine in (("blend", "som"), ("reinit", "cpg")):
            span = script.setting_span(setting)
            if span is not None:
                errors.append(
                    ScriptError(
                        span, f"setting '{setting}' is for engine {engine}; obb does not use it"
                    )
                )
        for ev in script.events:
            errors.append(
                ScriptError(
                    ev.span, "push events need engine cpg (the obb hexapod has no body dynamics)"
                )
            )
        return sorted(errors, key=lambda e: (e.span.line, e.span.column))

    def generate(self, script: Script, options: EngineOptions) -> GaitChannels:
        return generate(script)


ENGINE = _ObbEngine()


def gait_schedule(script: Script) -> list[tuple[int, Gait, Segment]]:
    """``(request step, gait, segment)`` per segment: a gait takes over at its first step boundary."""
    step_frames = script.fps * STEP_S
    out: list[tuple[int, Gait, Segment]] = []
    current: Gait | None = None
    for seg in script.segments:
        gait = (
            obb_gait(parse_r(seg.params["r"]), like=current)
            if seg.gait == "obb"
            else GAITS[seg.gait]
        )
        out.append((math.ceil(seg.start_frame / step_frames - 1e-9), gait, seg))
        current = gait
    return out


def speed_knots(plan: list[tuple[float, float]]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Knots ``(times s, speeds m/s)`` of the piecewise-linear body speed for ``[(start s, speed)]``.

    From each start the speed moves linearly, over :data:`SPEED_RAMP_S`, from the speed it has
    at that moment to the new one (a segment shorter than the ramp hands over mid-ramp, so the
    speed never jumps). Before the first knot the first speed holds, after the last the last.
    """
    t: list[float] = [plan[0][0]]
    v: list[float] = [plan[0][1]]
    for start, speed in plan[1:]:
        now = float(np.interp(start, t, v))
        keep = [i for i, ti in enumerate(t) if ti < start]
        t = [t[i] for i in keep] + [start, start + SPEED_RAMP_S]
        v = [v[i] for i in keep] + [now, speed]
    return np.array(t), np.array(v)


def _integrate(
    t: NDArray[np.float64], kt: NDArray[np.float64], kv: NDArray[np.float64]
) -> NDArray[np.float64]:
    """Integral of the piecewise-linear speed (knots ``kt``, ``kv``) from ``kt[0]`` to ``t``."""
    # Position at each knot: trapezoids are exact for a piecewise-linear speed.
    kx = np.concatenate([[0.0], np.cumsum(0.5 * (kv[1:] + kv[:-1]) * np.diff(kt))])
    k = np.clip(np.searchsorted(kt, t, side="right") - 1, 0, len(kt) - 1)
    dt = t - kt[k]
    nxt = np.minimum(k + 1, len(kt) - 1)
    ramping = (k < len(kt) - 1) & (dt >= 0)  # before the first knot and after the last: constant
    slope = np.where(ramping, (kv[nxt] - kv[k]) / np.maximum(kt[nxt] - kt[k], 1e-12), 0.0)
    return kx[k] + kv[k] * dt + 0.5 * slope * dt**2


def body_x(times_s: NDArray[np.float64], plan: list[tuple[float, float]]) -> NDArray[np.float64]:
    """Body position along +X (m, 0 at time 0) at ``times_s``: the exact integral of the speed."""
    kt, kv = speed_knots(plan)
    t = np.asarray(times_s, dtype=np.float64)
    return _integrate(t, kt, kv) - _integrate(np.zeros(1), kt, kv)[0]


def step_of(times_s: NDArray[np.float64], num_steps: int) -> NDArray[np.int64]:
    """Network step playing at each time (a frame on a step boundary belongs to the new step)."""
    # The epsilon keeps 234 / 30 s = 39 x 0.2 s in step 39 despite 39 * 0.2 = 7.800000000000001.
    return np.minimum(np.floor(times_s / STEP_S + 1e-9).astype(np.int64), num_steps - 1)


def foot_paths(
    run: NetworkRun,
    times_s: NDArray[np.float64],
    plan: list[tuple[float, float]],
    periods: NDArray[np.int64],
) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
    """World foot positions ``(F, 6, 3)`` and contacts ``(F, 6)`` at ``times_s``.

    ``periods`` is ``(S,)`` the steady cycle length (steps) of the gait running at each step; it
    sets where a foot stands before its first lift-off.
    """
    n_frames = len(times_s)
    step = step_of(times_s, run.num_steps)
    u = np.clip(times_s / STEP_S - step, 0.0, 1.0)  # progress through the step
    feet = np.zeros((n_frames, len(LEGS), 3))
    contact = ~run.swing[step]
    for n, leg in enumerate(LEGS):
        nx = rig.NEUTRAL_FOOT_X_M[leg[1]]
        lifts = np.flatnonzero(run.swing[:, n])
        stance_s = (periods[lifts[0]] - 1) * STEP_S
        t0 = lifts[0] * STEP_S
        # Where each stance stands: centred between the hip at touchdown and at the next lift-off.
        td_times = np.concatenate([[t0 - stance_s], (lifts[:-1] + 1) * STEP_S]).astype(np.float64)
        lift_times = (lifts * STEP_S).astype(np.float64)
        stand_x = nx + 0.5 * (body_x(td_times, plan) + body_x(lift_times, plan))
        # Stance k lasts from touchdown k to lift-off k; frames after the last lift-off cannot be
        # placed, so the network is always run past the clip's end.
        idx = np.searchsorted(lifts, step, side="right")  # lift-offs at or before this step
        assert np.all(idx < len(lifts)), "network run too short for the clip"
        x = stand_x[idx]
        y = np.zeros(n_frames)
        swinging = run.swing[step, n]
        k = idx[swinging] - 1  # the stance being left is stand_x[k], the next is stand_x[k + 1]
        blend = 0.5 * (1.0 - np.cos(np.pi * u[swinging]))
        x[swinging] = stand_x[k] + (stand_x[k + 1] - stand_x[k]) * blend
        y[swinging] = FOOT_LIFT_M * np.sin(np.pi * u[swinging])
        feet[:, n] = np.stack(
            [x, y, np.full(n_frames, rig.side_sign(leg) * rig.NEUTRAL_FOOT_Z_M)], axis=-1
        )
    return feet, contact


def generate(script: Script) -> GaitChannels:
    """Run the network over ``script`` and pose the legs (see the module docstring)."""
    schedule = gait_schedule(script)
    fps = float(script.fps)
    n_frames = script.total_frames
    times = np.arange(n_frames) / fps
    longest = max(g.period for _, g, _ in schedule)
    steps = (
        math.ceil(n_frames / (fps * STEP_S)) + 3 * longest + 2
    )  # look ahead for the last stances
    run = simulate([(s if i else 0, g) for i, (s, g, _) in enumerate(schedule)], steps)
    starts = np.array([s if i else 0 for i, (s, _, _) in enumerate(schedule)])
    seg_of_step = np.searchsorted(starts, np.arange(steps), side="right") - 1
    periods = np.array([schedule[i][1].period for i in seg_of_step])
    plan = [(s * STEP_S, STRIDE_M / ((g.period - 1) * STEP_S)) for s, g, _ in schedule]
    plan[0] = (0.0, plan[0][1])
    root = np.stack(
        [body_x(times, plan), np.full(n_frames, rig.BODY_HEIGHT_M), np.zeros(n_frames)], axis=-1
    )
    feet, contact = foot_paths(run, times, plan, periods)
    angles: dict[str, NDArray[np.float64]] = {}
    signals: dict[str, NDArray[np.float64]] = {}
    frame_step = step_of(times, steps)
    for n, leg in enumerate(LEGS):
        q = np.degrees(rig.leg_ik(leg, feet[:, n] - root))
        for c, joint in enumerate(("coxa", "femur", "tibia")):
            angles[f"{leg}_{joint}_deg"] = q[:, c]
        signals[f"{leg}_swing_neuron"] = run.swing[frame_step, n].astype(np.float64)
        signals[f"{leg}_stance_neuron"] = run.stance[frame_step, n].astype(np.float64)
        signals[f"{leg}_extensor_r"] = run.k[frame_step, n].astype(np.float64)
    signals["network_step"] = frame_step.astype(np.float64)
    notes = tuple(
        f"gait class change at {s * STEP_S:.2f} s: the OBB ring was re-oriented (re-initialised) "
        "for the new gait"
        for s in run.reinit_steps
        if s * STEP_S < n_frames / fps
    )
    return GaitChannels(
        fps=fps,
        character="hexapod",
        angles=angles,
        root_position_m=root,
        contacts={leg: contact[:, n] for n, leg in enumerate(LEGS)},
        segments=tuple(
            ClipSegment(seg.gait, seg.start_frame, seg.end_frame) for _, _, seg in schedule
        ),
        signals=signals,
        notes=notes,
    )
