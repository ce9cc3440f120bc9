"""USD export: validity (pxr.UsdValidation), UsdSkel structure, FK agreement, metadata, atomicity."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from pxr import Usd, UsdGeom, UsdSkel, UsdValidation

from animstudio.core import quat
from animstudio.core.clip import Clip
from animstudio.core.fk import joint_positions, rest_world_transforms, world_transforms
from animstudio.core.skeleton import Skeleton
from animstudio.errors import ExportError
from animstudio.export import usd
from animstudio.export.usd import build_stage, write_usd


@pytest.fixture(scope="module")
def validation_context() -> UsdValidation.ValidationContext:
    # usd-core 26.x: every registered validator (UsdGeom metadata, UsdSkel binding, composition ...).
    validators = UsdValidation.ValidationRegistry().GetOrLoadAllValidators()
    assert len(validators) > 10
    return UsdValidation.ValidationContext(validators)


def _problems(ctx: UsdValidation.ValidationContext, stage: Usd.Stage) -> list[str]:
    return [
        f"{e.GetName()}: {e.GetMessage()}"
        for e in ctx.Validate(stage)
        if e.GetType() == UsdValidation.ValidationErrorType.Error
    ]


def test_the_validator_set_catches_a_broken_skel_stage(validation_context) -> None:  # type: ignore[no-untyped-def]
    # The check below can fail: a stage without metadata and a skel:skeleton without the API errs.
    stage = Usd.Stage.CreateInMemory("broken.usda")
    UsdSkel.Root.Define(stage, "/R")
    mesh = UsdGeom.Mesh.Define(stage, "/R/M")
    mesh.GetPrim().CreateRelationship("skel:skeleton").SetTargets(["/R/S"])
    names = " ".join(_problems(validation_context, stage))
    assert "MissingUpAxisMetadata" in names and "MissingSkelBindingAPI" in names


@pytest.mark.parametrize("ext", [".usda", ".usdc", ".usd"])
def test_written_files_pass_usd_validation(
    tmp_path: Path, ext: str, validation_context, synthetic_humanoid_clip
) -> None:  # type: ignore[no-untyped-def]
    path = tmp_path / f"walk{ext}"
    write_usd(path, synthetic_humanoid_clip(40))
    stage = Usd.Stage.Open(str(path))
    assert _problems(validation_context, stage) == []


@pytest.mark.parametrize(
    ("ext", "magic"), [(".usda", b"#usda 1.0"), (".usdc", b"PXR-USDC"), (".usd", b"PXR-USDC")]
)
def test_extension_picks_the_format(
    tmp_path: Path, ext: str, magic: bytes, synthetic_humanoid_clip
) -> None:  # type: ignore[no-untyped-def]
    path = tmp_path / f"walk{ext}"
    write_usd(path, synthetic_humanoid_clip(5))
    assert path.read_bytes().startswith(magic)


def test_stage_metadata_and_frame_count(tmp_path: Path, synthetic_humanoid_clip) -> None:  # type: ignore[no-untyped-def]
    clip = synthetic_humanoid_clip(73, 24.0)
    path = tmp_path / "meta.usdc"
    write_usd(path, clip)
    stage = Usd.Stage.Open(str(path))
    assert UsdGeom.GetStageUpAxis(stage) == UsdGeom.Tokens.y
    assert UsdGeom.GetStageMetersPerUnit(stage) == 1.0
    assert stage.GetTimeCodesPerSecond() == 24.0 and stage.GetFramesPerSecond() == 24.0
    assert (stage.GetStartTimeCode(), stage.GetEndTimeCode()) == (0.0, 72.0)
    anim = UsdSkel.Animation(stage.GetPrimAtPath("/Character/Skeleton/Animation"))
    for attr in (anim.GetTranslationsAttr(), anim.GetRotationsAttr(), anim.GetScalesAttr()):
        assert attr.GetTimeSamples() == [float(k) for k in range(73)], attr.GetName()
    np.testing.assert_array_equal(np.array(anim.GetScalesAttr().Get(17)), 1.0)


def test_usdskel_structure_and_binding_api_on_every_skel_prim(synthetic_humanoid_clip) -> None:  # type: ignore[no-untyped-def]
    clip = synthetic_humanoid_clip(10)
    stage = build_stage(clip)
    root = stage.GetDefaultPrim()
    assert root.GetPath() == "/Character" and root.IsA(UsdSkel.Root)
    skel = UsdSkel.Skeleton(stage.GetPrimAtPath("/Character/Skeleton"))
    assert list(skel.GetJointsAttr().Get()) == list(clip.skeleton.joint_paths)
    assert list(skel.GetJointNamesAttr().Get()) == list(clip.skeleton.joint_names)
    source = UsdSkel.BindingAPI(skel.GetPrim()).GetAnimationSourceRel().GetTargets()
    assert [str(p) for p in source] == ["/Character/Skeleton/Animation"]
    anim = UsdSkel.Animation(stage.GetPrimAtPath(source[0]))
    assert list(anim.GetJointsAttr().Get()) == list(clip.skeleton.joint_paths)

    carrying = 0
    for prim in stage.Traverse():
        if any(n.startswith(("skel:", "primvars:skel:")) for n in prim.GetPropertyNames()):
            carrying += 1
            assert prim.HasAPI(UsdSkel.BindingAPI), prim.GetPath()
    assert carrying == 2  # the skeleton (animationSource) and the mesh

    mesh = UsdGeom.Mesh(stage.GetPrimAtPath("/Character/Mesh"))
    binding = UsdSkel.BindingAPI(mesh.GetPrim())
    assert [str(p) for p in binding.GetSkeletonRel().GetTargets()] == ["/Character/Skeleton"]
    k = clip.mesh.influences_per_vertex
    for primvar in (binding.GetJointIndicesPrimvar(), binding.GetJointWeightsPrimvar()):
        assert primvar.GetElementSize() == k
        assert primvar.GetInterpolation() == UsdGeom.Tokens.vertex
    assert len(mesh.GetPointsAttr().Get()) == len(clip.mesh.vertices)
    assert list(mesh.GetFaceVertexIndicesAttr().Get()) == clip.mesh.faces.reshape(-1).tolist()
    assert binding.GetGeomBindTransformAttr().HasAuthoredValue()


def test_bind_transforms_are_world_rest_matrices_in_gf_row_vector_layout(
    synthetic_humanoid_clip,
) -> None:  # type: ignore[no-untyped-def]
    clip = synthetic_humanoid_clip(3)
    stage = build_stage(clip)
    skel = UsdSkel.Skeleton(stage.GetPrimAtPath("/Character/Skeleton"))
    bind = np.array(skel.GetBindTransformsAttr().Get()).reshape(-1, 4, 4)
    rot, pos = rest_world_transforms(clip.skeleton)
    np.testing.assert_allclose(bind[:, 3, :3], pos, atol=1e-12)
    np.testing.assert_allclose(np.swapaxes(bind[:, :3, :3], -1, -2), rot, atol=1e-12)


def _usd_world_positions(path: Path, frames: list[int]) -> np.ndarray:
    """Joint world positions computed by UsdSkel itself (Cache -> SkeletonQuery)."""
    stage = Usd.Stage.Open(str(path))
    root = UsdSkel.Root(stage.GetDefaultPrim())
    cache = UsdSkel.Cache()
    assert cache.Populate(root, Usd.PrimDefaultPredicate)
    query = cache.GetSkelQuery(UsdSkel.Skeleton(stage.GetPrimAtPath("/Character/Skeleton")))
    out = []
    for f in frames:
        xf = UsdGeom.XformCache(Usd.TimeCode(f))
        m = np.array(query.ComputeJointWorldTransforms(xf)).reshape(-1, 4, 4)
        out.append(m[:, 3, :3])
    return np.array(out)


@pytest.mark.parametrize("ext", [".usda", ".usdc"])
def test_usdskel_world_joint_positions_match_our_fk(
    tmp_path: Path, ext: str, synthetic_humanoid_clip
) -> None:  # type: ignore[no-untyped-def]
    # Start 400 m out so float32 storage of the root is exercised far from the origin.
    clip = synthetic_humanoid_clip(300, start_m=(400.0, -120.0), speed_mps=4.0)
    path = tmp_path / f"far{ext}"
    write_usd(path, clip)
    frames = [0, 1, 57, 150, 233, 299]
    ours = joint_positions(clip, np.array(frames))
    theirs = _usd_world_positions(path, frames)
    assert np.abs(ours[..., 0]).max() > 400.0
    np.testing.assert_allclose(theirs, ours, atol=1e-4, rtol=0)


def test_usd_skinning_matches_our_linear_blend_skinning(synthetic_humanoid_clip) -> None:  # type: ignore[no-untyped-def]
    # Checks the whole binding (bindTransforms, geomBindTransform, joint indices and weights).
    clip = synthetic_humanoid_clip(30)
    stage = build_stage(clip)
    root = UsdSkel.Root(stage.GetDefaultPrim())
    cache = UsdSkel.Cache()
    cache.Populate(root, Usd.PrimDefaultPredicate)
    (binding,) = cache.ComputeSkelBindings(root, Usd.PrimDefaultPredicate)
    skel_query = cache.GetSkelQuery(binding.GetSkeleton())
    (skin_query,) = binding.GetSkinningTargets()
    frame = 21
    xforms = skel_query.ComputeSkinningTransforms(Usd.TimeCode(frame))
    points = UsdGeom.Mesh(skin_query.GetPrim()).GetPointsAttr().Get()
    assert skin_query.ComputeSkinnedPoints(xforms, points, Usd.TimeCode(frame))
    theirs = np.array(points)

    mesh = clip.mesh
    r_bind, t_bind = rest_world_transforms(clip.skeleton)
    r, t = world_transforms(
        clip.skeleton, clip.local_rotations[frame], clip.local_translations()[frame]
    )
    r_skin = r @ np.swapaxes(r_bind, -1, -2)
    t_skin = t - np.einsum("jab,jb->ja", r_skin, t_bind)
    ours = np.zeros_like(mesh.vertices)
    for k in range(mesh.influences_per_vertex):
        j = mesh.joint_indices[:, k]
        ours += mesh.joint_weights[:, k, None] * (
            np.einsum("vab,vb->va", r_skin[j], mesh.vertices) + t_skin[j]
        )
    np.testing.assert_allclose(theirs, ours, atol=1e-5)


def test_any_skeleton_with_rest_rotations_exports_faithfully(tmp_path: Path) -> None:
    rng = np.random.default_rng(11)
    names = ("root", "a", "b", "c", "d")
    parents = (-1, 0, 1, 0, 3)
    rest_r = quat.normalize(rng.normal(size=(5, 4)))
    skel = Skeleton(names, parents, rng.uniform(-0.5, 0.5, (5, 3)), rest_r)
    frames = 25
    motion = quat.from_axis_angle(
        quat.normalize(rng.normal(size=(5, 3))), rng.uniform(-3, 3, (frames, 5))
    )
    clip = Clip(
        fps=60.0,
        skeleton=skel,
        root_translations=rng.uniform(-2, 2, (frames, 3)),
        local_rotations=quat.multiply(rest_r, motion).astype(np.float32),
    )
    path = tmp_path / "generic.usda"
    write_usd(path, clip)
    sel = [0, 12, 24]
    np.testing.assert_allclose(
        _usd_world_positions(path, sel), joint_positions(clip, np.array(sel)), atol=1e-5
    )
    stage = Usd.Stage.Open(str(path))
    assert stage.GetPrimAtPath("/Character/Mesh").IsValid() is False  # no mesh, no Mesh prim


def test_segments_events_notes_and_version_in_custom_layer_data(synthetic_humanoid_clip) -> None:  # type: ignore[no-untyped-def]
    from animstudio import __version__

    clip = synthetic_humanoid_clip(40)
    stage = build_stage(clip)  # keep the stage alive while reading its layer
    data = stage.GetRootLayer().customLayerData
    assert data["animstudio:version"] == __version__
    assert list(data["animstudio:notes"]) == list(clip.notes)
    seg = data["animstudio:segments"]
    assert list(seg["gaits"]) == [s.gait for s in clip.segments]
    assert list(seg["startFrames"]) == [s.start_frame for s in clip.segments]
    assert list(seg["endFrames"]) == [s.end_frame for s in clip.segments]
    ev = data["animstudio:events"]
    assert list(ev["frames"]) == [e.frame for e in clip.events]
    assert list(ev["labels"]) == [e.label for e in clip.events]


def test_unknown_extension_is_an_export_error_listing_the_valid_ones(
    tmp_path: Path, synthetic_humanoid_clip
) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(ExportError, match=r"\.usda, \.usdc, \.usd"):
        write_usd(tmp_path / "walk.fbx", synthetic_humanoid_clip(3))
    assert list(tmp_path.iterdir()) == []


def test_bad_character_name_is_an_export_error(synthetic_humanoid_clip) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(ExportError, match="not a valid USD prim name"):
        build_stage(synthetic_humanoid_clip(2), name="my character")


def test_unwritable_target_is_an_export_error(tmp_path: Path, synthetic_humanoid_clip) -> None:  # type: ignore[no-untyped-def]
    blocker = tmp_path / "file"
    blocker.write_text("not a directory")
    with pytest.raises(ExportError):
        write_usd(blocker / "walk.usda", synthetic_humanoid_clip(2))


def _failing_export(layer, tmp: Path) -> None:  # type: ignore[no-untyped-def]
    """Write half a file, then fail: what a crash in the middle of an export looks like."""
    tmp.write_bytes(b"#usda 1.0\n(\n")
    raise RuntimeError("disk on fire")


def test_failed_write_leaves_no_file_and_no_temporary(
    tmp_path: Path, monkeypatch, synthetic_humanoid_clip
) -> None:  # type: ignore[no-untyped-def]
    monkeypatch.setattr(usd, "_export_layer", _failing_export)
    with pytest.raises(RuntimeError, match="disk on fire"):
        write_usd(tmp_path / "walk.usdc", synthetic_humanoid_clip(5))
    assert list(tmp_path.iterdir()) == []


def test_failed_write_leaves_an_existing_target_intact(
    tmp_path: Path, monkeypatch, synthetic_humanoid_clip
) -> None:  # type: ignore[no-untyped-def]
    target = tmp_path / "walk.usda"
    write_usd(target, synthetic_humanoid_clip(5))
    before = target.read_bytes()
    monkeypatch.setattr(usd, "_export_layer", _failing_export)
    with pytest.raises(RuntimeError):
        write_usd(target, synthetic_humanoid_clip(9))
    assert target.read_bytes() == before
    assert [p.name for p in tmp_path.iterdir()] == ["walk.usda"]


def test_export_goes_through_a_temporary_file_with_the_real_extension(
    tmp_path: Path, monkeypatch, synthetic_humanoid_clip
) -> None:  # type: ignore[no-untyped-def]
    seen: list[Path] = []
    real = usd._export_layer

    def spy(layer, tmp: Path) -> None:  # type: ignore[no-untyped-def]
        seen.append(tmp)
        real(layer, tmp)

    monkeypatch.setattr(usd, "_export_layer", spy)
    write_usd(tmp_path / "walk.usdc", synthetic_humanoid_clip(5))
    (tmp,) = seen
    assert tmp.parent == tmp_path and tmp.name.startswith(".walk.tmp-") and tmp.suffix == ".usdc"
    assert [p.name for p in tmp_path.iterdir()] == ["walk.usdc"]
