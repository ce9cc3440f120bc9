"""The ``som`` engine: the thesis's Kohonen locomotion controller (seed 000, ch. 9).

Script segments name gaits from the weights file's vocabulary; the controller
(:mod:`animstudio.som.controller`) runs at the thesis's 30 fps, root motion is the hip deltas
times the character's thigh (:mod:`animstudio.som.motion`). A script at another frame rate is
generated at 30 fps over the same duration and resampled to the script's rate: output frame k
(at ``k / fps`` s) interpolates the 30 fps angles and root linearly at ``30 k / fps``; contacts,
completions and winners take the nearest earlier 30 fps frame. The gait of every 30 fps frame
is the script's gait at that time, so segment boundaries stay where the script puts them.
"""

from __future__ import annotations

from functools import lru_cache
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from animstudio.core.channels import GaitChannels
from animstudio.core.clip import ClipSegment
from animstudio.engines import EngineOptions
from animstudio.errors import ScriptError
from animstudio.script.model import Script
from animstudio.som.controller import LEGS, ControllerRun, run_controller
from animstudio.som.motion import root_path
from animstudio.som.weights import DEFAULT_WEIGHTS, SomWeights, load_weights

CONTROL_FPS = 30
"""The thesis's rate: one Markov state per 1/30 s."""


@lru_cache(maxsize=8)
def _load(path: Path, mtime_ns: int, size: int) -> SomWeights:
    # Keyed by modification time and size so an edited file is re-read.
    return load_weights(path)


def weights_for(options: EngineOptions) -> SomWeights:
    """The weights named by ``options`` (the shipped default when none), cached per file."""
    path = Path(options.weights) if options.weights is not None else DEFAULT_WEIGHTS
    try:
        stat = path.stat()
    except OSError:
        return load_weights(path)  # raises the located "not found" DataError
    return _load(path.resolve(), stat.st_mtime_ns, stat.st_size)


def _control_gaits(script: Script, weights: SomWeights) -> tuple[NDArray[np.int64], float]:
    """Gait index per 30 fps frame covering the script, and 30 fps frames per script frame."""
    total = script.total_frames
    ratio = CONTROL_FPS / script.fps
    # Enough 30 fps frames to interpolate the last output frame (at 30 (F - 1) / fps).
    n = int(np.floor((total - 1) * ratio)) + 2 if ratio != 1.0 else total
    per_frame = np.empty(total, dtype=np.int64)
    for seg in script.segments:
        per_frame[seg.start_frame : seg.end_frame] = weights.gait_names.index(seg.gait)
    script_frame = np.minimum(np.floor(np.arange(n) / ratio + 1e-9).astype(np.int64), total - 1)
    return per_frame[script_frame], ratio


def _resample(values: NDArray[np.float64], positions: NDArray[np.float64]) -> NDArray[np.float64]:
    # Linear interpolation along axis 0 at fractional frame positions.
    i0 = np.minimum(np.floor(positions).astype(np.int64), len(values) - 1)
    i1 = np.minimum(i0 + 1, len(values) - 1)
    t = (positions - i0).reshape((-1,) + (1,) * (values.ndim - 1))
    return np.asarray((1.0 - t) * values[i0] + t * values[i1], dtype=np.float64)


class SomEngine:
    """:class:`animstudio.engines.Engine` for the Kohonen controller."""

    name = "som"
    characters: tuple[str, ...] = ("humanoid",)

    def gaits(self, options: EngineOptions) -> tuple[str, ...]:
        """The weights file's gait names."""
        return weights_for(options).gait_names

    def validate(self, script: Script, options: EngineOptions) -> list[ScriptError]:
        """Unknown gaits, segment parameters and push events (located)."""
        from animstudio.script.parser import check_gaits

        errors = check_gaits(script, self.gaits(options), engine_label="som")
        for seg in script.segments:
            if seg.params:
                first = next(iter(seg.params))
                span = seg.param_spans.get(first, seg.span)
                errors.append(ScriptError(span, f"gait '{seg.gait}' takes no parameters"))
        for event in script.events:
            errors.append(ScriptError(event.span, "push events need engine cpg"))
        return errors

    def generate(self, script: Script, options: EngineOptions) -> GaitChannels:
        """Run the controller over the script (module docstring for the frame-rate rule)."""
        weights = weights_for(options)
        gaits, ratio = _control_gaits(script, weights)
        blend = round(script.blend_frames * ratio)
        run = run_controller(weights, gaits, blend_frames=blend)
        root = root_path(run)
        if ratio == 1.0:
            return _channels(script, run, root, np.arange(script.total_frames, dtype=np.float64))
        positions = np.arange(script.total_frames, dtype=np.float64) * ratio
        return _channels(script, run, root, positions)


def _channels(
    script: Script, run: ControllerRun, root: NDArray[np.float64], positions: NDArray[np.float64]
) -> GaitChannels:
    angles = _resample(run.angles_deg, positions)  # (F, 2, 3)
    nearest = np.minimum(np.floor(positions + 1e-9).astype(np.int64), run.num_frames - 1)
    channel_angles: dict[str, NDArray[np.float64]] = {}
    contacts: dict[str, NDArray[np.bool_]] = {}
    signals: dict[str, NDArray[np.float64]] = {}
    for leg, side in enumerate(LEGS):
        for j, part in enumerate(("thigh", "shank", "foot")):
            channel_angles[f"{side}_{part}_deg"] = angles[:, leg, j]
        contacts[f"{side}_foot"] = run.stance[nearest, leg]
        signals[f"{side}_completion"] = run.completion[nearest, leg]
        signals[f"{side}_winner_unit"] = run.winner[nearest, leg].astype(np.float64)
    notes: tuple[str, ...] = ()
    if script.fps != CONTROL_FPS:
        notes = (
            f"som engine: generated at {CONTROL_FPS} fps (the training data's rate) and "
            f"resampled to {script.fps} fps",
        )
    return GaitChannels(
        fps=float(script.fps),
        character="humanoid",
        angles=channel_angles,
        root_position_m=_resample(root, positions),
        contacts=contacts,
        segments=tuple(ClipSegment(s.gait, s.start_frame, s.end_frame) for s in script.segments),
        signals=signals,
        notes=notes,
    )


ENGINE = SomEngine()
