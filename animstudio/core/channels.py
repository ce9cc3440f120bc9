"""GaitChannels: what an engine produces, before a rig turns it into a Clip."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from animstudio.core.clip import ClipEvent, ClipSegment, frozen_curves


@dataclass(frozen=True, eq=False)
class GaitChannels:
    """Per-frame joint angles and root motion from a motion engine.

    Attributes:
        fps: frame rate of every array here.
        character: which rig reads these channels (``"humanoid"`` or ``"hexapod"``).
        angles: ``name -> (F,) float64`` joint/segment angles, unit in the name. The humanoid
            rig reads ``{left,right}_{thigh,shank,foot}_deg`` (thesis Q, F, Y: thigh and shank
            from the downward vertical, positive = distal end ahead; foot from the horizontal,
            positive = toe up); the hexapod rig documents its own names.
        root_position_m: ``(F, 3) float64`` world position of the root (hip/pelvis or body centre),
            +X forward, +Y up, +Z right.
        contacts: ``name -> (F,) bool`` ground contact per foot (``left_foot``, ``right_foot``, ``L1`` ...).
        segments: script segments, tiling ``[0, F)``.
        events: pushes, falls, ... at frames.
        signals: ``name -> (F,) float64`` engine-internal curves worth plotting (neuron activity ...).
        notes: warnings a user must see (a fall and its time).
    """

    fps: float
    character: str
    angles: Mapping[str, NDArray[np.float64]]
    root_position_m: NDArray[np.float64]
    contacts: Mapping[str, NDArray[np.bool_]] = field(default_factory=dict)
    segments: tuple[ClipSegment, ...] = ()
    events: tuple[ClipEvent, ...] = ()
    signals: Mapping[str, NDArray[np.float64]] = field(default_factory=dict)
    notes: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        root = np.asarray(self.root_position_m, dtype=np.float64)
        if root.ndim != 2 or root.shape[1] != 3 or root.shape[0] < 1:
            raise ValueError(f"root_position_m must be (F, 3) with F >= 1, got {root.shape}")
        n = root.shape[0]
        if not np.all(np.isfinite(root)):
            raise ValueError("root_position_m contains non-finite values")
        root.setflags(write=False)
        object.__setattr__(self, "root_position_m", root)
        object.__setattr__(self, "angles", frozen_curves(self.angles, n))
        object.__setattr__(self, "signals", frozen_curves(self.signals, n))
        contacts = {}
        for name, c in self.contacts.items():
            arr = np.asarray(c, dtype=bool)
            if arr.shape != (n,):
                raise ValueError(f"contact {name!r} must be ({n},), got {arr.shape}")
            arr.setflags(write=False)
            contacts[name] = arr
        object.__setattr__(self, "contacts", contacts)
        for name, arr in self.angles.items():
            if not np.all(np.isfinite(arr)):
                raise ValueError(f"angle channel {name!r} contains non-finite values")

    @property
    def num_frames(self) -> int:
        return int(self.root_position_m.shape[0])
