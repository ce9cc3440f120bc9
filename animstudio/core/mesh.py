"""A linear-blend-skinned triangle mesh bound to a :class:`Skeleton` in rest pose."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray


@dataclass(frozen=True, eq=False)
class SkinnedMesh:
    """Triangle mesh with per-vertex joint influences.

    Attributes:
        vertices: ``(V, 3) float64`` metres, in the skeleton's rest (bind) pose, world space.
        faces: ``(T, 3) int32`` counter-clockwise vertex indices (outward normals).
        joint_indices: ``(V, K) int32`` influencing joints per vertex (K = influences per vertex).
        joint_weights: ``(V, K) float32``, each row sums to 1.
    """

    vertices: NDArray[np.float64]
    faces: NDArray[np.int32]
    joint_indices: NDArray[np.int32]
    joint_weights: NDArray[np.float32]

    def __post_init__(self) -> None:
        v = np.asarray(self.vertices, dtype=np.float64)
        f = np.asarray(self.faces, dtype=np.int32)
        ji = np.asarray(self.joint_indices, dtype=np.int32)
        jw = np.asarray(self.joint_weights, dtype=np.float32)
        if v.ndim != 2 or v.shape[1] != 3:
            raise ValueError(f"vertices must be (V, 3), got {v.shape}")
        if f.ndim != 2 or f.shape[1] != 3 or (f.size and (f.min() < 0 or f.max() >= len(v))):
            raise ValueError("faces must be (T, 3) indices into vertices")
        if ji.shape != jw.shape or ji.ndim != 2 or ji.shape[0] != len(v):
            raise ValueError("joint_indices and joint_weights must both be (V, K)")
        if not np.allclose(jw.sum(axis=1), 1.0, atol=1e-5):
            raise ValueError("joint weights must sum to 1 per vertex")
        for name, arr in (
            ("vertices", v),
            ("faces", f),
            ("joint_indices", ji),
            ("joint_weights", jw),
        ):
            arr.setflags(write=False)
            object.__setattr__(self, name, arr)

    @property
    def influences_per_vertex(self) -> int:
        return int(self.joint_indices.shape[1])
