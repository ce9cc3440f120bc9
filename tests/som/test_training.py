"""Training follows the thesis's schedule; the numba path equals the plain numpy statement."""

from __future__ import annotations

import numpy as np
import pytest

from animstudio.gaitdata import TrainingSet
from animstudio.som.training import TrainingSettings, train, train_reference


@pytest.mark.parametrize(
    "settings",
    [
        TrainingSettings(),  # the thesis: 40x40, 0.4, 20, 20,000
        TrainingSettings(map_shape=(13, 29), radius=7, presentations=3_001, seed=5),
    ],
)
def test_fast_path_equals_reference(training_set: TrainingSet, settings: TrainingSettings) -> None:
    fast = train(training_set, settings)
    ref = train_reference(training_set, settings)
    np.testing.assert_array_equal(fast.input_weights, ref.input_weights)
    np.testing.assert_array_equal(fast.outputs, ref.outputs)
    np.testing.assert_array_equal(fast.won, ref.won)
    np.testing.assert_array_equal(fast.stance, ref.stance)


def test_progress_chunks_do_not_change_the_result(training_set: TrainingSet) -> None:
    done: list[int] = []
    chunked = train(training_set, progress=done.append)
    assert sum(done) == 20_000 and len(done) > 1
    np.testing.assert_array_equal(chunked.input_weights, train(training_set).input_weights)


def test_seed_decides_and_output_units_hold_patterns(training_set: TrainingSet) -> None:
    a = train(training_set, TrainingSettings(seed=1))
    b = train(training_set, TrainingSettings(seed=2))
    assert not np.array_equal(a.input_weights, b.input_weights)
    # Every won unit's output is exactly one training pattern's output (set, never averaged);
    # never-won units keep zeros.
    patterns = {tuple(row) for row in training_set.outputs}
    for out in a.outputs[a.won]:
        assert tuple(out) in patterns
    assert not np.any(a.outputs[~a.won])
    # After the final winner-only phase each pattern's nearest unit holds that pattern.
    flat = a.input_weights.reshape(-1, 2)
    for x, y in zip(training_set.inputs, training_set.outputs, strict=True):
        unit = int(np.argmin(((flat - x) ** 2).sum(axis=1)))
        np.testing.assert_array_equal(a.outputs.reshape(-1, 6)[unit], y)


def test_schedule_shrinks_the_neighbourhood_to_the_winner(training_set: TrainingSet) -> None:
    # With one presentation the radius is r0 and the whole window moves; the last presentation of
    # a run has radius 0: training 1 presentation with radius 0 moves exactly one unit.
    settings = TrainingSettings(map_shape=(10, 10), radius=0, presentations=1, seed=3)
    start = np.random.Generator(np.random.PCG64(3)).random((10, 10, 2))
    moved = np.any(train(training_set, settings).input_weights != start, axis=2)
    assert moved.sum() == 1
    settings = TrainingSettings(map_shape=(10, 10), radius=2, presentations=1, seed=3)
    moved = np.any(train(training_set, settings).input_weights != start, axis=2)
    rows, cols = np.nonzero(moved)
    assert rows.max() - rows.min() <= 4 and cols.max() - cols.min() <= 4 and moved.sum() >= 9


def test_bad_settings_are_rejected() -> None:
    with pytest.raises(ValueError):
        TrainingSettings(map_shape=(0, 40))
    with pytest.raises(ValueError):
        TrainingSettings(learning_rate=0.0)
    with pytest.raises(ValueError):
        TrainingSettings(presentations=0)
