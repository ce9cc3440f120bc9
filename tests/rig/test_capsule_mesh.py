"""The capsule skin builder: geometry along bones, smooth weights, determinism, errors."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from animstudio.core import quat
from animstudio.core.fk import rest_world_transforms, world_transforms
from animstudio.core.skeleton import Skeleton
from animstudio.rig.humanoid import HUMANOID, humanoid_mesh
from animstudio.rig.mesh import INFLUENCES, Ellipsoid, build_capsule_mesh
from animstudio.rig.proportions import HEIGHT_M

# A bent three-bone chain (rest rotation on the middle joint) to show the builder is generic.
CHAIN = Skeleton(
    ("base", "mid", "tip", "end"),
    (-1, 0, 1, 2),
    np.array([[0.0, 1.0, 0.0], [0.3, 0.0, 0.0], [0.0, 0.25, 0.0], [0.0, 0.2, 0.0]]),
    np.array([[1.0, 0, 0, 0], [1.0, 0, 0, 0], *quat.about_x([0.5]), [1.0, 0, 0, 0]]),
)
RADII = {"mid": 0.05, "tip": 0.04, "end": 0.03}


def _segment_distance(p: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    d = b - a
    t = np.clip((p - a) @ d / (d @ d), 0.0, 1.0)
    return np.linalg.norm(p - (a + t[:, None] * d), axis=1)


def _skin(mesh, skeleton: Skeleton, rot: np.ndarray) -> np.ndarray:  # type: ignore[no-untyped-def]
    """Linear blend skinning of the rest-pose vertices for local rotations ``rot`` (J, 4)."""
    r_bind, t_bind = rest_world_transforms(skeleton)
    r, t = world_transforms(skeleton, rot, skeleton.rest_translations)
    r_skin = r @ np.swapaxes(r_bind, -1, -2)
    t_skin = t - np.einsum("jab,jb->ja", r_skin, t_bind)
    out = np.zeros_like(mesh.vertices)
    for k in range(mesh.influences_per_vertex):
        j = mesh.joint_indices[:, k]
        moved = np.einsum("vab,vb->va", r_skin[j], mesh.vertices) + t_skin[j]
        out += mesh.joint_weights[:, k, None] * moved
    return out


def test_humanoid_mesh_is_a_few_thousand_outward_facing_vertices_standing_on_the_floor() -> None:
    mesh = humanoid_mesh()
    assert 1000 <= len(mesh.vertices) <= 6000
    assert mesh.influences_per_vertex == INFLUENCES
    np.testing.assert_allclose(mesh.joint_weights.sum(axis=1), 1.0, atol=1e-6)
    assert mesh.joint_indices.min() >= 0 and mesh.joint_indices.max() < HUMANOID.num_joints
    tm = trimesh.Trimesh(mesh.vertices, mesh.faces, process=False)
    assert tm.is_winding_consistent
    assert tm.volume > 0.03  # closed parts with outward normals; a 1.75 m adult is ~0.07 m^3
    assert mesh.vertices[:, 1].min() == pytest.approx(0.0, abs=1e-3)  # soles on the floor
    assert mesh.vertices[:, 1].max() == pytest.approx(HEIGHT_M, abs=0.01)
    assert humanoid_mesh() is mesh  # cached


def test_mesh_is_deterministic() -> None:
    a = build_capsule_mesh(CHAIN, RADII)
    b = build_capsule_mesh(CHAIN, RADII)
    for name in ("vertices", "faces", "joint_indices", "joint_weights"):
        assert getattr(a, name).tobytes() == getattr(b, name).tobytes(), name


def test_capsules_wrap_their_bones_and_move_with_the_parent_joint() -> None:
    mesh = build_capsule_mesh(CHAIN, {"tip": 0.04}, blend_m=0.03)
    _, pos = rest_world_transforms(CHAIN)
    dist = _segment_distance(mesh.vertices, pos[1], pos[2])
    np.testing.assert_allclose(dist, 0.04, atol=1e-9)  # every vertex on the capsule surface
    length = np.linalg.norm(pos[2] - pos[1])
    along = (mesh.vertices - pos[1]) @ (pos[2] - pos[1]) / length
    assert np.all(mesh.joint_indices[:, 0] == CHAIN.index("mid"))
    inner = (along > 0.03 + 1e-9) & (along < length - 0.03 - 1e-9)
    assert inner.sum() >= 3 * 12  # rings along the straight part, not only at its ends
    np.testing.assert_allclose(mesh.joint_weights[inner, 0], 1.0)  # rigid away from the joints


def test_weights_split_half_and_half_at_a_joint_and_fade_over_the_blend_zone() -> None:
    blend = 0.04
    mesh = build_capsule_mesh(CHAIN, RADII, blend_m=blend, ring_spacing_m=0.01)
    _, pos = rest_world_transforms(CHAIN)
    mid, tip = CHAIN.index("mid"), CHAIN.index("tip")

    def weight_of(joint: int) -> np.ndarray:
        return np.where(mesh.joint_indices == joint, mesh.joint_weights, 0.0).sum(axis=1)

    # Vertices of the "end" capsule (moved by "tip"): on the bone tip->end, radius 0.03.
    on_bone = np.abs(_segment_distance(mesh.vertices, pos[2], pos[3]) - 0.03) < 1e-9
    axis = (pos[3] - pos[2]) / np.linalg.norm(pos[3] - pos[2])
    along = (mesh.vertices - pos[2]) @ axis
    at_joint = on_bone & (np.abs(along) < 1e-9)
    assert at_joint.sum() >= 8
    np.testing.assert_allclose(weight_of(tip)[at_joint], 0.5, atol=1e-6)
    np.testing.assert_allclose(weight_of(mid)[at_joint], 0.5, atol=1e-6)
    past = on_bone & (along > blend + 1e-9) & (along < 0.2 - blend)
    assert past.any()
    np.testing.assert_allclose(weight_of(tip)[past], 1.0, atol=1e-6)


def test_blended_skin_stays_closed_when_a_joint_bends() -> None:
    # Bend the middle joint 70 degrees: with blending, no edge stretches more than 2.5x.
    mesh = build_capsule_mesh(CHAIN, RADII, sections=16)
    rot = CHAIN.rest_rotations.copy()
    rot[2] = quat.multiply(rot[2], quat.about_z(np.radians(70.0)))
    posed = _skin(mesh, CHAIN, rot)
    edges = mesh.faces[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2)
    rest_len = np.linalg.norm(np.diff(mesh.vertices[edges], axis=1)[:, 0], axis=1)
    posed_len = np.linalg.norm(np.diff(posed[edges], axis=1)[:, 0], axis=1)
    assert np.max(posed_len / rest_len) < 2.5


def test_ellipsoids_are_rigid_parts_of_their_joint() -> None:
    ell = Ellipsoid("tip", (0.3, 1.2, 0.1), (0.05, 0.1, 0.2))
    mesh = build_capsule_mesh(CHAIN, {}, ellipsoids=[ell], ellipsoid_subdivisions=1)
    u = (mesh.vertices - np.array(ell.center_m)) / np.array(ell.radii_m)
    np.testing.assert_allclose(np.linalg.norm(u, axis=1), 1.0, atol=1e-9)
    assert np.all(mesh.joint_indices[:, 0] == CHAIN.index("tip"))
    np.testing.assert_allclose(mesh.joint_weights[:, 0], 1.0)


@pytest.mark.parametrize(
    ("radii", "ellipsoids", "message"),
    [
        ({"nope": 0.1}, (), "bone 'nope'"),
        ({"base": 0.1}, (), "root joint"),
        ({"tip": 0.0}, (), "radius must be positive"),
        ({}, (Ellipsoid("nope", (0, 0, 0), (1, 1, 1)),), "ellipsoid 'nope'"),
        ({}, (), "at least one"),
    ],
)
def test_bad_parts_are_clear_errors(radii, ellipsoids, message) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(ValueError, match=message):
        build_capsule_mesh(CHAIN, radii, ellipsoids=ellipsoids)


def test_zero_length_bone_is_an_error() -> None:
    skel = Skeleton(("a", "b"), (-1, 0), np.zeros((2, 3)))
    with pytest.raises(ValueError, match="zero length"):
        build_capsule_mesh(skel, {"b": 0.1})


def test_ellipsoid_needs_positive_radii() -> None:
    with pytest.raises(ValueError, match="positive"):
        Ellipsoid("a", (0, 0, 0), (1, 0, 1))
