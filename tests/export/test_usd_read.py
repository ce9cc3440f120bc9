"""Reading USD back into a Clip: round trips, foreign joint orders, and clear errors."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from pxr import Usd, UsdGeom, UsdSkel, Vt

from animstudio.core import quat
from animstudio.errors import DataError
from animstudio.export.usd import build_stage, write_usd
from animstudio.export.usd_read import read_clip


def _same_rotation(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Largest component difference up to the quaternion double cover."""
    return np.minimum(np.abs(a - b).max(axis=-1), np.abs(a + b).max(axis=-1))


@pytest.mark.parametrize("ext", [".usda", ".usdc"])
def test_round_trip(tmp_path: Path, ext: str, synthetic_humanoid_clip) -> None:  # type: ignore[no-untyped-def]
    clip = synthetic_humanoid_clip(90, 25.0, start_m=(12.0, -3.0))
    path = tmp_path / f"walk{ext}"
    write_usd(path, clip)
    back = read_clip(path)
    assert back.fps == 25.0 and back.num_frames == 90
    assert back.skeleton.joint_names == clip.skeleton.joint_names
    assert back.skeleton.parents == clip.skeleton.parents
    np.testing.assert_allclose(
        back.skeleton.rest_translations, clip.skeleton.rest_translations, atol=1e-6
    )
    assert _same_rotation(back.skeleton.rest_rotations, clip.skeleton.rest_rotations).max() < 1e-9
    assert _same_rotation(back.local_rotations, clip.local_rotations).max() <= 1e-6
    np.testing.assert_allclose(back.root_translations, clip.root_translations, atol=1e-5, rtol=0)
    assert (
        back.segments == clip.segments and back.events == clip.events and back.notes == clip.notes
    )
    assert back.mesh is not None and clip.mesh is not None
    np.testing.assert_allclose(back.mesh.vertices, clip.mesh.vertices, atol=1e-6)
    np.testing.assert_array_equal(back.mesh.faces, clip.mesh.faces)
    np.testing.assert_array_equal(back.mesh.joint_indices, clip.mesh.joint_indices)
    np.testing.assert_allclose(back.mesh.joint_weights, clip.mesh.joint_weights, atol=1e-7)


def test_animation_in_a_foreign_joint_order_is_mapped_by_path(
    tmp_path: Path, synthetic_humanoid_clip
) -> None:  # type: ignore[no-untyped-def]
    clip = synthetic_humanoid_clip(6)
    stage = build_stage(clip)
    anim = UsdSkel.Animation(stage.GetPrimAtPath("/Character/Skeleton/Animation"))
    perm = np.random.default_rng(0).permutation(clip.skeleton.num_joints)
    paths = list(clip.skeleton.joint_paths)
    anim.GetJointsAttr().Set(Vt.TokenArray([paths[i] for i in perm]))
    for attr in (anim.GetTranslationsAttr(), anim.GetRotationsAttr(), anim.GetScalesAttr()):
        for t in attr.GetTimeSamples():
            values = list(attr.Get(t))
            attr.Set(type(attr.Get(t))([values[i] for i in perm]), t)
    path = tmp_path / "shuffled.usda"
    stage.GetRootLayer().Export(str(path))
    back = read_clip(path)
    assert _same_rotation(back.local_rotations, clip.local_rotations).max() <= 1e-6
    np.testing.assert_allclose(back.root_translations, clip.root_translations, atol=1e-5)


def test_a_skeleton_without_animation_reads_as_its_rest_pose(
    tmp_path: Path, synthetic_humanoid_clip
) -> None:  # type: ignore[no-untyped-def]
    stage = build_stage(synthetic_humanoid_clip(4))
    stage.RemovePrim("/Character/Skeleton/Animation")
    UsdSkel.BindingAPI(
        stage.GetPrimAtPath("/Character/Skeleton")
    ).GetAnimationSourceRel().ClearTargets(True)
    path = tmp_path / "rest.usda"
    stage.GetRootLayer().Export(str(path))
    back = read_clip(path)
    assert back.num_frames == 4
    np.testing.assert_allclose(
        back.local_rotations, np.broadcast_to([1.0, 0, 0, 0], back.local_rotations.shape)
    )


def test_missing_file_is_a_data_error(tmp_path: Path) -> None:
    with pytest.raises(DataError, match="no such USD file"):
        read_clip(tmp_path / "absent.usda")


def test_garbage_file_is_a_data_error(tmp_path: Path) -> None:
    path = tmp_path / "junk.usda"
    path.write_text('#usda 1.0\ndef Xform "A" {{{ nonsense\n')
    with pytest.raises(DataError, match=r"junk\.usda"):
        read_clip(path)
    crate = tmp_path / "junk.usdc"
    crate.write_bytes(b"PXR-USDC" + bytes(range(200)))
    with pytest.raises(DataError, match=r"junk\.usdc"):
        read_clip(crate)


def test_stage_without_a_skeleton_is_a_data_error(tmp_path: Path) -> None:
    stage = Usd.Stage.CreateInMemory("plain.usda")
    UsdGeom.Xform.Define(stage, "/World")
    path = tmp_path / "plain.usda"
    stage.GetRootLayer().Export(str(path))
    with pytest.raises(DataError, match="no UsdSkel SkelRoot"):
        read_clip(path)
    UsdSkel.Root.Define(stage, "/World/Char")
    stage.GetRootLayer().Export(str(path))
    with pytest.raises(DataError, match="holds no Skeleton"):
        read_clip(path)


def test_scaled_joints_are_refused(tmp_path: Path, synthetic_humanoid_clip) -> None:  # type: ignore[no-untyped-def]
    stage = build_stage(synthetic_humanoid_clip(3))
    anim = UsdSkel.Animation(stage.GetPrimAtPath("/Character/Skeleton/Animation"))
    n = len(anim.GetJointsAttr().Get())
    anim.GetScalesAttr().Set(Vt.Vec3hArray.FromNumpy(np.full((n, 3), 2.0, np.float16)), 1)
    path = tmp_path / "scaled.usda"
    stage.GetRootLayer().Export(str(path))
    with pytest.raises(DataError, match="scale"):
        read_clip(path)


def test_moving_skeleton_prim_is_refused(tmp_path: Path, synthetic_humanoid_clip) -> None:  # type: ignore[no-untyped-def]
    stage = build_stage(synthetic_humanoid_clip(3))
    UsdGeom.Xformable(stage.GetPrimAtPath("/Character/Skeleton")).AddTranslateOp().Set((1.0, 0, 0))
    path = tmp_path / "moved.usda"
    stage.GetRootLayer().Export(str(path))
    with pytest.raises(DataError, match="non-identity transform"):
        read_clip(path)


def test_read_clip_agrees_with_the_rotation_helpers(
    tmp_path: Path, synthetic_humanoid_clip
) -> None:  # type: ignore[no-untyped-def]
    # Read rotations are unit quaternions in wxyz order (not xyzw): rotate the same vector alike.
    clip = synthetic_humanoid_clip(10)
    path = tmp_path / "w.usdc"
    write_usd(path, clip)
    back = read_clip(path)
    v = np.array([0.3, -1.0, 0.2])
    np.testing.assert_allclose(
        quat.rotate(back.local_rotations, v), quat.rotate(clip.local_rotations, v), atol=1e-6
    )


def test_without_a_time_range_the_animation_samples_give_the_frames(
    tmp_path: Path, synthetic_humanoid_clip
) -> None:  # type: ignore[no-untyped-def]
    clip = synthetic_humanoid_clip(12)
    stage = build_stage(clip)
    layer = stage.GetRootLayer()
    layer.ClearStartTimeCode()
    layer.ClearEndTimeCode()
    assert not stage.HasAuthoredTimeCodeRange()
    path = tmp_path / "norange.usda"
    layer.Export(str(path))
    back = read_clip(path)
    assert back.num_frames == 12
    assert _same_rotation(back.local_rotations, clip.local_rotations).max() <= 1e-6


def test_absurd_time_range_is_a_data_error(tmp_path: Path, synthetic_humanoid_clip) -> None:  # type: ignore[no-untyped-def]
    stage = build_stage(synthetic_humanoid_clip(3))
    stage.SetEndTimeCode(1e12)
    path = tmp_path / "huge.usda"
    stage.GetRootLayer().Export(str(path))
    with pytest.raises(DataError, match="unusable time range"):
        read_clip(path)
