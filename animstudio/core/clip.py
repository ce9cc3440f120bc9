"""The Clip: the one exchange type every exporter and the preview read."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from types import MappingProxyType

import numpy as np
from numpy.typing import NDArray

from animstudio.core.mesh import SkinnedMesh
from animstudio.core.skeleton import Skeleton


@dataclass(frozen=True)
class ClipSegment:
    """Frames ``[start_frame, end_frame)`` of a clip play ``gait`` (as the script named it)."""

    gait: str
    start_frame: int
    end_frame: int

    def __post_init__(self) -> None:
        if not 0 <= self.start_frame < self.end_frame:
            raise ValueError(
                f"segment {self.gait!r}: need 0 <= start < end, got {self.start_frame}, {self.end_frame}"
            )

    @property
    def num_frames(self) -> int:
        return self.end_frame - self.start_frame


@dataclass(frozen=True)
class ClipEvent:
    """Something that happens at a frame: a push, a fall. ``label`` is for people (``push 350 N backward``)."""

    kind: str
    frame: int
    label: str


def frozen_curves(
    curves: Mapping[str, NDArray[np.float64]], num_frames: int
) -> Mapping[str, NDArray[np.float64]]:
    """Validate ``name -> (F,)`` curves, make them read-only float64 and wrap them in a read-only mapping."""
    out: dict[str, NDArray[np.float64]] = {}
    for name, values in curves.items():
        arr = np.asarray(values, dtype=np.float64)
        if arr.shape != (num_frames,):
            raise ValueError(f"curve {name!r} must have shape ({num_frames},), got {arr.shape}")
        arr.setflags(write=False)
        out[name] = arr
    return MappingProxyType(out)


@dataclass(frozen=True, eq=False)
class Clip:
    """An animation of a skinned character, frame-major.

    Attributes:
        fps: frames per second (time code ``k`` is at ``k / fps`` s).
        skeleton: the joint hierarchy; local transforms of non-root joints keep their rest translation.
        root_translations: ``(F, 3) float64`` metres, the root joint's translation in the world
            (Y up, +X is the direction of travel, +Z the character's right; docs/conventions.md).
        local_rotations: ``(F, J, 4) float32`` wxyz, ``T_parent_joint`` rotation of every joint
            (the root's is its world rotation).
        segments: the script's segments in frame order, covering ``[0, F)``.
        events: pushes, falls and other marks, for plots and the preview.
        curves: ``name -> (F,)`` curves for people (joint angles in ``*_deg``, neuron activity, ...).
        mesh: the skin bound to ``skeleton`` in rest pose (``None`` for a bare skeleton).
        notes: warnings a user must see (``walker fell at 12.43 s``), also written into exports.
    """

    fps: float
    skeleton: Skeleton
    root_translations: NDArray[np.float64]
    local_rotations: NDArray[np.float32]
    segments: tuple[ClipSegment, ...] = ()
    events: tuple[ClipEvent, ...] = ()
    curves: Mapping[str, NDArray[np.float64]] = field(default_factory=dict)
    mesh: SkinnedMesh | None = None
    notes: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        if not self.fps > 0:
            raise ValueError(f"fps must be positive, got {self.fps}")
        rt = np.asarray(self.root_translations, dtype=np.float64)
        lr = np.asarray(self.local_rotations, dtype=np.float32)
        n_frames = rt.shape[0] if rt.ndim == 2 else -1
        if rt.ndim != 2 or rt.shape[1] != 3 or n_frames < 1:
            raise ValueError(f"root_translations must be (F, 3) with F >= 1, got {rt.shape}")
        if lr.shape != (n_frames, self.skeleton.num_joints, 4):
            raise ValueError(
                f"local_rotations must be ({n_frames}, {self.skeleton.num_joints}, 4) wxyz, got {lr.shape}"
            )
        if not (np.all(np.isfinite(rt)) and np.all(np.isfinite(lr))):
            raise ValueError("clip contains non-finite values")
        covered = 0
        for seg in self.segments:
            if seg.start_frame != covered:
                raise ValueError(
                    f"segments must tile the clip: {seg.gait!r} starts at {seg.start_frame}, expected {covered}"
                )
            covered = seg.end_frame
        if self.segments and covered != n_frames:
            raise ValueError(f"segments cover {covered} frames, clip has {n_frames}")
        for ev in self.events:
            if not 0 <= ev.frame < n_frames:
                raise ValueError(f"event {ev.label!r} at frame {ev.frame} is outside the clip")
        rt.setflags(write=False)
        lr.setflags(write=False)
        object.__setattr__(self, "root_translations", rt)
        object.__setattr__(self, "local_rotations", lr)
        object.__setattr__(self, "curves", frozen_curves(self.curves, n_frames))
        object.__setattr__(self, "segments", tuple(self.segments))
        object.__setattr__(self, "events", tuple(self.events))
        object.__setattr__(self, "notes", tuple(self.notes))

    @property
    def num_frames(self) -> int:
        return int(self.root_translations.shape[0])

    @property
    def duration_s(self) -> float:
        """Time covered, counting each frame as 1/fps long."""
        return self.num_frames / self.fps

    def segment_at(self, frame: int) -> ClipSegment | None:
        """The segment playing at ``frame`` (``None`` for a clip without segments)."""
        for seg in self.segments:
            if seg.start_frame <= frame < seg.end_frame:
                return seg
        return None

    def local_translations(self) -> NDArray[np.float64]:
        """``(F, J, 3)`` local translations: rest offsets, with the root's replaced by ``root_translations``."""
        out = np.broadcast_to(
            self.skeleton.rest_translations, (self.num_frames, self.skeleton.num_joints, 3)
        ).copy()
        out[:, 0] = self.root_translations
        return out
