"""Forward kinematics: local joint transforms to world (skeleton space) transforms."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from animstudio.core import quat
from animstudio.core.clip import Clip
from animstudio.core.skeleton import Skeleton


def world_transforms(
    skeleton: Skeleton,
    local_rotations: NDArray[np.floating],
    local_translations: NDArray[np.floating],
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """World rotations ``(..., J, 3, 3)`` and positions ``(..., J, 3)`` from local ones.

    ``local_rotations`` is ``(..., J, 4)`` wxyz and ``local_translations`` ``(..., J, 3)``; the
    root's local transform is its world transform.
    """
    local_m = quat.to_matrix(local_rotations)
    local_t = np.asarray(local_translations, dtype=np.float64)
    world_m = np.empty_like(local_m)
    world_t = np.empty_like(local_t)
    for j, p in enumerate(skeleton.parents):
        if p < 0:
            world_m[..., j, :, :] = local_m[..., j, :, :]
            world_t[..., j, :] = local_t[..., j, :]
        else:
            world_m[..., j, :, :] = world_m[..., p, :, :] @ local_m[..., j, :, :]
            world_t[..., j, :] = world_t[..., p, :] + np.einsum(
                "...ij,...j->...i", world_m[..., p, :, :], local_t[..., j, :]
            )
    return world_m, world_t


def joint_positions(
    clip: Clip, frames: NDArray[np.integer] | slice | None = None
) -> NDArray[np.float64]:
    """World joint positions ``(F, J, 3)`` in metres of ``clip`` (optionally only ``frames``)."""
    sel = slice(None) if frames is None else frames
    rot = clip.local_rotations[sel]
    trans = clip.local_translations()[sel]
    return world_transforms(clip.skeleton, rot, trans)[1]


def rest_world_transforms(skeleton: Skeleton) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """World rotation matrices ``(J, 3, 3)`` and positions ``(J, 3)`` of the rest pose."""
    return world_transforms(skeleton, skeleton.rest_rotations, skeleton.rest_translations)
