"""Training data: the cycle-file format, its loader, and the derivation from real trials."""

from animstudio.gaitdata.cycles import Cycle, TrainingSet, load_training_set

__all__ = ["Cycle", "TrainingSet", "load_training_set"]
