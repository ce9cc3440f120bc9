from __future__ import annotations

from pathlib import Path

import pytest

from animstudio.gaitdata import TrainingSet, load_training_set
from animstudio.som.weights import DEFAULT_WEIGHTS, SomWeights, load_weights

TRAINING_DATA = Path(__file__).resolve().parents[2] / "training_data"


@pytest.fixture(scope="session")
def training_set() -> TrainingSet:
    return load_training_set(TRAINING_DATA)


@pytest.fixture(scope="session")
def shipped() -> SomWeights:
    return load_weights(DEFAULT_WEIGHTS)
