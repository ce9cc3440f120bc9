"""The joint hierarchy of a character, in its rest (= bind) pose."""

from __future__ import annotations

import re
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

_TOKEN = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")  # a valid USD prim name / token


@dataclass(frozen=True, eq=False)
class Skeleton:
    """A joint tree in rest pose.

    Attributes:
        joint_names: ``(J,)`` unique names, valid USD identifiers. Joint 0 is the root.
        parents: ``(J,)`` parent index of each joint, ``-1`` for the root; ``parents[j] < j``
            (topological order), so one forward pass computes world transforms.
        rest_translations: ``(J, 3) float64`` metres, ``T_parent_joint`` translation in rest pose.
        rest_rotations: ``(J, 4) float64`` wxyz, ``T_parent_joint`` rotation in rest pose.
    """

    joint_names: tuple[str, ...]
    parents: tuple[int, ...]
    rest_translations: NDArray[np.float64]
    # None means identity for every joint; __post_init__ replaces it with the (J, 4) array.
    rest_rotations: NDArray[np.float64] = field(default=None)  # type: ignore[arg-type]

    def __post_init__(self) -> None:
        n = len(self.joint_names)
        if n == 0:
            raise ValueError("a skeleton needs at least one joint")
        if len(set(self.joint_names)) != n:
            raise ValueError("joint names must be unique")
        for name in self.joint_names:
            if not _TOKEN.match(name):
                raise ValueError(f"joint name {name!r} is not a valid USD identifier")
        if len(self.parents) != n or self.parents[0] != -1:
            raise ValueError(
                "parents must have one entry per joint and the root (joint 0) must be -1"
            )
        for j, p in enumerate(self.parents[1:], start=1):
            if not 0 <= p < j:
                raise ValueError(f"joint {self.joint_names[j]!r}: parent {p} must come before it")
        t = np.asarray(self.rest_translations, dtype=np.float64)
        if t.shape != (n, 3):
            raise ValueError(f"rest_translations must be ({n}, 3), got {t.shape}")
        r = (
            np.tile([1.0, 0.0, 0.0, 0.0], (n, 1))
            if self.rest_rotations is None
            else np.asarray(self.rest_rotations, dtype=np.float64)
        )
        if r.shape != (n, 4):
            raise ValueError(f"rest_rotations must be ({n}, 4) wxyz, got {r.shape}")
        t.setflags(write=False)
        r.setflags(write=False)
        object.__setattr__(self, "rest_translations", t)
        object.__setattr__(self, "rest_rotations", r)

    @property
    def num_joints(self) -> int:
        return len(self.joint_names)

    def index(self, name: str) -> int:
        """Index of joint ``name`` (``KeyError`` naming the joints if absent)."""
        try:
            return self.joint_names.index(name)
        except ValueError:
            raise KeyError(f"no joint {name!r}; joints are {', '.join(self.joint_names)}") from None

    @property
    def joint_paths(self) -> tuple[str, ...]:
        """UsdSkel joint paths (``pelvis/spine/chest``), one per joint, in joint order."""
        paths: list[str] = []
        for name, parent in zip(self.joint_names, self.parents, strict=True):
            paths.append(name if parent < 0 else f"{paths[parent]}/{name}")
        return tuple(paths)

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Skeleton):
            return NotImplemented
        return (
            self.joint_names == other.joint_names
            and self.parents == other.parents
            and np.array_equal(self.rest_translations, other.rest_translations)
            and np.array_equal(self.rest_rotations, other.rest_rotations)
        )

    __hash__ = None  # type: ignore[assignment]
