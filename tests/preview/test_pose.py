"""Bone poses for viser's skinned mesh: forward kinematics of the bind pose and of a frame."""

from __future__ import annotations

import numpy as np

from animstudio.core import quat
from animstudio.core.clip import Clip
from animstudio.core.fk import joint_positions
from animstudio.preview.pose import PosedClip, dense_skin_weights, pose_clip


def _skin(posed: PosedClip, bone_wxyz: np.ndarray, bone_pos: np.ndarray) -> np.ndarray:
    # Linear blend skinning as the browser does it: bone * inverse(bind) * vertex, weighted.
    mesh = posed.clip.mesh
    assert mesh is not None and posed.skin_weights is not None
    bind_m = quat.to_matrix(posed.bind_wxyz.astype(np.float64))
    pose_m = quat.to_matrix(bone_wxyz.astype(np.float64))
    local = np.einsum(
        "jki,vjk->vji", bind_m, mesh.vertices[:, None, :] - posed.bind_positions[None]
    )
    world = np.einsum("jik,vjk->vji", pose_m, local) + bone_pos[None]
    return np.einsum("vj,vji->vi", posed.skin_weights, world)


def test_frame_poses_are_the_clips_joint_positions(walk_climb_clip: Clip) -> None:
    posed = pose_clip(walk_climb_clip)
    positions = joint_positions(walk_climb_clip)
    for frame in (0, 64, 194):
        wxyz, pos = posed.frame_pose(frame)
        assert wxyz.shape == (walk_climb_clip.skeleton.num_joints, 4)
        assert np.allclose(pos, positions[frame], atol=1e-5)
        assert np.allclose(posed.focus_point(frame), walk_climb_clip.root_translations[frame])


def test_dense_weights_keep_every_influence(walk_climb_clip: Clip) -> None:
    dense = dense_skin_weights(walk_climb_clip)
    mesh = walk_climb_clip.mesh
    assert dense is not None and mesh is not None
    assert np.allclose(dense.sum(axis=1), 1.0, atol=1e-5)
    v = 123
    for j, w in zip(mesh.joint_indices[v], mesh.joint_weights[v], strict=True):
        assert dense[v, j] >= w - 1e-7


def test_skinning_the_bind_pose_gives_the_rest_mesh_and_frames_move_it(
    walk_climb_clip: Clip,
) -> None:
    posed = pose_clip(walk_climb_clip)
    mesh = walk_climb_clip.mesh
    assert mesh is not None and posed.skin_weights is not None
    assert np.allclose(
        _skin(posed, posed.bind_wxyz, posed.bind_positions), mesh.vertices, atol=1e-5
    )
    # A vertex bound to one joint only keeps its distance to that joint in every frame.
    rigid = np.nonzero(posed.skin_weights.max(axis=1) > 0.999)[0][::50]
    joint = posed.skin_weights[rigid].argmax(axis=1)
    rest_d = np.linalg.norm(mesh.vertices[rigid] - posed.bind_positions[joint], axis=1)
    for frame in (0, 77, 150):
        wxyz, pos = posed.frame_pose(frame)
        d = np.linalg.norm(_skin(posed, wxyz, pos)[rigid] - pos[joint], axis=1)
        assert np.allclose(d, rest_d, atol=1e-4)
    # The pelvis is not rotated by the rig: its skin moves by the root translation.
    pelvis = np.nonzero(posed.skin_weights[:, 0] > 0.999)[0]
    assert pelvis.size > 0
    delta = walk_climb_clip.root_translations[150] - walk_climb_clip.root_translations[0]
    at0 = _skin(posed, *posed.frame_pose(0))[pelvis]
    at150 = _skin(posed, *posed.frame_pose(150))[pelvis]
    assert np.allclose(at150 - at0, delta, atol=1e-4)
