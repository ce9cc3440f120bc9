"""USD export: a Clip as a UsdSkel character (docs/usd-export.md).

Layout of the stage :func:`build_stage` returns::

    /Character             SkelRoot (default prim)
        Skeleton           Skeleton: joints, jointNames, bindTransforms, restTransforms,
                           skel:animationSource -> Animation        (SkelBindingAPI)
            Animation      SkelAnimation: joints, translations, rotations, scales, one time
                           sample per frame (time code k = frame k)
        Mesh               Mesh (if the clip has one): points, triangles, skel:skeleton,
                           primvars:skel:jointIndices/jointWeights, skel:geomBindTransform
                           (SkelBindingAPI)

Stage metadata: ``upAxis = Y``, ``metersPerUnit = 1``, ``timeCodesPerSecond = framesPerSecond =
fps``, ``startTimeCode = 0``, ``endTimeCode = F - 1``. The clip's segments, events and notes and
the animstudio version go into the root layer's ``customLayerData`` (keys ``animstudio:*``).

Speed: the time samples are written straight into the root layer with ``Sdf.Layer.SetTimeSample``
inside one ``Sdf.ChangeBlock``, one ``Vt.*Array.FromNumpy`` per frame and attribute (the
high-level ``Usd.Attribute.Set`` per sample is several times slower; benchmarks/bench_render.py).

Precision: USD stores joint translations as float32, so the root's position is exact to about
6e-8 of its distance from the origin (0.06 mm at 1 km).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from numpy.typing import NDArray
from pxr import Gf, Sdf, Tf, Usd, UsdGeom, UsdSkel, Vt

from animstudio import __version__
from animstudio.core import quat
from animstudio.core.clip import Clip
from animstudio.core.fk import rest_world_transforms
from animstudio.core.mesh import SkinnedMesh
from animstudio.errors import ExportError
from animstudio.export.atomic import write_with

USD_EXTENSIONS: tuple[str, ...] = (".usda", ".usdc", ".usd")
"""``.usda`` is text; ``.usdc`` and ``.usd`` are the binary crate format."""

SKELETON_NAME = "Skeleton"
ANIMATION_NAME = "Animation"
MESH_NAME = "Mesh"

KEY_VERSION = "animstudio:version"
KEY_NOTES = "animstudio:notes"
KEY_SEGMENTS = "animstudio:segments"
KEY_EVENTS = "animstudio:events"


def build_stage(clip: Clip, *, name: str = "Character") -> Usd.Stage:
    """Build an in-memory UsdSkel stage of ``clip`` (layout in the module docstring).

    Args:
        clip: the animation to export.
        name: the SkelRoot's prim name (a valid USD identifier).

    Raises:
        ExportError: ``name`` is not a valid prim name.
    """
    if not Sdf.Path.IsValidIdentifier(name):
        raise ExportError(f"character name {name!r} is not a valid USD prim name")
    stage = Usd.Stage.CreateInMemory(f"{name}.usda")
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.y)
    UsdGeom.SetStageMetersPerUnit(stage, 1.0)
    stage.SetTimeCodesPerSecond(clip.fps)
    stage.SetFramesPerSecond(clip.fps)
    stage.SetStartTimeCode(0)
    stage.SetEndTimeCode(clip.num_frames - 1)
    stage.GetRootLayer().customLayerData = _layer_data(clip)

    root_path = Sdf.Path.absoluteRootPath.AppendChild(name)
    root = UsdSkel.Root.Define(stage, root_path)
    stage.SetDefaultPrim(root.GetPrim())

    skel_path = root_path.AppendChild(SKELETON_NAME)
    anim_path = skel_path.AppendChild(ANIMATION_NAME)
    skeleton = clip.skeleton
    joints = Vt.TokenArray(list(skeleton.joint_paths))
    skel = UsdSkel.Skeleton.Define(stage, skel_path)
    skel.CreateJointsAttr(joints)
    skel.CreateJointNamesAttr(Vt.TokenArray(list(skeleton.joint_names)))
    world_r, world_t = rest_world_transforms(skeleton)
    skel.CreateBindTransformsAttr(Vt.Matrix4dArray.FromNumpy(_gf_matrices(world_r, world_t)))
    rest_r = quat.to_matrix(skeleton.rest_rotations)
    skel.CreateRestTransformsAttr(
        Vt.Matrix4dArray.FromNumpy(_gf_matrices(rest_r, skeleton.rest_translations))
    )
    UsdSkel.BindingAPI.Apply(skel.GetPrim()).CreateAnimationSourceRel().SetTargets([anim_path])

    anim = UsdSkel.Animation.Define(stage, anim_path)
    anim.CreateJointsAttr(joints)
    _author_samples(stage.GetRootLayer(), anim, clip)

    if clip.mesh is not None:
        _author_mesh(stage, root_path.AppendChild(MESH_NAME), skel_path, clip.mesh)
    return stage


def write_usd(path: Path, clip: Clip) -> None:
    """Write ``clip`` to ``path`` atomically; the extension picks the format (:data:`USD_EXTENSIONS`).

    Raises:
        ExportError: an unknown extension (the message lists the valid ones), or the file cannot
            be written. The target is then untouched and no temporary file is left behind.
    """
    path = Path(path)
    if path.suffix.lower() not in USD_EXTENSIONS:
        raise ExportError(
            f"{path}: not a USD file name; valid extensions are {', '.join(USD_EXTENSIONS)}"
        )
    stage = build_stage(clip)  # keep the stage alive: its root layer is only weakly held
    write_with(path, lambda tmp: _export_layer(stage.GetRootLayer(), tmp))


def _export_layer(layer: Sdf.Layer, tmp: Path) -> None:
    """Save ``layer`` to ``tmp``, whose extension (kept by ``write_with``) chooses the format."""
    try:
        ok = layer.Export(str(tmp))
    except Tf.ErrorException as exc:
        raise ExportError(f"{tmp}: USD could not write the file: {exc}") from exc
    if not ok:
        raise ExportError(f"{tmp}: USD could not write the file")


def _gf_matrices(rot: NDArray[np.float64], trans: NDArray[np.float64]) -> NDArray[np.float64]:
    """``(J, 4, 4)`` GfMatrix4d layouts of rotations ``(J, 3, 3)`` (column vectors) and translations.

    Gf multiplies row vectors (``p' = p M``), so the rotation goes in transposed and the
    translation in the last row.
    """
    out = np.zeros((rot.shape[0], 4, 4))
    out[:, :3, :3] = np.swapaxes(rot, -1, -2)
    out[:, 3, :3] = trans
    out[:, 3, 3] = 1.0
    return out


def _author_samples(layer: Sdf.Layer, anim: UsdSkel.Animation, clip: Clip) -> None:
    """Author translations, rotations and scales at every frame, straight into ``layer``."""
    n_joints = clip.skeleton.num_joints
    # Vt.QuatfArray.FromNumpy reads memory as (x, y, z, w): reorder our wxyz once for all frames.
    xyzw = np.ascontiguousarray(clip.local_rotations[..., [1, 2, 3, 0]], dtype=np.float32)
    trans = np.ascontiguousarray(clip.local_translations(), dtype=np.float32)
    ones = Vt.Vec3hArray.FromNumpy(np.ones((n_joints, 3), dtype=np.float16))
    t_path = anim.CreateTranslationsAttr().GetPath()
    r_path = anim.CreateRotationsAttr().GetPath()
    s_path = anim.CreateScalesAttr().GetPath()
    from_quats = Vt.QuatfArray.FromNumpy
    from_vecs = Vt.Vec3fArray.FromNumpy
    set_sample = layer.SetTimeSample
    with Sdf.ChangeBlock():
        for k in range(clip.num_frames):
            set_sample(t_path, k, from_vecs(trans[k]))
            set_sample(r_path, k, from_quats(xyzw[k]))
            set_sample(s_path, k, ones)


def _author_mesh(
    stage: Usd.Stage, mesh_path: Sdf.Path, skel_path: Sdf.Path, skin: SkinnedMesh
) -> None:
    mesh = UsdGeom.Mesh.Define(stage, mesh_path)
    points = skin.vertices.astype(np.float32)
    mesh.CreatePointsAttr(Vt.Vec3fArray.FromNumpy(points))
    mesh.CreateFaceVertexCountsAttr(Vt.IntArray.FromNumpy(np.full(len(skin.faces), 3, np.int32)))
    mesh.CreateFaceVertexIndicesAttr(Vt.IntArray.FromNumpy(skin.faces.reshape(-1)))
    # A capsule character is a polygon mesh; a subdivision surface would shrink it.
    mesh.CreateSubdivisionSchemeAttr(UsdGeom.Tokens.none)
    mesh.CreateExtentAttr(
        Vt.Vec3fArray([Gf.Vec3f(*map(float, points.min(0))), Gf.Vec3f(*map(float, points.max(0)))])
    )
    binding = UsdSkel.BindingAPI.Apply(mesh.GetPrim())
    binding.CreateSkeletonRel().SetTargets([skel_path])
    k = skin.influences_per_vertex
    binding.CreateJointIndicesPrimvar(False, k).Set(
        Vt.IntArray.FromNumpy(np.ascontiguousarray(skin.joint_indices.reshape(-1)))
    )
    binding.CreateJointWeightsPrimvar(False, k).Set(
        Vt.FloatArray.FromNumpy(np.ascontiguousarray(skin.joint_weights.reshape(-1)))
    )
    # The mesh is modelled in the skeleton's bind pose, in the same space: no extra transform.
    binding.CreateGeomBindTransformAttr(Gf.Matrix4d(1.0))


def _layer_data(clip: Clip) -> dict[str, object]:
    """``customLayerData``: what a pipeline needs besides the animation (segments, notes ...)."""
    return {
        KEY_VERSION: __version__,
        KEY_NOTES: Vt.StringArray(list(clip.notes)),
        KEY_SEGMENTS: {
            "gaits": Vt.StringArray([s.gait for s in clip.segments]),
            "startFrames": Vt.IntArray([s.start_frame for s in clip.segments]),
            "endFrames": Vt.IntArray([s.end_frame for s in clip.segments]),
        },
        KEY_EVENTS: {
            "kinds": Vt.StringArray([e.kind for e in clip.events]),
            "frames": Vt.IntArray([e.frame for e in clip.events]),
            "labels": Vt.StringArray([e.label for e in clip.events]),
        },
    }
