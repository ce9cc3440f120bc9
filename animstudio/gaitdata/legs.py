"""Planar leg geometry of the shipped character, from the thesis's angles (sagittal plane).

Points are relative to the hip-joint centre, ``(..., 2)`` metres as (x forward, y up), using
``animstudio.rig.proportions``. The heel is not a joint of the rig: it is modelled as the point
``ANKLE_HEIGHT_M`` straight below the ankle when the foot is at its standing angle
``FOOT_REST_DEG``, rotating with the foot (so in quiet standing both the heel and the toe joint
touch the floor).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from animstudio.rig.proportions import (
    ANKLE_HEIGHT_M,
    FOOT_M,
    FOOT_REST_DEG,
    SHANK_M,
    THIGH_M,
)


@dataclass(frozen=True)
class LegPoints:
    """Leg points relative to the hip, each ``(..., 2)`` (x forward, y up) metres."""

    knee: NDArray[np.float64]
    ankle: NDArray[np.float64]
    toe: NDArray[np.float64]
    heel: NDArray[np.float64]

    def lowest_y(self) -> NDArray[np.float64]:
        """``(...)`` height of the lower of heel and toe joint (the foot's ground contact)."""
        return np.minimum(self.heel[..., 1], self.toe[..., 1])


def leg_points(angles_deg: NDArray[np.float64], *, scale: float = 1.0) -> LegPoints:
    """Points of a leg posed by ``(..., 3)`` thesis angles Q, F, Y (degrees).

    ``scale`` multiplies every length: ``L_thigh / THIGH_M`` poses a leg with the character's
    proportions and a thigh of ``L_thigh`` (how the training-data derivation models a subject).
    """
    a = np.radians(np.asarray(angles_deg, dtype=np.float64))
    q, f, y = a[..., 0], a[..., 1], a[..., 2]
    knee = np.stack([THIGH_M * np.sin(q), -THIGH_M * np.cos(q)], axis=-1)
    ankle = knee + np.stack([SHANK_M * np.sin(f), -SHANK_M * np.cos(f)], axis=-1)
    toe = ankle + np.stack([FOOT_M * np.cos(y), FOOT_M * np.sin(y)], axis=-1)
    tilt = y - np.radians(FOOT_REST_DEG)  # foot rotation away from standing, + = toe up
    heel = ankle + np.stack(
        [ANKLE_HEIGHT_M * np.sin(tilt), -ANKLE_HEIGHT_M * np.cos(tilt)], axis=-1
    )
    return LegPoints(knee=scale * knee, ankle=scale * ankle, toe=scale * toe, heel=scale * heel)
