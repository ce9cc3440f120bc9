"""The ``cpg`` engine: the neuro-mechanical biped of seed 001 walking the humanoid.

The script's ``walk`` segments run the walker (the model has one gait; see docs/cpg-model.md §6
for why there is no ``stand``/``stop``), ``push`` events push its hip, ``reinit`` chooses the
posture controller's policy (``auto``: φc chosen by look-ahead after pushes; ``off``: φc = 0).

The walker starts on its limit cycle (the settled gait from the seed's initial condition,
shifted to x = 0 and t = 0), so frame 0 already shows steady walking. The simulation is sampled
at the frame times; the seed body's hip height and travel are scaled from its 0.9 m leg to the
character's leg (THIGH_M + SHANK_M) and lifted by the ankle height so the soles meet the floor.
A fall ends the simulated motion: the animation shows it until the body reaches the floor (or
for :data:`AFTER_FALL_S`) and then holds the last pose; the channels carry a note and a
``fall`` event.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from animstudio.core.channels import GaitChannels
from animstudio.core.clip import ClipEvent, ClipSegment
from animstudio.engines import EngineOptions
from animstudio.errors import ScriptError
from animstudio.rig.proportions import ANKLE_HEIGHT_M, FOOT_REST_DEG, SHANK_M, THIGH_M
from animstudio.script.model import Script
from animstudio.script.parser import check_gaits
from animstudio.sim.cpg import integrator as ig
from animstudio.sim.cpg.analysis import start_on_cycle
from animstudio.sim.cpg.model import DT_S, Model, Push
from animstudio.sim.cpg.params import CpgParams
from animstudio.sim.cpg.reinit import Walk, simulate_walk

GAITS: tuple[str, ...] = ("walk",)
AFTER_FALL_S = 2.0
"""Longest time the fall itself is shown before the pose is held."""
HEEL_STRIKE_DEG = 12.0
"""Toe-up of the foot relative to the shank at heel strike (the foot flattens after landing)."""
TOE_OFF_DEG = -28.0
"""Foot pitch below rest at toe-off (heel up)."""
FOOT_FLAT_S = 0.08
"""Time from heel strike to foot flat."""


@dataclass(frozen=True)
class _CpgEngine:
    name: str = "cpg"
    characters: tuple[str, ...] = ("humanoid",)

    def gaits(self, options: EngineOptions) -> tuple[str, ...]:
        return GAITS

    def validate(self, script: Script, options: EngineOptions) -> list[ScriptError]:
        return validate(script)

    def generate(self, script: Script, options: EngineOptions) -> GaitChannels:
        return generate(script)


def validate(script: Script) -> list[ScriptError]:
    """Every located problem of ``script`` for the cpg engine."""
    errors = check_gaits(script, GAITS, engine_label="cpg")
    if script.character not in ("humanoid",):
        span = script.setting_span("character") or script.setting_span("engine")
        if span is not None:
            errors.append(
                ScriptError(span, f"engine cpg animates the humanoid, not a {script.character}")
            )
    for seg in script.segments:
        for key, span in seg.param_spans.items():
            errors.append(
                ScriptError(
                    span, f"gait {seg.gait} takes no parameters for engine cpg (got '{key}')"
                )
            )
    span = script.setting_span("blend")
    if span is not None:
        errors.append(ScriptError(span, "setting 'blend' is for engine som; cpg does not use it"))
    return sorted(errors, key=lambda e: (e.span.line, e.span.column))


def simulate(script: Script, params: CpgParams | None = None) -> tuple[Walk, float]:
    """Run the walker for the script. Returns the walk and the record interval (s)."""
    prm = params or CpgParams()
    model = Model.build(prm)
    duration = script.total_frames / script.fps
    # Record about four samples per frame on the integrator's grid; frames interpolate.
    every = max(1, int(1.0 / (4.0 * script.fps * DT_S)))
    pushes = [Push(ev.frame / script.fps, ev.signed_force_n, ev.duration_s) for ev in script.events]
    walk = simulate_walk(
        model, duration + every * DT_S, pushes, reinit=script.reinit, start=start_on_cycle(prm),
        record_every=every, after_fall_s=AFTER_FALL_S,
    )  # fmt: skip
    return walk, every * DT_S


def _sample(rec: NDArray[np.float64], times: NDArray[np.float64]) -> NDArray[np.float64]:
    """Rows of ``rec`` linearly interpolated at ``times`` (held beyond the last row)."""
    t = rec[:, ig.C_T]
    out = np.empty((times.shape[0], rec.shape[1]))
    for j in range(rec.shape[1]):
        out[:, j] = np.interp(times, t, rec[:, j])
    return out


def _hold_from(
    rows: NDArray[np.float64], params: CpgParams, fall_t: float, times: NDArray[np.float64]
) -> int:
    """First frame to hold after a fall: body on the floor (knee or hip low) or time is up."""
    knee_l = rows[:, ig.C_X + 1] - params.l1 * np.cos(rows[:, ig.C_X + 2])
    knee_r = rows[:, ig.C_X + 1] - params.l3 * np.cos(rows[:, ig.C_X + 4])
    down = (np.minimum(knee_l, knee_r) < 0.05) | (rows[:, ig.C_X + 1] < 0.3)
    late = times >= fall_t + AFTER_FALL_S
    idx = np.flatnonzero((down | late) & (times >= fall_t))
    return int(idx[0]) if idx.size else times.shape[0]


def foot_angles_deg(
    shank_deg: NDArray[np.float64], contact: NDArray[np.bool_], fps: float
) -> NDArray[np.float64]:
    """Foot pitch (deg from horizontal): flat in stance, heel strike -> flat, toe-off -> swing.

    In stance the foot lies at :data:`FOOT_REST_DEG` (flat), reached from the heel-strike pose
    over :data:`FOOT_FLAT_S`; the heel rises over the last fifth of stance towards
    :data:`TOE_OFF_DEG` below rest; in swing the foot follows the shank, its ankle going from
    toe-off plantarflexion to the heel-strike dorsiflexion (a smoothstep over the swing).
    """
    n = shank_deg.shape[0]
    out = np.full(n, FOOT_REST_DEG)
    frames = np.arange(n)
    change = np.flatnonzero(np.diff(contact.astype(np.int8)) != 0) + 1
    bounds = np.concatenate([[0], change, [n]])
    for a, b in itertools.pairwise(bounds):
        if a == b:
            continue
        if contact[a]:
            s = (frames[a:b] - a) / max(1, b - a)
            land = FOOT_REST_DEG + HEEL_STRIKE_DEG + shank_deg[a]
            blend = np.clip((frames[a:b] - a) / (FOOT_FLAT_S * fps), 0.0, 1.0) if a > 0 else 1.0
            flat = land + (FOOT_REST_DEG - land) * blend
            rise = np.clip((s - 0.8) / 0.2, 0.0, 1.0) if b < n else np.zeros(b - a)
            out[a:b] = flat + TOE_OFF_DEG * rise * rise
        else:
            s = (frames[a:b] - a) / max(1, b - a)
            smooth = s * s * (3.0 - 2.0 * s)
            ankle_rel = (TOE_OFF_DEG - shank_deg[a]) * (1.0 - smooth) + HEEL_STRIKE_DEG * smooth
            out[a:b] = FOOT_REST_DEG + shank_deg[a:b] + ankle_rel
    return out


def generate(script: Script, params: CpgParams | None = None) -> GaitChannels:
    """Simulate the script and sample it as humanoid channels at ``script.fps``."""
    prm = params or CpgParams()
    walk, _ = simulate(script, prm)
    n = script.total_frames
    times = np.arange(n) / script.fps
    rows = _sample(walk.rollout.records, times)
    notes: list[str] = []
    events = [
        ClipEvent("push", min(ev.frame, n - 1), ev.label) for ev in script.events if ev.frame < n
    ]
    scale = (THIGH_M + SHANK_M) / prm.leg_length_m
    if walk.fall_t_s is not None:
        fall_frame = min(n - 1, int(np.ceil(walk.fall_t_s * script.fps)))
        hold = _hold_from(rows, prm, walk.fall_t_s, times)
        if hold < n:
            rows[hold:] = rows[hold]
        height = rows[fall_frame, ig.C_X + 1] * scale + ANKLE_HEIGHT_M
        message = f"walker fell at {walk.fall_t_s:.2f} s (hip height {height:.2f} m)"
        notes.append(message)
        events.append(ClipEvent("fall", fall_frame, message))
    rad = np.degrees
    angles = {
        "left_thigh_deg": rad(rows[:, ig.C_X + 2]),
        "left_shank_deg": rad(rows[:, ig.C_X + 3]),
        "right_thigh_deg": rad(rows[:, ig.C_X + 4]),
        "right_shank_deg": rad(rows[:, ig.C_X + 5]),
    }
    contacts = {
        "left_foot": rows[:, ig.C_CONTACT_L] > 0.5,
        "right_foot": rows[:, ig.C_CONTACT_R] > 0.5,
    }
    angles["left_foot_deg"] = foot_angles_deg(
        angles["left_shank_deg"], contacts["left_foot"], script.fps
    )
    angles["right_foot_deg"] = foot_angles_deg(
        angles["right_shank_deg"], contacts["right_foot"], script.fps
    )
    root = np.zeros((n, 3))
    root[:, 0] = rows[:, ig.C_X] * scale
    root[:, 1] = rows[:, ig.C_X + 1] * scale + ANKLE_HEIGHT_M
    signals = {f"neuron_{i + 1}": np.maximum(rows[:, ig.C_U + i], 0.0) for i in range(12)}
    signals["posture_p1"] = np.maximum(rows[:, ig.C_U + 12], 0.0)
    signals["posture_p2"] = np.maximum(rows[:, ig.C_U + 13], 0.0)
    for side, col, bsp in (("left", 0, 6), ("right", 3, 7)):
        signals[f"{side}_hip_torque_nm"] = rows[:, ig.C_AUX + col]
        signals[f"{side}_knee_torque_nm"] = rows[:, ig.C_AUX + col + 1] + rows[:, ig.C_AUX + bsp]
        signals[f"{side}_ankle_torque_nm"] = rows[:, ig.C_AUX + col + 2]
        signals[f"{side}_bsp_torque_nm"] = rows[:, ig.C_AUX + bsp]
    signals["phi_c_rad"] = np.maximum(rows[:, ig.C_PHIC_L], rows[:, ig.C_PHIC_R])
    signals["push_force_n"] = rows[:, ig.C_PUSH]
    signals["hip_height_m"] = root[:, 1]
    segments = tuple(ClipSegment(s.gait, s.start_frame, s.end_frame) for s in script.segments)
    return GaitChannels(
        fps=float(script.fps),
        character="humanoid",
        angles=angles,
        root_position_m=root,
        contacts=contacts,
        segments=segments,
        events=tuple(sorted(events, key=lambda e: e.frame)),
        signals=signals,
        notes=tuple(notes),
    )


ENGINE = _CpgEngine()
