"""Read a UsdSkel file back into a :class:`~animstudio.core.clip.Clip` (the preview and batch use it).

Everything goes through ``UsdSkel.Cache``: the first SkelRoot (the default prim if it is one), its
first Skeleton and that skeleton's ``SkeletonQuery`` / ``AnimQuery``. Frames are the integer time
codes ``startTimeCode .. endTimeCode`` (the animation's sample range if the file has none); fps is
``timeCodesPerSecond``. Skinned meshes bound to the skeleton become the clip's mesh (several are
merged); segments, events and notes come back from the ``animstudio:*`` keys of
``customLayerData`` (docs/usd-export.md). Curves are not exported, so a read clip has none.

What a :class:`Clip` cannot hold is refused with a :class:`DataError` rather than silently dropped:
scaled joints, non-root joints whose translation changes over time, and a Skeleton prim with a
non-identity (or animated) transform of its own.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray
from pxr import Gf, Sdf, Tf, Usd, UsdGeom, UsdSkel

from animstudio.core import quat
from animstudio.core.clip import Clip, ClipEvent, ClipSegment
from animstudio.core.mesh import SkinnedMesh
from animstudio.core.skeleton import Skeleton
from animstudio.errors import DataError
from animstudio.export.usd import KEY_EVENTS, KEY_NOTES, KEY_SEGMENTS

_SCALE_TOL = 1e-4
MAX_FRAMES = 10_000_000
"""More time codes than this (over 3 days at 30 fps) is a corrupt time range, not an animation."""
_TRANSLATION_TOL_M = 1e-5


def read_clip(path: Path) -> Clip:
    """Read the UsdSkel animation in ``path`` (``.usda``/``.usdc``/``.usd``).

    Raises:
        DataError: the file is missing or not USD, holds no UsdSkel skeleton, or holds what a
            Clip cannot represent (the message says what and where).
    """
    path = Path(path)
    if not path.is_file():
        raise DataError(f"{path}: no such USD file")
    try:
        stage = Usd.Stage.Open(str(path))
    except Tf.ErrorException as exc:
        raise DataError(f"{path}: not a readable USD file: {_first_line(exc)}") from exc
    if stage is None:
        raise DataError(f"{path}: not a readable USD file")
    try:
        return _read_stage(stage, str(path))
    except Tf.ErrorException as exc:
        raise DataError(f"{path}: USD error while reading: {_first_line(exc)}") from exc
    except ValueError as exc:  # a Clip / Skeleton / SkinnedMesh invariant the file breaks
        raise DataError(f"{path}: {exc}") from exc


def _read_stage(stage: Usd.Stage, where: str) -> Clip:
    root = _skel_root(stage, where)
    cache = UsdSkel.Cache()
    cache.Populate(root, Usd.PrimDefaultPredicate)
    skel_prim = next(
        (p for p in Usd.PrimRange(root.GetPrim()) if p.IsA(UsdSkel.Skeleton)),
        None,
    )
    if skel_prim is None:
        raise DataError(f"{where}: SkelRoot {root.GetPath()} holds no Skeleton")
    to_world = UsdGeom.XformCache(Usd.TimeCode.Default()).GetLocalToWorldTransform(skel_prim)
    if not Gf.IsClose(to_world, Gf.Matrix4d(1.0), 1e-9):
        # A clip's root transform is its world transform; a moved Skeleton prim would need folding in.
        raise DataError(f"{where}: skeleton {skel_prim.GetPath()} has a non-identity transform")
    skel_query = cache.GetSkelQuery(UsdSkel.Skeleton(skel_prim))
    if not skel_query:
        raise DataError(f"{where}: skeleton {skel_prim.GetPath()} is not valid UsdSkel")
    joint_paths = [str(p) for p in skel_query.GetJointOrder()]
    names = tuple(Sdf.Path(p).name for p in joint_paths)
    parents = tuple(int(p) for p in skel_query.GetTopology().GetParentIndices())
    if len(set(names)) != len(names):
        raise DataError(f"{where}: joint names (last path elements) are not unique")

    rest = _matrices(skel_query.ComputeJointLocalTransforms(Usd.TimeCode.Default(), True))
    rest_rot = quat.from_matrix(np.swapaxes(rest[:, :3, :3], -1, -2))
    rest_trans = rest[:, 3, :3]

    fps = float(stage.GetTimeCodesPerSecond())
    frames = _frames(stage, skel_query, where)
    trans, rots = _animation(skel_query, joint_paths, frames, rest_trans, rest_rot, where)

    moving = np.abs(trans[:, 1:] - trans[:1, 1:]).max(initial=0.0)
    if moving > _TRANSLATION_TOL_M:
        raise DataError(
            f"{where}: non-root joints translate over time (by {moving:.3g} m); a clip animates "
            "only the root's translation"
        )
    # Non-root translations are constant: they are the skeleton's offsets as animated.
    rest_trans = np.concatenate([rest_trans[:1], trans[0, 1:]])
    skeleton = Skeleton(names, parents, rest_trans, rest_rot)
    segments, events, notes = _layer_data(stage.GetRootLayer().customLayerData, where)
    return Clip(
        fps=fps,
        skeleton=skeleton,
        root_translations=trans[:, 0],
        local_rotations=rots.astype(np.float32),
        segments=segments,
        events=events,
        mesh=_mesh(cache, root, skel_prim, joint_paths, where),
        notes=notes,
    )


def _frames(stage: Usd.Stage, skel_query: UsdSkel.SkeletonQuery, where: str) -> NDArray[np.int64]:
    """Integer time codes to sample: the stage's time range, else the animation's samples."""
    if stage.HasAuthoredTimeCodeRange():
        start, end = stage.GetStartTimeCode(), stage.GetEndTimeCode()
    else:  # files from other tools may leave the range out
        anim_query = skel_query.GetAnimQuery()
        times = list(anim_query.GetJointTransformTimeSamples()) if anim_query else []
        start, end = (min(times), max(times)) if times else (0.0, 0.0)
    if not (np.isfinite(start) and np.isfinite(end)) or end - start + 1 > MAX_FRAMES:
        raise DataError(f"{where}: unusable time range {start} .. {end}")
    first = int(np.floor(start))
    return np.arange(first, max(first, int(np.floor(end))) + 1)


def _skel_root(stage: Usd.Stage, where: str) -> UsdSkel.Root:
    default = stage.GetDefaultPrim()
    if default and default.IsA(UsdSkel.Root):
        return UsdSkel.Root(default)
    for prim in stage.Traverse():
        if prim.IsA(UsdSkel.Root):
            return UsdSkel.Root(prim)
    raise DataError(f"{where}: no UsdSkel SkelRoot with a Skeleton on this stage")


def _matrices(vt_matrices: Any) -> NDArray[np.float64]:
    return np.array(vt_matrices, dtype=np.float64).reshape(-1, 4, 4)


def _animation(
    skel_query: UsdSkel.SkeletonQuery,
    joint_paths: list[str],
    frames: NDArray[np.int64],
    rest_trans: NDArray[np.float64],
    rest_rot: NDArray[np.float64],
    where: str,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Per-frame local translations ``(F, J, 3)`` and rotations ``(F, J, 4)`` wxyz, skeleton order.

    Joints the animation does not name keep their rest transform (UsdSkel's rule).
    """
    n_frames, n_joints = len(frames), len(joint_paths)
    trans = np.broadcast_to(rest_trans, (n_frames, n_joints, 3)).copy()
    rots = np.broadcast_to(rest_rot, (n_frames, n_joints, 4)).copy()
    anim_query = skel_query.GetAnimQuery()
    if not anim_query:
        return trans, rots
    index = {p: j for j, p in enumerate(joint_paths)}
    anim_order = [str(p) for p in anim_query.GetJointOrder()]
    src = np.array([i for i, p in enumerate(anim_order) if p in index], dtype=np.intp)
    dst = np.array([index[p] for p in anim_order if p in index], dtype=np.intp)
    compute = anim_query.ComputeJointLocalTransformComponents
    samples = [compute(Usd.TimeCode(float(frame))) for frame in frames]
    n_anim = len(anim_order)
    for frame, (t, r, s) in zip(frames, samples, strict=True):
        if len(t) != n_anim or len(r) != n_anim or len(s) not in (0, n_anim):
            raise DataError(
                f"{where}: animation {anim_query.GetPrim().GetPath()} at time {frame}: "
                f"{len(r)} rotations / {len(t)} translations / {len(s)} scales for {n_anim} joints"
            )
    # One conversion per component for all frames: per-frame numpy conversions cost more than USD.
    scales = [s for _, _, s in samples if len(s)]
    if scales and np.abs(np.array(scales, dtype=np.float64) - 1.0).max() > _SCALE_TOL:
        raise DataError(f"{where}: joints are scaled; a clip cannot hold scale")
    trans[:, dst] = np.array([t for t, _, _ in samples], dtype=np.float64)[:, src]
    # Vt quaternions come out as (x, y, z, w): move w to the front.
    xyzw = np.array([r for _, r, _ in samples], dtype=np.float64)[:, src]
    rots[:, dst] = np.roll(xyzw, 1, axis=-1)
    return trans, rots


def _mesh(
    cache: UsdSkel.Cache,
    root: UsdSkel.Root,
    skel_prim: Usd.Prim,
    joint_paths: list[str],
    where: str,
) -> SkinnedMesh | None:
    """The skinned meshes bound to ``skel_prim``, merged, in bind pose (``None`` if there are none)."""
    index = {p: j for j, p in enumerate(joint_paths)}
    parts: list[
        tuple[NDArray[np.float64], NDArray[np.int64], NDArray[np.int32], NDArray[np.float64]]
    ] = []
    for binding in cache.ComputeSkelBindings(root, Usd.PrimDefaultPredicate):
        if binding.GetSkeleton().GetPrim() != skel_prim:
            continue
        for query in binding.GetSkinningTargets():
            prim = query.GetPrim()
            if not prim.IsA(UsdGeom.Mesh) or not query.HasJointInfluences():
                continue
            parts.append(_mesh_part(UsdGeom.Mesh(prim), query, index, where))
    if not parts:
        return None
    k = max(p[2].shape[1] for p in parts)
    verts, faces, idx, wts = [], [], [], []
    offset = 0
    for v, f, ji, jw in parts:
        pad = k - ji.shape[1]  # merged meshes may differ in influence counts: pad with weight 0
        verts.append(v)
        faces.append(f + offset)
        idx.append(np.pad(ji, ((0, 0), (0, pad))))
        wts.append(np.pad(jw, ((0, 0), (0, pad))))
        offset += len(v)
    return SkinnedMesh(
        vertices=np.concatenate(verts),
        faces=np.concatenate(faces).astype(np.int32),
        joint_indices=np.concatenate(idx).astype(np.int32),
        joint_weights=np.concatenate(wts).astype(np.float32),
    )


def _mesh_part(
    mesh: UsdGeom.Mesh,
    query: UsdSkel.SkinningQuery,
    index: dict[str, int],
    where: str,
) -> tuple[NDArray[np.float64], NDArray[np.int64], NDArray[np.int32], NDArray[np.float64]]:
    path = mesh.GetPath()
    points = np.asarray(mesh.GetPointsAttr().Get() or [], dtype=np.float64).reshape(-1, 3)
    counts = np.asarray(mesh.GetFaceVertexCountsAttr().Get() or [], dtype=np.int64)
    flat = np.asarray(mesh.GetFaceVertexIndicesAttr().Get() or [], dtype=np.int64)
    if counts.sum() != len(flat) or (counts < 3).any():
        raise DataError(f"{where}: mesh {path} has inconsistent face counts and indices")
    faces = _triangulate(counts, flat)
    bind = _matrices([query.GetGeomBindTransform()])[0]
    vertices = points @ bind[:3, :3] + bind[3, :3]  # Gf row-vector convention: p' = p M

    k = query.GetNumInfluencesPerComponent()
    ji_flat, jw_flat = query.ComputeJointInfluences()
    ji = np.asarray(ji_flat, dtype=np.int64).reshape(-1, k)
    jw = np.asarray(jw_flat, dtype=np.float64).reshape(-1, k)
    if query.IsRigidlyDeformed():  # constant interpolation: one set of influences for all points
        ji = np.repeat(ji[:1], len(points), axis=0)
        jw = np.repeat(jw[:1], len(points), axis=0)
    if len(ji) != len(points):
        raise DataError(f"{where}: mesh {path}: {len(ji)} influence rows for {len(points)} points")
    order = query.GetJointOrder()
    if order:  # the mesh names its own joint order (skel:joints): map it onto the skeleton's
        try:
            remap = np.array([index[str(p)] for p in order], dtype=np.int64)
        except KeyError as exc:
            raise DataError(
                f"{where}: mesh {path} is bound to unknown joint {exc.args[0]}"
            ) from None
        ji = remap[ji]
    if ji.min(initial=0) < 0 or ji.max(initial=0) >= len(index):
        raise DataError(f"{where}: mesh {path} has joint indices outside the skeleton")
    totals = jw.sum(axis=1, keepdims=True)
    if (totals <= 0).any():
        raise DataError(f"{where}: mesh {path} has points with no joint weight")
    return vertices, faces, ji.astype(np.int32), jw / totals


def _triangulate(counts: NDArray[np.int64], flat: NDArray[np.int64]) -> NDArray[np.int64]:
    """Triangles from polygons (fan triangulation; our own meshes are triangles already)."""
    if (counts == 3).all():
        return flat.reshape(-1, 3)
    starts = np.concatenate([[0], np.cumsum(counts)[:-1]])
    tris = [
        (flat[s], flat[s + i], flat[s + i + 1])
        for s, c in zip(starts.tolist(), counts.tolist(), strict=True)
        for i in range(1, c - 1)
    ]
    return np.array(tris, dtype=np.int64).reshape(-1, 3)


def _layer_data(
    data: dict[str, Any], where: str
) -> tuple[tuple[ClipSegment, ...], tuple[ClipEvent, ...], tuple[str, ...]]:
    """Segments, events and notes from ``customLayerData`` (absent keys give empty tuples)."""
    try:
        seg = data.get(KEY_SEGMENTS, {})
        segments = tuple(
            ClipSegment(str(g), int(s), int(e))
            for g, s, e in zip(
                seg.get("gaits", []),
                seg.get("startFrames", []),
                seg.get("endFrames", []),
                strict=True,
            )
        )
        ev = data.get(KEY_EVENTS, {})
        events = tuple(
            ClipEvent(str(k), int(f), str(label))
            for k, f, label in zip(
                ev.get("kinds", []), ev.get("frames", []), ev.get("labels", []), strict=True
            )
        )
        notes = tuple(str(n) for n in data.get(KEY_NOTES, []))
    except (AttributeError, TypeError, ValueError) as exc:
        raise DataError(f"{where}: malformed animstudio customLayerData: {exc}") from exc
    return segments, events, notes


def _first_line(exc: BaseException) -> str:
    return str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
