"""Capsule-and-ellipsoid skin for any skeleton, built with trimesh and bound by linear blend skinning.

A character's skin is a set of overlapping closed parts, each bound to one joint in the rest pose:

* a **capsule** per bone listed in ``radii``. A bone is named by its *child* joint: ``radii["left_knee"]``
  is the thigh, from ``left_hip`` to ``left_knee``, and it is moved by the parent joint
  (``left_hip``). Near either end a capsule's vertices blend smoothly with the neighbouring bones'
  joints (up to 3 influences), so an elbow bends instead of tearing;
* an **ellipsoid** per :class:`Ellipsoid` (head, torso, feet, a hexapod's body), bound rigidly to
  one joint.

Parts are not merged (no boolean union): a capsule-like character reads fine with overlapping parts.
Everything here is deterministic: the same skeleton and parts give the same mesh, byte for byte.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
import trimesh
from numpy.typing import NDArray

from animstudio.core.fk import rest_world_transforms
from animstudio.core.mesh import SkinnedMesh
from animstudio.core.skeleton import Skeleton

INFLUENCES = 3
"""Joint influences per vertex: the bone's own joint, the one above it and the one below it."""


@dataclass(frozen=True)
class Ellipsoid:
    """An ellipsoid bound rigidly to ``joint``.

    Attributes:
        joint: the joint that moves it.
        center_m: centre in the rest pose, world space (metres).
        radii_m: semi-axes along world X, Y, Z in the rest pose (metres).
    """

    joint: str
    center_m: tuple[float, float, float]
    radii_m: tuple[float, float, float]

    def __post_init__(self) -> None:
        if len(self.center_m) != 3 or len(self.radii_m) != 3:
            raise ValueError(f"ellipsoid on {self.joint!r}: centre and radii need 3 values each")
        if not all(r > 0 for r in self.radii_m):
            raise ValueError(
                f"ellipsoid on {self.joint!r}: radii must be positive, got {self.radii_m}"
            )


def build_capsule_mesh(
    skeleton: Skeleton,
    radii: Mapping[str, float],
    *,
    ellipsoids: Sequence[Ellipsoid] = (),
    sections: int = 12,
    ring_spacing_m: float = 0.03,
    blend_m: float = 0.04,
    ellipsoid_subdivisions: int = 2,
) -> SkinnedMesh:
    """Build a skinned mesh of capsules along bones plus rigid ellipsoids.

    Args:
        skeleton: the rest (bind) pose the mesh is built in.
        radii: ``child joint name -> radius (m)``: one capsule from the joint's parent to it, moved
            by the parent. Bones not listed get no capsule.
        ellipsoids: extra rigid parts (head, torso, feet).
        sections: vertices around each capsule ring.
        ring_spacing_m: the largest distance between rings along a capsule's straight part
            (linear blend skinning needs rings near joints to bend smoothly).
        blend_m: half-width of the blending zone around each joint.
        ellipsoid_subdivisions: icosphere subdivisions of each ellipsoid (2 gives 162 vertices).

    Returns:
        A :class:`SkinnedMesh` with ``INFLUENCES`` influences per vertex, outward-facing triangles.

    Raises:
        ValueError: an unknown joint, the root named as a bone, a non-positive radius or size, or
            a zero-length bone.
    """
    if sections < 3 or ring_spacing_m <= 0 or blend_m <= 0 or ellipsoid_subdivisions < 0:
        raise ValueError("sections >= 3, ring_spacing_m > 0, blend_m > 0 and subdivisions >= 0")
    _, rest_pos = rest_world_transforms(skeleton)
    children: dict[int, list[int]] = {j: [] for j in range(skeleton.num_joints)}
    for j, p in enumerate(skeleton.parents):
        if p >= 0:
            children[p].append(j)

    verts: list[NDArray[np.float64]] = []
    faces: list[NDArray[np.int64]] = []
    idx: list[NDArray[np.int32]] = []
    wts: list[NDArray[np.float64]] = []
    offset = 0
    for child_name, radius in radii.items():
        child = _joint(skeleton, child_name, "bone")
        owner = skeleton.parents[child]
        if owner < 0:
            raise ValueError(f"bone {child_name!r}: the root joint has no parent bone")
        if not radius > 0:
            raise ValueError(f"bone {child_name!r}: radius must be positive, got {radius}")
        start, end = rest_pos[owner], rest_pos[child]
        length = float(np.linalg.norm(end - start))
        if length < 1e-9:
            raise ValueError(f"bone {child_name!r} has zero length")
        part = _capsule(length, float(radius), sections, ring_spacing_m)
        axis = (end - start) / length
        placed = part.vertices @ _align_z(axis).T + start
        along = part.vertices[:, 2]  # distance along the bone from its start joint, in metres
        up = skeleton.parents[owner]  # the bone above moves with this joint's parent
        # Blend into the next bone only where the chain continues past the child joint.
        down = child if children[child] else -1
        ji, w = _blend_weights(along, length, owner, up, down, blend_m)
        verts.append(placed)
        faces.append(part.faces + offset)
        idx.append(ji)
        wts.append(w)
        offset += len(placed)

    for ell in ellipsoids:
        j = _joint(skeleton, ell.joint, "ellipsoid")
        sphere = trimesh.creation.icosphere(subdivisions=ellipsoid_subdivisions, radius=1.0)
        placed = sphere.vertices * np.asarray(ell.radii_m) + np.asarray(ell.center_m)
        n = len(placed)
        ji = np.full((n, INFLUENCES), j, dtype=np.int32)
        w = np.zeros((n, INFLUENCES))
        w[:, 0] = 1.0
        verts.append(placed)
        faces.append(sphere.faces + offset)
        idx.append(ji)
        wts.append(w)
        offset += n

    if not verts:
        raise ValueError("a mesh needs at least one bone radius or ellipsoid")
    return SkinnedMesh(
        vertices=np.concatenate(verts),
        faces=np.concatenate(faces).astype(np.int32),
        joint_indices=np.concatenate(idx),
        joint_weights=np.concatenate(wts).astype(np.float32),
    )


def _joint(skeleton: Skeleton, name: str, what: str) -> int:
    try:
        return skeleton.index(name)
    except KeyError as exc:
        raise ValueError(f"{what} {name!r}: {exc.args[0]}") from None


def _capsule(length: float, radius: float, sections: int, ring_spacing_m: float) -> trimesh.Trimesh:
    """A capsule along +Z from z=0 to z=length with hemispherical caps beyond both ends.

    Built by revolving its profile (trimesh.creation.revolve) rather than with
    ``trimesh.creation.capsule``, whose straight part has rings only at its two ends: skinning
    needs rings inside the blending zones to bend smoothly.
    """
    cap = np.linspace(-0.5 * np.pi, 0.0, max(3, sections // 3))
    n_mid = max(2, int(np.ceil(length / ring_spacing_m)) + 1)
    bottom = np.c_[radius * np.cos(cap), radius * np.sin(cap)]
    mid = np.c_[np.full(n_mid - 2, radius), np.linspace(0.0, length, n_mid)[1:-1]]
    top = np.c_[radius * np.cos(cap[::-1]), length - radius * np.sin(cap[::-1])]
    profile = np.vstack([bottom, mid, top])
    profile[[0, -1], 0] = 0.0  # the poles lie exactly on the axis, so revolve closes them
    return trimesh.creation.revolve(profile, sections=sections)


def _align_z(axis: NDArray[np.float64]) -> NDArray[np.float64]:
    """Rotation matrix (column vectors) taking +Z onto the unit vector ``axis``."""
    return np.asarray(trimesh.geometry.align_vectors([0.0, 0.0, 1.0], axis))[:3, :3]


def _smoothstep(x: NDArray[np.float64]) -> NDArray[np.float64]:
    t = np.clip(x, 0.0, 1.0)
    return t * t * (3.0 - 2.0 * t)


def _blend_weights(
    along: NDArray[np.float64],
    length: float,
    owner: int,
    up: int,
    down: int,
    blend_m: float,
) -> tuple[NDArray[np.int32], NDArray[np.float64]]:
    """Influences ``(owner, up, down)`` and weights for vertices ``along`` a bone (metres from its start).

    At a joint the two bones that meet there share their vertices 50/50, fading to the bone's own
    joint ``blend_m`` away from it; the bone on the other side of the joint uses the mirror rule,
    so the skin is continuous across the joint. ``up``/``down`` of ``-1`` mean no neighbour.
    """
    ones = np.ones_like(along)
    f_start = _smoothstep((along + blend_m) / (2.0 * blend_m)) if up >= 0 else ones
    f_end = _smoothstep((length - along + blend_m) / (2.0 * blend_m)) if down >= 0 else ones
    # The three raw weights sum to at least 1 (whichever of f_start, f_end is smaller is offset
    # by its complement), so normalising never divides by zero.
    w = np.stack([np.minimum(f_start, f_end), 1.0 - f_start, 1.0 - f_end], axis=1)
    w /= w.sum(axis=1, keepdims=True)
    ji = np.empty((len(along), INFLUENCES), dtype=np.int32)
    ji[:, 0] = owner
    ji[:, 1] = up if up >= 0 else owner  # weight 0 there; any valid index will do
    ji[:, 2] = down if down >= 0 else owner
    return ji, w
