"""Root motion from the controller's hip deltas, scaled to the character.

The thesis multiplies the dimensionless hip deltas by the thigh length; here it is the
character's thigh (``animstudio.rig.proportions.THIGH_M``), so a taller character takes longer
strides with the same motion.

Both legs' winners emit a hip delta each frame: two samples of the recorded hip path, half a
cycle apart. The pelvis moves once, so the two are combined as their mean. Over one cycle the
mean sums to exactly the training cycle's displacement (the stride; zero height change on level
ground, the measured rise on stairs), so a long script never drifts. The alternative of
following the stance leg's delta (the one recorded with that foot planted) was measured and
rejected: it only ever uses the stance half of the recorded hip path, whose vertical deltas do
not sum to zero — the walking hip sank 1 cm per cycle (docs/som-controller.md).

The root starts at x = 0, z = 0, at the height that puts the lowest point of the lowest stance
foot (heel or toe joint, :mod:`animstudio.som.legs`) on the floor y = 0 at frame 0.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from animstudio.gaitdata.legs import leg_points
from animstudio.rig.proportions import THIGH_M
from animstudio.som.controller import ControllerRun


def combined_hip_delta(run: ControllerRun) -> NDArray[np.float64]:
    """``(F, 2)`` hip Δx, Δy per frame (thigh lengths): the mean of both legs' outputs."""
    return np.asarray(run.hip_delta_thigh.mean(axis=1), dtype=np.float64)


def initial_hip_height(run: ControllerRun) -> float:
    """Hip height (m) that puts the lowest stance foot of frame 0 on the floor."""
    lowest = leg_points(run.angles_deg[0]).lowest_y()  # (2,) per leg, relative to the hip
    stance = run.stance[0]
    feet = lowest[stance] if np.any(stance) else lowest
    return float(-np.min(feet))


def root_path(run: ControllerRun, *, thigh_m: float = THIGH_M) -> NDArray[np.float64]:
    """``(F, 3)`` root (hip-centre) positions: accumulated deltas x ``thigh_m``, z = 0."""
    delta = combined_hip_delta(run) * thigh_m
    path = np.zeros((run.num_frames, 3))
    path[1:, :2] = np.cumsum(delta[:-1], axis=0)
    path[:, 1] += initial_hip_height(run)
    return path
