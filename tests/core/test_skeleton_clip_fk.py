"""Core value types (Skeleton, Clip, SkinnedMesh, GaitChannels) and forward kinematics."""

from __future__ import annotations

import numpy as np
import pytest

from animstudio.core import quat
from animstudio.core.channels import GaitChannels
from animstudio.core.clip import Clip, ClipEvent, ClipSegment
from animstudio.core.fk import joint_positions, rest_world_transforms, world_transforms
from animstudio.core.mesh import SkinnedMesh
from animstudio.core.skeleton import Skeleton

ARM = Skeleton(
    ("root", "upper", "lower"),
    (-1, 0, 1),
    np.array([[0, 1, 0], [0, -0.3, 0], [0, -0.25, 0]], float),
)


def _clip(frames: int = 4, **kwargs: object) -> Clip:
    rot = quat.identity((frames, 3)).astype(np.float32)
    return Clip(
        fps=30.0,
        skeleton=ARM,
        root_translations=np.zeros((frames, 3)),
        local_rotations=rot,
        **kwargs,
    )  # type: ignore[arg-type]


# --- Skeleton -------------------------------------------------------------------------------


def test_skeleton_paths_index_and_defaults() -> None:
    assert ARM.joint_paths == ("root", "root/upper", "root/upper/lower")
    assert ARM.index("lower") == 2
    np.testing.assert_array_equal(ARM.rest_rotations, quat.identity((3,)))
    assert not ARM.rest_translations.flags.writeable
    assert ARM == Skeleton(ARM.joint_names, ARM.parents, ARM.rest_translations.copy())
    with pytest.raises(KeyError, match="joints are root, upper, lower"):
        ARM.index("hand")


@pytest.mark.parametrize(
    ("names", "parents", "message"),
    [
        ((), (), "at least one joint"),
        (("a", "a"), (-1, 0), "unique"),
        (("a", "b c"), (-1, 0), "not a valid USD identifier"),
        (("a", "b"), (0, 0), "root"),
        (("a", "b", "c"), (-1, 2, 0), "must come before"),
    ],
)
def test_skeleton_rejects_bad_hierarchies(names, parents, message) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(ValueError, match=message):
        Skeleton(names, parents, np.zeros((len(names), 3)))


def test_skeleton_rejects_bad_shapes() -> None:
    with pytest.raises(ValueError, match="rest_translations"):
        Skeleton(("a",), (-1,), np.zeros((2, 3)))
    with pytest.raises(ValueError, match="rest_rotations"):
        Skeleton(("a",), (-1,), np.zeros((1, 3)), np.zeros((1, 3)))


# --- Clip -----------------------------------------------------------------------------------


def test_clip_freezes_its_arrays_and_derives_translations() -> None:
    clip = _clip(3, curves={"x_deg": [1.0, 2.0, 3.0]})
    assert clip.num_frames == 3 and clip.duration_s == pytest.approx(0.1)
    assert not clip.local_rotations.flags.writeable and not clip.curves["x_deg"].flags.writeable
    with pytest.raises(TypeError):
        clip.curves["y"] = np.zeros(3)  # type: ignore[index]
    lt = clip.local_translations()
    assert lt.shape == (3, 3, 3)
    np.testing.assert_array_equal(lt[:, 1], np.broadcast_to(ARM.rest_translations[1], (3, 3)))
    np.testing.assert_array_equal(lt[:, 0], 0.0)  # the root's comes from root_translations


def test_clip_segments_must_tile_and_events_lie_inside() -> None:
    ok = _clip(4, segments=(ClipSegment("walk", 0, 2), ClipSegment("run", 2, 4)))
    assert ok.segment_at(3) == ClipSegment("run", 2, 4) and ok.segment_at(9) is None
    with pytest.raises(ValueError, match="tile"):
        _clip(4, segments=(ClipSegment("walk", 1, 4),))
    with pytest.raises(ValueError, match="cover 3 frames"):
        _clip(4, segments=(ClipSegment("walk", 0, 3),))
    with pytest.raises(ValueError, match="outside the clip"):
        _clip(4, events=(ClipEvent("push", 4, "late"),))
    with pytest.raises(ValueError, match="start < end"):
        ClipSegment("walk", 2, 2)


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"fps": 0.0}, "fps"),
        ({"root_translations": np.zeros((4, 2))}, "root_translations"),
        ({"local_rotations": np.zeros((4, 2, 4))}, "local_rotations"),
        ({"root_translations": np.full((4, 3), np.nan)}, "non-finite"),
        ({"curves": {"a": np.zeros(3)}}, "curve 'a'"),
    ],
)
def test_clip_rejects_bad_arrays(kwargs, message) -> None:  # type: ignore[no-untyped-def]
    base = {
        "fps": 30.0,
        "skeleton": ARM,
        "root_translations": np.zeros((4, 3)),
        "local_rotations": quat.identity((4, 3)),
    }
    with pytest.raises(ValueError, match=message):
        Clip(**(base | kwargs))  # type: ignore[arg-type]


# --- SkinnedMesh / GaitChannels ---------------------------------------------------------------


def test_skinned_mesh_checks_indices_and_weights() -> None:
    v = np.zeros((3, 3))
    f = np.array([[0, 1, 2]])
    ok = SkinnedMesh(v, f, np.zeros((3, 2)), np.array([[0.5, 0.5]] * 3))
    assert ok.influences_per_vertex == 2
    with pytest.raises(ValueError, match="faces"):
        SkinnedMesh(v, np.array([[0, 1, 3]]), np.zeros((3, 1)), np.ones((3, 1)))
    with pytest.raises(ValueError, match="sum to 1"):
        SkinnedMesh(v, f, np.zeros((3, 1)), np.full((3, 1), 0.9))
    with pytest.raises(ValueError, match=r"\(V, K\)"):
        SkinnedMesh(v, f, np.zeros((3, 1)), np.ones((3, 2)))


def test_gait_channels_validate_lengths_and_values() -> None:
    root = np.zeros((5, 3))
    ch = GaitChannels(
        30.0, "humanoid", {"a_deg": np.arange(5.0)}, root, {"left_foot": [1, 0, 1, 0, 1]}
    )
    assert ch.num_frames == 5 and ch.contacts["left_foot"].dtype == bool
    with pytest.raises(ValueError, match="curve 'a_deg'"):
        GaitChannels(30.0, "humanoid", {"a_deg": np.arange(4.0)}, root)
    with pytest.raises(ValueError, match="contact"):
        GaitChannels(30.0, "humanoid", {}, root, {"left_foot": [True]})
    with pytest.raises(ValueError, match="non-finite"):
        GaitChannels(30.0, "humanoid", {"a_deg": np.full(5, np.inf)}, root)


# --- forward kinematics -----------------------------------------------------------------------


def test_fk_of_a_bent_arm_matches_hand_computation() -> None:
    # Root at (1, 1, 0) turned 90 deg about +Y; shoulder 30 deg and elbow 45 deg about +Z.
    rot = np.stack(
        [quat.about_y(np.pi / 2), quat.about_z(np.radians(30)), quat.about_z(np.radians(45))]
    )
    trans = np.array([[1.0, 1.0, 0.0], [0, -0.3, 0], [0, -0.25, 0]])
    world_r, world_p = world_transforms(ARM, rot, trans)
    a, b = np.radians(30), np.radians(75)
    # In the root's frame: "upper" hangs 0.3 below the root, "lower" 0.25 further along the
    # upper joint's 30 deg direction; a point 0.25 along "lower" points at 30 + 45 = 75 deg.
    upper_local = np.array([0.0, -0.3, 0.0])
    lower_local = upper_local + 0.25 * np.array([np.sin(a), -np.cos(a), 0.0])
    tip_local = lower_local + 0.25 * np.array([np.sin(b), -np.cos(b), 0.0])
    # The root is turned 90 deg about +Y: its (x, y, z) is world (z, y, -x).
    to_world = lambda v: np.array([v[2], v[1], -v[0]]) + np.array([1.0, 1.0, 0.0])  # noqa: E731
    np.testing.assert_allclose(world_p[0], [1.0, 1.0, 0.0], atol=1e-12)
    np.testing.assert_allclose(world_p[1], to_world(upper_local), atol=1e-12)
    np.testing.assert_allclose(world_p[2], to_world(lower_local), atol=1e-12)
    np.testing.assert_allclose(
        world_p[2] + world_r[2] @ [0, -0.25, 0], to_world(tip_local), atol=1e-12
    )
    np.testing.assert_allclose(
        world_r[2], quat.to_matrix(quat.multiply(rot[0], quat.about_z(b))), atol=1e-12
    )


def test_fk_broadcasts_over_frames_and_selects_frames() -> None:
    frames = 6
    angles = np.linspace(0.0, 1.0, frames)
    rot = np.stack(
        [quat.identity((frames,)), quat.about_z(angles), quat.identity((frames,))], axis=1
    )
    clip = Clip(30.0, ARM, np.tile([0.0, 1.0, 0.0], (frames, 1)), rot.astype(np.float32))
    pos = joint_positions(clip)
    assert pos.shape == (frames, 3, 3)
    np.testing.assert_allclose(pos[:, 2, 0], 0.25 * np.sin(angles), atol=1e-6)
    np.testing.assert_allclose(joint_positions(clip, np.array([4, 1])), pos[[4, 1]])
    np.testing.assert_allclose(joint_positions(clip, slice(2, 4)), pos[2:4])


def test_rest_world_transforms_use_rest_rotations() -> None:
    skel = Skeleton(
        ("a", "b"),
        (-1, 0),
        np.array([[0.0, 0, 0], [1.0, 0, 0]]),
        np.stack([quat.about_z(np.pi / 2), quat.identity()]),
    )
    rot, pos = rest_world_transforms(skel)
    np.testing.assert_allclose(pos[1], [0.0, 1.0, 0.0], atol=1e-12)
    np.testing.assert_allclose(rot[1], quat.to_matrix(quat.about_z(np.pi / 2)), atol=1e-12)
