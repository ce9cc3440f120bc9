"""The shipped humanoid: skeleton, skinned mesh, and the mapping from sagittal gait channels to a Clip.

Proportions: the leg from :mod:`animstudio.rig.proportions`; torso, head and arms from Winter's
segment fractions of the height H (*Biomechanics and Motor Control of Human Movement*, fig. 4.1):
shoulder (acromion) height 0.818 H, chin 0.870 H, upper arm 0.186 H, forearm 0.146 H, hand 0.108 H,
shoulder width 0.259 H.

Rest pose (= bind pose): standing, legs straight down, feet forward along +X, arms hanging slightly
abducted, every joint frame aligned with the world (identity rest rotations). Axes follow
docs/conventions.md: +Y up, +X forward, +Z the character's right, so left joints are at -Z.

Channel mapping (:func:`clip_from_channels`), all angles about +Z (the sagittal axis):

* hip local rotation = ``thigh``; knee = ``shank - thigh``; so the shank's world angle is ``shank``;
* ankle = ``foot - FOOT_REST_DEG - shank``: the ankle -> toe-joint line then makes ``foot`` with the
  horizontal (it makes ``FOOT_REST_DEG`` in the rest pose);
* toe joint = ``FOOT_REST_DEG - foot`` while the foot is in contact with its heel up (``foot <
  FOOT_REST_DEG``), which keeps the toes flat on the floor at push-off; otherwise neutral, reached
  by an exponential relaxation (``TOE_RELAX_S``) after lift-off so the toes do not pop;
* arms swing opposite the legs: shoulder = ``ARM_SWING`` x the other side's thigh about its
  running mean (a centred ``ARM_CENTRE_S`` window), so the arms swing symmetrically about hanging
  even when a gait's thigh angle is mostly forward (climbing); the elbow flexes ``ELBOW_BASE_DEG``
  plus ``ELBOW_FORWARD_GAIN`` x the forward part of the swing;
* trunk: the pelvis keeps the channels' root exactly (no rotation, so the legs are exactly the
  channels'); the spine leans forward with walking speed and the chest counter-rotates about +Y
  with the legs (right shoulder forward when the left thigh is forward).
"""

from __future__ import annotations

import functools
from typing import Any

import numpy as np
from numpy.typing import NDArray

from animstudio.core import quat
from animstudio.core.channels import GaitChannels
from animstudio.core.clip import Clip
from animstudio.core.mesh import SkinnedMesh
from animstudio.core.skeleton import Skeleton
from animstudio.rig.mesh import Ellipsoid, build_capsule_mesh
from animstudio.rig.proportions import (
    ANKLE_HEIGHT_M,
    FOOT_M,
    FOOT_REST_DEG,
    HEIGHT_M,
    HIP_HALF_WIDTH_M,
    SHANK_M,
    STANDING_HIP_HEIGHT_M,
    THIGH_M,
)

SHOULDER_HEIGHT_M = 0.818 * HEIGHT_M
CHIN_HEIGHT_M = 0.870 * HEIGHT_M
UPPER_ARM_M = 0.186 * HEIGHT_M
FOREARM_M = 0.146 * HEIGHT_M
HAND_M = 0.108 * HEIGHT_M
UPPER_ARM_RADIUS_M = 0.045
SHOULDER_HALF_WIDTH_M = 0.5 * 0.259 * HEIGHT_M - UPPER_ARM_RADIUS_M
"""Shoulder-joint centre: one upper-arm radius inside Winter's (outer) shoulder width."""
ARM_ABDUCTION_DEG = 4.0
"""The arms hang this far out of the vertical so the hands clear the thighs."""
SPINE_ABOVE_HIP_M = 0.10
"""Lumbar joint above the hip-joint centre."""
CHEST_ABOVE_HIP_M = 0.30
"""Thoracic joint above the hip-joint centre."""
TOE_LENGTH_M = 0.06
"""Toe joint (metatarsal heads) to the toe tip."""

ARM_SWING = 0.6
"""Shoulder angle per degree of the opposite thigh angle (about its running mean)."""
ARM_CENTRE_S = 1.0
"""Window of the thigh's running mean the arm swing is centred on (about one stride)."""
ELBOW_BASE_DEG = 10.0
ELBOW_FORWARD_GAIN = 0.5
CHEST_TWIST = 0.15
"""Chest rotation about +Y per degree of (left thigh - right thigh)."""
LEAN_DEG_PER_MPS = 1.5
LEAN_MAX_DEG = 8.0
LEAN_SMOOTH_S = 0.5
TOE_RELAX_S = 0.06

_SIDES = {"left": -1.0, "right": 1.0}  # sign of Z


def _build_skeleton() -> Skeleton:
    foot_rest = np.radians(FOOT_REST_DEG)
    abd = np.radians(ARM_ABDUCTION_DEG)
    joints: list[tuple[str, str | None, tuple[float, float, float]]] = [
        ("pelvis", None, (0.0, STANDING_HIP_HEIGHT_M, 0.0)),
        ("spine", "pelvis", (0.0, SPINE_ABOVE_HIP_M, 0.0)),
        ("chest", "spine", (0.0, CHEST_ABOVE_HIP_M - SPINE_ABOVE_HIP_M, 0.0)),
        (
            "neck",
            "chest",
            (0.0, SHOULDER_HEIGHT_M - STANDING_HIP_HEIGHT_M - CHEST_ABOVE_HIP_M, 0.0),
        ),
        ("head", "neck", (0.0, CHIN_HEIGHT_M - SHOULDER_HEIGHT_M, 0.0)),
        ("head_end", "head", (0.0, HEIGHT_M - CHIN_HEIGHT_M, 0.0)),
    ]
    for side, z in _SIDES.items():
        joints += [
            (f"{side}_hip", "pelvis", (0.0, 0.0, z * HIP_HALF_WIDTH_M)),
            (f"{side}_knee", f"{side}_hip", (0.0, -THIGH_M, 0.0)),
            (f"{side}_ankle", f"{side}_knee", (0.0, -SHANK_M, 0.0)),
            (
                f"{side}_toe",
                f"{side}_ankle",
                (FOOT_M * np.cos(foot_rest), FOOT_M * np.sin(foot_rest), 0.0),
            ),
            (f"{side}_toe_end", f"{side}_toe", (TOE_LENGTH_M, 0.0, 0.0)),
        ]
    for side, z in _SIDES.items():
        joints += [
            (
                f"{side}_shoulder",
                "chest",
                (
                    0.0,
                    SHOULDER_HEIGHT_M - STANDING_HIP_HEIGHT_M - CHEST_ABOVE_HIP_M,
                    z * SHOULDER_HALF_WIDTH_M,
                ),
            ),
            (
                f"{side}_elbow",
                f"{side}_shoulder",
                (0.0, -UPPER_ARM_M * np.cos(abd), z * UPPER_ARM_M * np.sin(abd)),
            ),
            (
                f"{side}_wrist",
                f"{side}_elbow",
                (0.0, -FOREARM_M * np.cos(abd), z * FOREARM_M * np.sin(abd)),
            ),
            # The hand bone ends mid-fingers, so its capsule's rounded cap reaches the fingertips.
            (f"{side}_hand_end", f"{side}_wrist", (0.0, -0.8 * HAND_M, 0.0)),
        ]
    names = tuple(n for n, _, _ in joints)
    parents = tuple(-1 if p is None else names.index(p) for _, p, _ in joints)
    return Skeleton(names, parents, np.array([t for _, _, t in joints], dtype=np.float64))


HUMANOID: Skeleton = _build_skeleton()
"""The shipped humanoid skeleton: 24 joints, the 19 animated ones plus 5 end joints (head, toes, hands)."""

HUMANOID_RADII: dict[str, float] = {
    "head": 0.05,  # the neck, from neck to head
    "left_knee": 0.075,
    "left_ankle": 0.055,
    "left_elbow": UPPER_ARM_RADIUS_M,
    "left_wrist": 0.038,
    "left_hand_end": 0.035,
}
HUMANOID_RADII |= {
    k.replace("left_", "right_"): v for k, v in HUMANOID_RADII.items() if "left_" in k
}


def _humanoid_ellipsoids() -> list[Ellipsoid]:
    hip = STANDING_HIP_HEIGHT_M
    parts = [
        Ellipsoid("pelvis", (0.0, hip + 0.03, 0.0), (0.11, 0.11, 0.17)),
        Ellipsoid("spine", (0.0, hip + 0.17, 0.0), (0.10, 0.14, 0.15)),
        Ellipsoid("chest", (0.0, hip + 0.37, 0.0), (0.11, 0.17, 0.17)),
        Ellipsoid("head", (0.02, 0.5 * (CHIN_HEIGHT_M + HEIGHT_M), 0.0), (0.10, 0.12, 0.085)),
    ]
    toe_x = FOOT_M * np.cos(np.radians(FOOT_REST_DEG))
    for side, z in _SIDES.items():
        heel_x = -0.05
        parts += [
            # Sole on the floor (y = 0), heel to the toe joint, moved by the ankle.
            Ellipsoid(
                f"{side}_ankle",
                (0.5 * (heel_x + toe_x), 0.5 * ANKLE_HEIGHT_M + 0.01, z * HIP_HALF_WIDTH_M),
                (0.5 * (toe_x - heel_x) + 0.02, 0.5 * ANKLE_HEIGHT_M + 0.01, 0.045),
            ),
            Ellipsoid(
                f"{side}_toe",
                (toe_x + 0.5 * TOE_LENGTH_M, 0.02, z * HIP_HALF_WIDTH_M),
                (0.5 * TOE_LENGTH_M + 0.01, 0.02, 0.042),
            ),
        ]
    return parts


@functools.cache
def humanoid_mesh() -> SkinnedMesh:
    """The humanoid's skinned mesh, built on first use and cached (a few thousand vertices)."""
    return build_capsule_mesh(HUMANOID, HUMANOID_RADII, ellipsoids=_humanoid_ellipsoids())


def __getattr__(name: str) -> Any:
    # HUMANOID_MESH is built lazily: importing the rig must not pay for trimesh meshing.
    if name == "HUMANOID_MESH":
        return humanoid_mesh()
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


REQUIRED_ANGLES = tuple(f"{s}_{seg}_deg" for s in _SIDES for seg in ("thigh", "shank", "foot"))


def clip_from_channels(channels: GaitChannels) -> Clip:
    """Pose :data:`HUMANOID` with sagittal gait channels (module docstring for the mapping).

    Args:
        channels: humanoid channels (docs/conventions.md): ``{left,right}_{thigh,shank,foot}_deg``,
            ``root_position_m`` (the hip-joint centre), contacts ``left_foot``/``right_foot``
            (missing contacts count as "in the air").

    Returns:
        A clip with the channels' segments, events and notes; curves = the angles, the signals
        and ``{left,right}_knee_flexion_deg`` (thigh - shank); ``mesh`` = :func:`humanoid_mesh`.

    Raises:
        ValueError: an angle channel is missing.
    """
    missing = [n for n in REQUIRED_ANGLES if n not in channels.angles]
    if missing:
        raise ValueError(
            f"humanoid rig needs channels {', '.join(REQUIRED_ANGLES)}; missing {', '.join(missing)}"
        )
    n = channels.num_frames
    skel = HUMANOID
    angles = {name: np.radians(channels.angles[name]) for name in REQUIRED_ANGLES}
    rot_z = np.zeros((n, skel.num_joints))  # sagittal angle of each joint, radians
    foot_rest = np.radians(FOOT_REST_DEG)
    curves: dict[str, NDArray[np.float64]] = {**channels.angles, **channels.signals}
    for side in _SIDES:
        thigh, shank, foot = (angles[f"{side}_{s}_deg"] for s in ("thigh", "shank", "foot"))
        rot_z[:, skel.index(f"{side}_hip")] = thigh
        rot_z[:, skel.index(f"{side}_knee")] = shank - thigh
        rot_z[:, skel.index(f"{side}_ankle")] = foot - foot_rest - shank
        contact = channels.contacts.get(f"{side}_foot", np.zeros(n, dtype=bool))
        rot_z[:, skel.index(f"{side}_toe")] = _toe_angle(foot, contact, channels.fps)
        curves[f"{side}_knee_flexion_deg"] = np.degrees(thigh - shank)
    for side, other in (("left", "right"), ("right", "left")):
        thigh = angles[f"{other}_thigh_deg"]
        swing = ARM_SWING * (thigh - _centred_mean(thigh, ARM_CENTRE_S, channels.fps))
        rot_z[:, skel.index(f"{side}_shoulder")] = swing
        elbow = np.radians(ELBOW_BASE_DEG) + ELBOW_FORWARD_GAIN * np.maximum(swing, 0.0)
        rot_z[:, skel.index(f"{side}_elbow")] = elbow
    rot_z[:, skel.index("spine")] = -np.radians(_forward_lean_deg(channels))  # -Z tilts forward

    local = quat.about_z(rot_z)
    twist = CHEST_TWIST * (angles["left_thigh_deg"] - angles["right_thigh_deg"])
    chest = skel.index("chest")
    local[:, chest] = quat.multiply(quat.about_y(twist), local[:, chest])
    return Clip(
        fps=channels.fps,
        skeleton=skel,
        root_translations=channels.root_position_m,
        local_rotations=local.astype(np.float32),
        segments=channels.segments,
        events=channels.events,
        curves=curves,
        mesh=humanoid_mesh(),
        notes=channels.notes,
    )


def _toe_angle(
    foot: NDArray[np.float64], contact: NDArray[np.bool_], fps: float
) -> NDArray[np.float64]:
    """Toe-joint angle (rad): flat toes at push-off, relaxing to neutral after lift-off."""
    foot_rest = np.radians(FOOT_REST_DEG)
    target = np.where(contact, np.maximum(foot_rest - foot, 0.0), 0.0)
    frames = np.arange(len(foot))
    # Index of the latest contact frame at or before each frame (-1 before the first contact).
    last = np.maximum.accumulate(np.where(contact, frames, -1))
    since = (frames - last) / fps
    decayed = np.where(last >= 0, target[np.maximum(last, 0)] * np.exp(-since / TOE_RELAX_S), 0.0)
    return np.where(contact, target, decayed)


def _forward_lean_deg(channels: GaitChannels) -> NDArray[np.float64]:
    """Trunk lean (deg) growing with the horizontal speed, smoothed so gait changes do not jerk."""
    n = channels.num_frames
    if n < 2:
        return np.full(n, 0.0)
    xz = channels.root_position_m[:, [0, 2]]
    speed = np.linalg.norm(np.gradient(xz, axis=0), axis=1) * channels.fps
    return np.minimum(
        LEAN_DEG_PER_MPS * _centred_mean(speed, LEAN_SMOOTH_S, channels.fps), LEAN_MAX_DEG
    )


def _centred_mean(x: NDArray[np.float64], window_s: float, fps: float) -> NDArray[np.float64]:
    """Moving average over an odd number of frames (about ``window_s``), edges held constant."""
    width = max(1, round(window_s * fps)) | 1  # odd, so the window is centred on each frame
    padded = np.pad(x, width // 2, mode="edge")
    return np.convolve(padded, np.full(width, 1.0 / width), mode="valid")
