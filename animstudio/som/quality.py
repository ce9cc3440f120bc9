"""Foot slide: how far a planted foot's ground contact drifts during one stance phase.

Definition (docs/som-controller.md). The foot touches the ground at its heel early in stance
and at its toe joint late in stance. The heel is not a joint: it is the point ``ANKLE_HEIGHT_M``
below the ankle in the standing foot pose, turning with the foot (:mod:`animstudio.gaitdata.legs`),
found here from the clip's ankle and toe-joint world positions. At each stance frame the
*contact point* is the lower of heel and toe joint; its horizontal displacement from frame k
to k + 1 is measured on the same point (so the hand-over from heel to toe at heel-off is not a
jump), and the slide of a step is the largest horizontal distance the accumulated displacement
reaches from where the foot landed, over the stance phase (first to last contact frame).
Stance phases cut off by the start or the end of the clip are not counted.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from animstudio.core.clip import Clip
from animstudio.core.fk import joint_positions
from animstudio.rig.proportions import ANKLE_HEIGHT_M, FOOT_REST_DEG


def heel_and_toe(clip: Clip, side: str) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """``(F, 3)`` world positions of the modelled heel point and the toe joint of ``side``."""
    pos = joint_positions(clip)
    ankle = pos[:, clip.skeleton.index(f"{side}_ankle")]
    toe = pos[:, clip.skeleton.index(f"{side}_toe")]
    foot = toe - ankle
    # Foot pitch in the sagittal plane: the x-y angle of the ankle -> toe line.
    pitch = np.arctan2(foot[:, 1], np.hypot(foot[:, 0], foot[:, 2]))
    tilt = pitch - np.radians(FOOT_REST_DEG)
    heading = foot[:, [0, 2]] / np.maximum(
        np.linalg.norm(foot[:, [0, 2]], axis=1, keepdims=True), 1e-12
    )
    heel = ankle.copy()
    heel[:, 0] += ANKLE_HEIGHT_M * np.sin(tilt) * heading[:, 0]
    heel[:, 2] += ANKLE_HEIGHT_M * np.sin(tilt) * heading[:, 1]
    heel[:, 1] -= ANKLE_HEIGHT_M * np.cos(tilt)
    return heel, toe


def foot_slide_per_step(clip: Clip, contact: NDArray[np.bool_], side: str) -> NDArray[np.float64]:
    """``(S,)`` slide (m) of each complete stance phase of ``side`` (module docstring)."""
    contact = np.asarray(contact, dtype=bool)
    heel, toe = heel_and_toe(clip, side)
    use_heel = heel[:, 1] <= toe[:, 1]
    here = np.where(use_heel[:, None], heel, toe)[:, [0, 2]]
    there = np.where(use_heel[:-1, None], heel[1:], toe[1:])[:, [0, 2]]
    step = there - here[:-1]  # (F - 1, 2) horizontal displacement of the contact point
    slides = []
    k = 1
    n = len(contact)
    while k < n:
        if contact[k] and not contact[k - 1]:
            end = k
            while end < n and contact[end]:
                end += 1
            if end >= n:
                break
            drift = np.cumsum(step[k : end - 1], axis=0)
            slides.append(float(np.max(np.linalg.norm(drift, axis=1), initial=0.0)))
            k = end
        k += 1
    return np.array(slides, dtype=np.float64)
