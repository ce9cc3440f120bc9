"""Kohonen map training exactly as the thesis (ch. 9, "Training") describes it.

A rectangular ``R x C`` competitive layer (default 40 x 40) with 2-D input weights, and one 6-D
output unit per competitive unit. For each of ``T`` presentations (default 20,000), at step
``t = 0 .. T-1``:

* a pattern ``p`` is drawn uniformly at random (``numpy.random.Generator(PCG64(seed))``);
* the winner is the unit whose input weight is nearest (Euclidean) to the pattern's input
  ``x = (gait id, completion)``; ties go to the lowest row-major index;
* learning rate ``alpha_t = alpha_0 (T - t) / T`` (0.4 at the first presentation, decreasing
  linearly, alpha_0 / T at the last) and neighbourhood radius ``r_t = floor(r_0 (T - t) / T)``
  (20 at the first, 0 — the winner alone — for the last 5 % of presentations);
* traditional Kohonen update of every unit in the square window
  ``|i - i*| <= r_t, |j - j*| <= r_t`` (rectangular topology, cut at the map's edges):
  ``w += alpha_t (x - w)``;
* the winner's output unit is SET to the pattern's output; neighbours' outputs are untouched.
  The winner is marked as "won" (and carries the pattern's stance flag, used for foot contacts).

After the last presentation each pattern's winner under the final weights is recorded
(``pattern_winner``).

Input weights start uniform in [0, 1)^2 (both inputs live in [0, 1]) from the same generator,
then the presentation order is drawn. :func:`train_reference` is the plain numpy statement of
the algorithm; :func:`train` runs the same arithmetic in a numba loop that touches only the
neighbourhood window, and tests check the two give identical weights.
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from animstudio.gaitdata.cycles import TrainingSet


@dataclass(frozen=True)
class TrainingSettings:
    """The thesis's training schedule (defaults) and the seed.

    Attributes:
        map_shape: competitive layer rows, columns.
        learning_rate: alpha_0, decreasing linearly to alpha_0 / T.
        radius: r_0 in units, decreasing linearly (floored) to 0.
        presentations: T.
        seed: PCG64 seed for the initial weights and the presentation order.
    """

    map_shape: tuple[int, int] = (40, 40)
    learning_rate: float = 0.4
    radius: int = 20
    presentations: int = 20_000
    seed: int = 0

    def __post_init__(self) -> None:
        rows, cols = self.map_shape
        if rows < 1 or cols < 1:
            raise ValueError(f"map_shape must be positive, got {self.map_shape}")
        if not 0.0 < self.learning_rate <= 1.0:
            raise ValueError(f"learning_rate must be in (0, 1], got {self.learning_rate}")
        if self.radius < 0 or self.presentations < 1 or self.seed < 0:
            raise ValueError("radius >= 0, presentations >= 1 and seed >= 0 are required")


@dataclass(frozen=True, eq=False)
class TrainedMap:
    """The state a training run ends in.

    Attributes:
        input_weights: ``(R, C, 2) float64`` competitive-layer weights (gait id, completion).
        outputs: ``(R, C, 6) float64`` output units (Q, F, Y deg, Δx, Δy thigh lengths, next
            completion); zero for units that never won.
        won: ``(R, C) bool`` units that won at least one presentation.
        stance: ``(R, C) bool`` stance flag of the last pattern each unit won.
        pattern_winner: ``(R, C) bool`` units that won during training and are the winner of at
            least one training pattern with the final input weights. Units that won early
            in training and were later dragged elsewhere as neighbours still hold an early
            pattern's output at a place where it does not belong ("stale" units); the
            controller searches only these (docs/som-controller.md).
    """

    input_weights: NDArray[np.float64]
    outputs: NDArray[np.float64]
    won: NDArray[np.bool_]
    stance: NDArray[np.bool_]
    pattern_winner: NDArray[np.bool_]


def _start(
    patterns: int, settings: TrainingSettings
) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    rng = np.random.Generator(np.random.PCG64(settings.seed))
    rows, cols = settings.map_shape
    weights = rng.random((rows, cols, 2))
    order = rng.integers(0, patterns, size=settings.presentations, dtype=np.int64)
    return weights, order


def train_reference(data: TrainingSet, settings: TrainingSettings | None = None) -> TrainedMap:
    """The algorithm of the module docstring in plain numpy (slow: the check for :func:`train`)."""
    settings = settings or TrainingSettings()
    weights, order = _start(data.num_patterns, settings)
    rows, cols = settings.map_shape
    outputs = np.zeros((rows, cols, 6))
    won = np.zeros((rows, cols), dtype=bool)
    stance = np.zeros((rows, cols), dtype=bool)
    total = settings.presentations
    for t in range(total):
        p = int(order[t])
        x0, x1 = data.inputs[p]
        alpha = settings.learning_rate * (total - t) / total
        r = (settings.radius * (total - t)) // total
        dist = (weights[:, :, 0] - x0) ** 2 + (weights[:, :, 1] - x1) ** 2
        bi, bj = divmod(int(np.argmin(dist)), cols)
        i0, i1 = max(bi - r, 0), min(bi + r + 1, rows)
        j0, j1 = max(bj - r, 0), min(bj + r + 1, cols)
        window = weights[i0:i1, j0:j1]
        window[:, :, 0] += alpha * (x0 - window[:, :, 0])
        window[:, :, 1] += alpha * (x1 - window[:, :, 1])
        outputs[bi, bj] = data.outputs[p]
        won[bi, bj] = True
        stance[bi, bj] = data.stance[p]
    return TrainedMap(weights, outputs, won, stance, _pattern_winners(weights, data.inputs, won))


def _train_steps_py(
    weights: NDArray[np.float64],
    outputs: NDArray[np.float64],
    won: NDArray[np.bool_],
    stance: NDArray[np.bool_],
    inputs: NDArray[np.float64],
    pattern_outputs: NDArray[np.float64],
    pattern_stance: NDArray[np.bool_],
    order: NDArray[np.int64],
    learning_rate: float,
    radius: int,
    start: int,
    stop: int,
) -> None:  # pragma: no cover - compiled; checked against train_reference in tests
    rows, cols = weights.shape[0], weights.shape[1]
    total = order.shape[0]
    for t in range(start, stop):
        p = order[t]
        x0 = inputs[p, 0]
        x1 = inputs[p, 1]
        alpha = learning_rate * (total - t) / total
        r = (radius * (total - t)) // total
        best = 0
        best_d = np.inf
        for i in range(rows):
            for j in range(cols):
                d0 = weights[i, j, 0] - x0
                d1 = weights[i, j, 1] - x1
                d = d0 * d0 + d1 * d1
                if d < best_d:
                    best_d = d
                    best = i * cols + j
        bi = best // cols
        bj = best % cols
        for i in range(max(bi - r, 0), min(bi + r + 1, rows)):
            for j in range(max(bj - r, 0), min(bj + r + 1, cols)):
                weights[i, j, 0] += alpha * (x0 - weights[i, j, 0])
                weights[i, j, 1] += alpha * (x1 - weights[i, j, 1])
        for k in range(pattern_outputs.shape[1]):
            outputs[bi, bj, k] = pattern_outputs[p, k]
        won[bi, bj] = True
        stance[bi, bj] = pattern_stance[p]


@functools.cache
def _train_steps() -> Callable[..., None]:
    # numba is imported on first training only: rendering with shipped weights never pays for it.
    import numba

    return numba.njit(cache=True, nogil=True)(_train_steps_py)


def train(
    data: TrainingSet,
    settings: TrainingSettings | None = None,
    *,
    progress: Callable[[int], None] | None = None,
) -> TrainedMap:
    """Train the map (module docstring); same result as :func:`train_reference`, much faster.

    Args:
        data: the training patterns.
        settings: schedule, map size and seed (thesis defaults).
        progress: called with the number of presentations done after each chunk.
    """
    settings = settings or TrainingSettings()
    weights, order = _start(data.num_patterns, settings)
    rows, cols = settings.map_shape
    outputs = np.zeros((rows, cols, 6))
    won = np.zeros((rows, cols), dtype=bool)
    stance = np.zeros((rows, cols), dtype=bool)
    inputs = np.ascontiguousarray(data.inputs)
    pattern_outputs = np.ascontiguousarray(data.outputs)
    pattern_stance = np.ascontiguousarray(data.stance)
    chunk = 2_000 if progress is not None else settings.presentations
    for start in range(0, settings.presentations, chunk):
        stop = min(start + chunk, settings.presentations)
        _train_steps()(
            weights,
            outputs,
            won,
            stance,
            inputs,
            pattern_outputs,
            pattern_stance,
            order,
            float(settings.learning_rate),
            int(settings.radius),
            start,
            stop,
        )
        if progress is not None:
            progress(stop - start)
    return TrainedMap(weights, outputs, won, stance, _pattern_winners(weights, inputs, won))


def _pattern_winners(
    weights: NDArray[np.float64], inputs: NDArray[np.float64], won: NDArray[np.bool_]
) -> NDArray[np.bool_]:
    flat = weights.reshape(-1, 2)
    mask = np.zeros(flat.shape[0], dtype=bool)
    for x in inputs:
        # Same expression and tie rule (first minimum) as the training's winner search.
        d = (flat[:, 0] - x[0]) ** 2 + (flat[:, 1] - x[1]) ** 2
        mask[int(np.argmin(d))] = True
    # A very short training may end with a pattern's nearest unit never having won it (its
    # output is not a pattern's): such a unit must not drive the pose either.
    return mask.reshape(weights.shape[:2]) & won


def unreproduced_patterns(trained: TrainedMap, data: TrainingSet) -> NDArray[np.int64]:
    """Indices of patterns whose winner (nearest pattern-winner unit) lacks that pattern's output.

    The thesis's scheme stores one pattern per unit; when two patterns end training with the
    same winner (the map did not separate them), the unit keeps whichever was presented last and
    the controller cannot replay the other. Empty for a map that reproduces its training set
    (the shipped one; ``animstudio train`` warns otherwise).
    """
    units = np.flatnonzero(trained.pattern_winner.ravel())
    flat = trained.input_weights.reshape(-1, 2)[units]
    outputs = trained.outputs.reshape(-1, 6)
    bad = []
    for p, (x, y) in enumerate(zip(data.inputs, data.outputs, strict=True)):
        unit = units[int(np.argmin(((flat - x) ** 2).sum(axis=1)))]
        if not np.array_equal(outputs[unit], y):
            bad.append(p)
    return np.array(bad, dtype=np.int64)
