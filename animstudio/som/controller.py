"""The thesis's animation controller (ch. 9, "The Animation Controller") over a trained map.

Two legs share one map. The right leg starts at completion 0.0 (heel strike: the training data
are a right leg) and the left at 0.5. Every frame, for each leg, the winner for the input
(gait id, completion) is found, its output (Q, F, Y, hip Δx, Δy) is emitted and its next
completion becomes the leg's input for the following frame. A gait change swaps the gait id and
keeps the completion.

Never-won units: a unit that never won a training presentation holds no pattern output (its
output is zeros) but still has an input weight, and may be the nearest unit to some input, so
it must never win. The search is restricted further, by default (``search="pattern"``), to the
units that win a training pattern with the final weights: most units that ever won did so early,
when the neighbourhood was wide, and were then dragged elsewhere as neighbours; they keep an
early pattern's output at a place where it no longer belongs. With them in the search
(``search="won"``, the ever-won mask) the shipped map starts the walking left leg (input
completion 0.5) on a stale unit at completion 0.4996 holding frame 15 of 35, and the legs stay
2.5 frames out of antiphase for the whole clip. docs/som-controller.md has the numbers.

Optional transition blend (``blend_frames = n > 0``; 0 is the thesis's hard switch): for ``n``
frames after a gait change, each leg also keeps running the previous gait from the completion
it had at the change, and the emitted angles and hip deltas are the cross-fade
``(1 - w) old + w new`` with ``w = (j + 1) / (n + 1)`` at the ``j``-th frame after the change.
The feedback loop always follows the new gait, so the blend never changes where the cycle goes.
A further change during a blend restarts the blend from the gait that was active just before it.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import NDArray

from animstudio.som.weights import SomWeights

LEGS = ("right", "left")
"""Leg order of every ``(F, 2, ...)`` array here."""

SearchMask = Literal["pattern", "won"]
"""Units the winner search considers: pattern winners (default) or every unit that ever won."""

START_COMPLETIONS = (0.0, 0.5)
"""Initial completion of the right and the left leg (thesis)."""


@dataclass(frozen=True, eq=False)
class ControllerRun:
    """What the controller emitted, frame-major, legs in :data:`LEGS` order.

    Attributes:
        angles_deg: ``(F, 2, 3)`` Q, F, Y.
        hip_delta_thigh: ``(F, 2, 2)`` hip Δx, Δy from frame k to k+1 (thigh lengths).
        completion: ``(F, 2)`` the completion input at frame k.
        winner: ``(F, 2) int64`` row-major index of the winning unit.
        stance: ``(F, 2) bool`` the winner's pattern has the foot on the ground.
    """

    angles_deg: NDArray[np.float64]
    hip_delta_thigh: NDArray[np.float64]
    completion: NDArray[np.float64]
    winner: NDArray[np.int64]
    stance: NDArray[np.bool_]

    @property
    def num_frames(self) -> int:
        return int(self.angles_deg.shape[0])


class WinnerSearch:
    """Nearest won unit for an input, memoised.

    The controller's inputs are finitely many (gait ids x completions the output layer can
    feed back), so each distinct input is searched once; an 18,000-frame script needs a few
    hundred searches.
    """

    def __init__(self, weights: SomWeights, *, search: SearchMask = "pattern") -> None:
        trained = weights.trained
        mask = trained.pattern_winner if search == "pattern" else trained.won
        self.units = np.flatnonzero(mask.ravel())
        flat = trained.input_weights.reshape(-1, 2)
        self._w0 = np.ascontiguousarray(flat[self.units, 0])
        self._w1 = np.ascontiguousarray(flat[self.units, 1])
        self._memo: dict[tuple[float, float], int] = {}

    def __call__(self, gait_id: float, completion: float) -> int:
        key = (gait_id, completion)
        unit = self._memo.get(key)
        if unit is None:
            d = (self._w0 - gait_id) ** 2 + (self._w1 - completion) ** 2
            unit = int(self.units[int(np.argmin(d))])
            self._memo[key] = unit
        return unit


def run_controller(
    weights: SomWeights,
    gait_index: NDArray[np.integer],
    *,
    blend_frames: int = 0,
    start_completions: tuple[float, float] = START_COMPLETIONS,
    search: SearchMask = "pattern",
) -> ControllerRun:
    """Drive both legs for ``len(gait_index)`` frames (module docstring).

    Args:
        weights: the trained map.
        gait_index: ``(F,)`` index into ``weights.gait_names`` of the gait at each frame.
        blend_frames: cross-fade length after a gait change (0 = thesis's hard switch).
        start_completions: right and left leg completion at frame 0.
        search: which units may win (module docstring).
    """
    gait_index = np.asarray(gait_index)
    n = int(gait_index.shape[0])
    if gait_index.ndim != 1 or n < 1:
        raise ValueError(f"gait_index must be (F,) with F >= 1, got {gait_index.shape}")
    if gait_index.min() < 0 or gait_index.max() >= len(weights.gait_names):
        raise ValueError("gait_index out of range of the weights' gaits")
    if blend_frames < 0:
        raise ValueError(f"blend_frames must be >= 0, got {blend_frames}")
    winner_of = WinnerSearch(weights, search=search)
    outputs = weights.trained.outputs.reshape(-1, 6)
    next_completion = [float(v) for v in outputs[:, 5]]
    ids = [float(v) for v in weights.gait_ids]
    gaits = [int(v) for v in gait_index]
    # The loop only follows the feedback chains (plain Python floats and a memoised search) and
    # tiles them once they repeat; outputs are gathered by index afterwards.
    winner = np.empty((n, 2), dtype=np.int64)
    completion = np.empty((n, 2))
    shadow = np.full((n, 2), -1, dtype=np.int64)  # previous gait's unit during a blend
    weight = np.ones(n)  # weight of the current gait's output
    c = [float(start_completions[0]), float(start_completions[1])]
    shadow_c = [0.0, 0.0]
    shadow_gait = -1
    blend_step = blend_frames  # >= blend_frames: no blend running
    k = 0
    while k < n:
        g = gaits[k]
        if k > 0 and g != gaits[k - 1] and blend_frames > 0:
            shadow_gait, shadow_c, blend_step = gaits[k - 1], list(c), 0
        if blend_step >= blend_frames:
            # No blend: follow each leg's chain to the end of this gait's run in one go.
            end = k + 1
            while end < n and gaits[end] == g:
                end += 1
            for leg in range(2):
                units, comps = _follow(winner_of, ids[g], c[leg], end - k, next_completion)
                winner[k:end, leg] = units
                completion[k:end, leg] = comps
                c[leg] = next_completion[int(units[-1])]
            k = end
            continue
        weight[k] = (blend_step + 1) / (blend_frames + 1)
        for leg in range(2):
            unit = winner_of(ids[g], c[leg])
            completion[k, leg] = c[leg]
            winner[k, leg] = unit
            old = winner_of(ids[shadow_gait], shadow_c[leg])
            shadow[k, leg] = old
            shadow_c[leg] = next_completion[old]
            c[leg] = next_completion[unit]
        blend_step += 1
        k += 1
    values = outputs[winner, :5]  # (F, 2, 5)
    mixed = shadow >= 0
    if np.any(mixed):
        w = np.broadcast_to(weight[:, None, None], values.shape)[mixed]
        values[mixed] = (1.0 - w) * outputs[shadow[mixed], :5] + w * values[mixed]
    unit_stance = weights.trained.stance.ravel()
    return ControllerRun(
        angles_deg=values[:, :, :3].copy(),
        hip_delta_thigh=values[:, :, 3:].copy(),
        completion=completion,
        winner=winner,
        stance=unit_stance[winner],
    )


def _follow(
    winner_of: WinnerSearch,
    gait_id: float,
    start: float,
    length: int,
    next_completion: list[float],
) -> tuple[NDArray[np.int64], NDArray[np.float64]]:
    """Winners and input completions of one leg for ``length`` frames of one gait.

    The chain is deterministic, so once a completion comes back the rest repeats that loop (a
    gait's cycle): it is tiled instead of searched frame by frame.
    """
    units: list[int] = []
    comps: list[float] = []
    seen: dict[float, int] = {}
    c = start
    while len(units) < length:
        if c in seen:
            loop = seen[c]
            rest = length - len(units)
            return (
                np.concatenate([units, np.resize(np.array(units[loop:]), rest)]).astype(np.int64),
                np.concatenate([comps, np.resize(np.array(comps[loop:]), rest)]),
            )
        seen[c] = len(units)
        unit = winner_of(gait_id, c)
        units.append(unit)
        comps.append(c)
        c = next_completion[unit]
    return np.array(units, dtype=np.int64), np.array(comps, dtype=np.float64)
