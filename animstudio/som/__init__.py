"""The Kohonen locomotion controller of seed 000 (thesis ch. 9): training, weights, controller."""

from animstudio.som.training import TrainedMap, TrainingSettings, train, train_reference
from animstudio.som.weights import (
    DEFAULT_SEED,
    DEFAULT_WEIGHTS,
    SomWeights,
    load_weights,
    save_weights,
    train_weights,
)

__all__ = [
    "DEFAULT_SEED",
    "DEFAULT_WEIGHTS",
    "SomWeights",
    "TrainedMap",
    "TrainingSettings",
    "load_weights",
    "save_weights",
    "train",
    "train_reference",
    "train_weights",
]
