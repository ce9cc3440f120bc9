"""Everything the 3D view needs from a Clip, precomputed once per (re)load as arrays.

viser's skinned mesh takes bone poses in *mesh space*: the bind pose when it is created and the
current pose on every update (the client derives the bone inverses from the bind pose). With
the mesh at the scene origin, mesh space is the world, so both are forward kinematics of the
clip: the rest pose for the bind, and the shown frame during playback.

The frame's pose is computed when it is shown (a fraction of a millisecond for one frame)
rather than for every frame up front: FK of a whole minute (1800 frames) takes ~35 ms, which
would sit on the live-reload path between a save and the updated view.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from animstudio.core import quat
from animstudio.core.clip import Clip
from animstudio.core.fk import rest_world_transforms, world_transforms


@dataclass(frozen=True, eq=False)
class PosedClip:
    """A clip's poses in the form the viewer sends.

    Attributes:
        clip: the source clip.
        bind_wxyz: ``(J, 4) float32`` wxyz world rotation of every joint in the rest (bind) pose.
        bind_positions: ``(J, 3) float32`` metres, world position of every joint in the bind pose.
        skin_weights: ``(V, J) float32`` dense weights (rows sum to 1), ``None`` without a mesh.
        bone_segments: ``(J - 1, 2)`` int joint index pairs ``(parent, child)``, for drawing the
            skeleton as lines.
    """

    clip: Clip
    bind_wxyz: NDArray[np.float32]
    bind_positions: NDArray[np.float32]
    skin_weights: NDArray[np.float32] | None
    bone_segments: NDArray[np.int64]

    @property
    def num_frames(self) -> int:
        return self.clip.num_frames

    def frame_pose(self, frame: int) -> tuple[NDArray[np.float32], NDArray[np.float32]]:
        """World ``(J, 4)`` wxyz rotations and ``(J, 3)`` positions (metres) of every joint at ``frame``."""
        clip = self.clip
        local_t = clip.skeleton.rest_translations.copy()
        local_t[0] = clip.root_translations[frame]
        world_m, world_t = world_transforms(clip.skeleton, clip.local_rotations[frame], local_t)
        return quat.from_matrix(world_m).astype(np.float32), world_t.astype(np.float32)

    def focus_point(self, frame: int) -> NDArray[np.float64]:
        """``(3,)`` the point the camera follows at ``frame``: the root joint (its local = world)."""
        return np.array(self.clip.root_translations[frame], dtype=np.float64)

    def segments_world(self, frame: int) -> NDArray[np.float32]:
        """``(J - 1, 2, 3)`` parent-to-child bone lines at ``frame``."""
        return self.frame_pose(frame)[1][self.bone_segments]


def dense_skin_weights(clip: Clip) -> NDArray[np.float32] | None:
    """``(V, J)`` weights from the mesh's ``(V, K)`` influences (viser keeps the top four)."""
    mesh = clip.mesh
    if mesh is None:
        return None
    num_vertices = mesh.vertices.shape[0]
    dense = np.zeros((num_vertices, clip.skeleton.num_joints), dtype=np.float32)
    rows = np.repeat(np.arange(num_vertices), mesh.influences_per_vertex)
    # add.at, not assignment: a joint listed twice for one vertex must sum its weights.
    np.add.at(dense, (rows, mesh.joint_indices.ravel()), mesh.joint_weights.ravel())
    return dense


def pose_clip(clip: Clip) -> PosedClip:
    """The bind pose of ``clip`` in the form the viewer sends (frames are posed on demand)."""
    skeleton = clip.skeleton
    rest_m, rest_t = rest_world_transforms(skeleton)
    segments = np.array([(p, j) for j, p in enumerate(skeleton.parents) if p >= 0], dtype=np.int64)
    return PosedClip(
        clip=clip,
        bind_wxyz=quat.from_matrix(rest_m).astype(np.float32),
        bind_positions=rest_t.astype(np.float32),
        skin_weights=dense_skin_weights(clip),
        bone_segments=segments.reshape(-1, 2),
    )
