"""BVH export (Biovision Hierarchy) for tools that live on BVH (docs/batch.md).

Conventions of the file written here:

- **Y up**, +X forward, +Z the character's right (docs/conventions.md), **metres**.
- HIERARCHY: the root joint has 6 channels ``Xposition Yposition Zposition Zrotation Xrotation
  Yrotation``, every other joint 3 channels ``Zrotation Xrotation Yrotation``: the joint's
  local rotation is ``Rz(z) @ Rx(x) @ Ry(y)`` (column vectors, angles in degrees), the usual
  ZXY order of motion-capture BVH.
- The root's ``OFFSET`` is ``0 0 0`` and its position channels are its absolute world position
  in metres. Readers disagree on whether root position channels add to the root offset
  (Blender treats them as absolute); a zero root offset makes both readings agree.
- BVH has no rest rotation: with all channels zero every joint frame is aligned with the world
  axes. A skeleton whose rest pose has rotations is therefore re-expressed in world-aligned
  joint frames. With ``Q_j`` the rest world rotation of joint ``j`` and ``p`` its parent,
  the ``OFFSET`` is ``Q_p t_j`` (the rest translation turned into world axes) and the frame's
  rotation is ``Q_p R_j Q_j^T`` (``R_j`` the clip's local rotation). World positions are then
  exactly those of :func:`animstudio.core.fk.joint_positions`, and all-zero channels show the
  rest pose.
- A joint without children gets an ``End Site`` continuing its bone by a quarter of its rest
  offset (5 cm along +Y for a zero-length bone): BVH needs one; it carries no motion.
- ``Frame Time`` is ``1 / fps`` seconds, 10 decimals (so 1/24 reads back as 24.0 fps in float32).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from animstudio.core import quat
from animstudio.core.clip import Clip
from animstudio.core.fk import rest_world_transforms
from animstudio.export import atomic

ROTATION_ORDER = "ZXY"
"""Order of the rotation channels: local rotation = Rz @ Rx @ Ry."""

_END_SITE_FRACTION = 0.25
_END_SITE_DEFAULT_M = 0.05


def euler_zxy_deg(matrices: NDArray[np.float64]) -> NDArray[np.float64]:
    """``(..., 3)`` angles ``(z, x, y)`` in degrees with ``R = Rz(z) @ Rx(x) @ Ry(y)``.

    ``matrices`` is ``(..., 3, 3)``. For ``R = Rz Rx Ry``: ``R[2,1] = sin x``,
    ``R[2,0] = -cos x sin y``, ``R[2,2] = cos x cos y``, ``R[0,1] = -sin z cos x``,
    ``R[1,1] = cos z cos x``. ``x`` and ``y`` come from the last row; ``z`` from
    ``R @ Ry(y)^T @ Rx(x)^T = Rz(z)``, which stays exact near gimbal lock (``cos x = 0``), where
    the last row no longer determines ``y`` and any ``y`` paired with the matching ``z`` is right.
    """
    m = np.asarray(matrices, dtype=np.float64)
    x = np.arctan2(m[..., 2, 1], np.hypot(m[..., 2, 0], m[..., 2, 2]))
    y = np.arctan2(-m[..., 2, 0], m[..., 2, 2])
    cy, sy = np.cos(y), np.sin(y)
    # First column of R @ (Rx Ry)^T is R @ (first row of Rx Ry) = R @ (cy, 0, sy) = (cos z, sin z, 0).
    cz = m[..., 0, 0] * cy + m[..., 0, 2] * sy
    sz = m[..., 1, 0] * cy + m[..., 1, 2] * sy
    z = np.arctan2(sz, cz)
    return np.degrees(np.stack([z, x, y], axis=-1))


def bvh_motion(clip: Clip) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """World-aligned BVH offsets ``(J, 3)`` m and channel values ``(F, 3 + 3 J)`` of ``clip``.

    Channel columns follow the HIERARCHY order (joint order): root position (m), then
    ``z, x, y`` degrees per joint. Each angle is unwrapped over time so that readers
    interpolating between frames never swing the long way round.
    """
    skel = clip.skeleton
    rest_m, _ = rest_world_transforms(skel)  # Q_j
    local_m = quat.to_matrix(clip.local_rotations.astype(np.float64))  # (F, J, 3, 3) R_j
    offsets = np.zeros((skel.num_joints, 3))
    bvh_local = np.empty_like(local_m)
    for j, p in enumerate(skel.parents):
        q_parent = np.eye(3) if p < 0 else rest_m[p]
        if p >= 0:
            offsets[j] = q_parent @ skel.rest_translations[j]
        bvh_local[:, j] = q_parent @ local_m[:, j] @ rest_m[j].T
    angles = np.unwrap(euler_zxy_deg(bvh_local), axis=0, period=360.0)
    channels = np.concatenate([clip.root_translations, angles.reshape(clip.num_frames, -1)], axis=1)
    return offsets, channels


def build_bvh(clip: Clip) -> str:
    """The BVH text of ``clip`` (conventions in the module docstring)."""
    skel = clip.skeleton
    offsets, channels = bvh_motion(clip)
    children: list[list[int]] = [[] for _ in range(skel.num_joints)]
    for j, p in enumerate(skel.parents):
        if p >= 0:
            children[p].append(j)

    lines = ["HIERARCHY"]

    def emit(j: int, depth: int) -> None:
        pad = "  " * depth
        keyword = "ROOT" if skel.parents[j] < 0 else "JOINT"
        lines.append(f"{pad}{keyword} {skel.joint_names[j]}")
        lines.append(f"{pad}{{")
        lines.append(f"{pad}  OFFSET {_fmt(offsets[j])}")
        if skel.parents[j] < 0:
            lines.append(
                f"{pad}  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation"
            )
        else:
            lines.append(f"{pad}  CHANNELS 3 Zrotation Xrotation Yrotation")
        for c in children[j]:
            emit(c, depth + 1)
        if not children[j]:
            lines.append(f"{pad}  End Site")
            lines.append(f"{pad}  {{")
            lines.append(f"{pad}    OFFSET {_fmt(_end_site(offsets[j]))}")
            lines.append(f"{pad}  }}")
        lines.append(f"{pad}}}")

    # MOTION columns must follow the HIERARCHY's depth-first order, which differs from joint
    # order for some trees (parents (-1, 0, 0, 1) emits 0, 1, 3, 2): permute the columns.
    emit(0, 0)
    order = _depth_first(children)
    cols = [0, 1, 2] + [3 + 3 * j + k for j in order for k in range(3)]
    lines.append("MOTION")
    lines.append(f"Frames: {clip.num_frames}")
    lines.append(f"Frame Time: {1.0 / clip.fps:.10f}")  # 10 decimals: 1/24 reads back as 24.0
    for row in channels[:, cols]:
        lines.append(_fmt(row))
    return "\n".join(lines) + "\n"


def write_bvh(path: Path, clip: Clip) -> None:
    """Write ``clip`` as BVH to ``path`` atomically (a crash never leaves a truncated file)."""
    atomic.write_text(Path(path), build_bvh(clip))


def _depth_first(children: list[list[int]]) -> list[int]:
    order: list[int] = []
    stack = [0]
    while stack:
        j = stack.pop()
        order.append(j)
        stack.extend(reversed(children[j]))
    return order


def _end_site(offset: NDArray[np.float64]) -> NDArray[np.float64]:
    length = float(np.linalg.norm(offset))
    if length < 1e-9:
        return np.array([0.0, _END_SITE_DEFAULT_M, 0.0])
    return offset * _END_SITE_FRACTION


def _fmt(values: NDArray[np.float64]) -> str:
    # 6 decimals: 1 µm for positions, 1e-6 degree for angles (< 1e-7 m at the end of a 1 m chain).
    return " ".join(f"{v:.6f}" for v in np.asarray(values).ravel())
