"""The hexapod character: skeleton, skin, leg inverse kinematics and channels -> Clip.

Skeleton: root ``body``; per leg ``<leg>_coxa`` (on the body), ``<leg>_femur`` (end of the coxa),
``<leg>_tibia`` (the "knee") and ``<leg>_foot`` (tip of the tibia), legs ``L1 L2 L3`` (left front,
middle, hind, at -Z) and ``R1 R2 R3`` (+Z). In the rest pose every leg segment points straight out
sideways, all rest rotations identity.

Channels (``GaitChannels.angles``), per leg, degrees:

* ``<leg>_coxa_deg``: yaw of the coxa about +Y, positive = the foot moves forward (+X) on both
  sides (the rig mirrors the sign for the left legs);
* ``<leg>_femur_deg``: elevation of the femur above the horizontal, positive = up;
* ``<leg>_tibia_deg``: bend of the tibia below the femur's line, positive = the foot goes down
  (0 = straight leg).

``root_position_m`` is the body centre; the body does not turn (it walks along +X).
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
from animstudio.errors import SimulationError
from animstudio.rig.mesh import Ellipsoid, build_capsule_mesh

LEGS: tuple[str, ...] = ("L1", "L2", "L3", "R1", "R2", "R3")
COXA_M = 0.04
"""Coxa joint to femur joint."""
FEMUR_M = 0.10
"""Femur joint to tibia joint."""
TIBIA_M = 0.14
"""Tibia joint to the foot tip."""
BODY_HEIGHT_M = 0.11
"""Body centre (and coxa joints) above the ground while walking."""
COXA_X_M = {"1": 0.12, "2": 0.0, "3": -0.12}
"""Coxa joints along the body (+X forward) by leg number."""
COXA_Z_M = 0.07
"""Coxa joints beside the body centre (left at -Z, right at +Z)."""
NEUTRAL_FOOT_X_M = {"1": 0.19, "2": 0.0, "3": -0.19}
"""Foot at mid-stance, relative to the body centre: front feet ahead, hind feet behind."""
NEUTRAL_FOOT_Z_M = 0.22
"""Foot at mid-stance beside the body centre."""


def side_sign(leg: str) -> float:
    """``-1`` for left legs (at -Z), ``+1`` for right legs."""
    return -1.0 if leg.startswith("L") else 1.0


def coxa_position(leg: str) -> NDArray[np.float64]:
    """Coxa joint in the body frame (m)."""
    return np.array([COXA_X_M[leg[1]], 0.0, side_sign(leg) * COXA_Z_M])


def neutral_foot(leg: str) -> NDArray[np.float64]:
    """Mid-stance foot position relative to the body centre, on the ground (m)."""
    return np.array([NEUTRAL_FOOT_X_M[leg[1]], -BODY_HEIGHT_M, side_sign(leg) * NEUTRAL_FOOT_Z_M])


def _build_skeleton() -> Skeleton:
    names = ["body"]
    parents = [-1]
    offsets: list[tuple[float, ...]] = [(0.0, BODY_HEIGHT_M, 0.0)]
    for leg in LEGS:
        s = side_sign(leg)
        base = len(names)
        names += [f"{leg}_coxa", f"{leg}_femur", f"{leg}_tibia", f"{leg}_foot"]
        parents += [0, base, base + 1, base + 2]
        offsets += [
            tuple(coxa_position(leg)),
            (0.0, 0.0, s * COXA_M),
            (0.0, 0.0, s * FEMUR_M),
            (0.0, 0.0, s * TIBIA_M),
        ]
    return Skeleton(tuple(names), tuple(parents), np.array(offsets))


HEXAPOD = _build_skeleton()
"""The hexapod skeleton (25 joints), rest pose standing at :data:`BODY_HEIGHT_M`."""

HEXAPOD_RADII: dict[str, float] = {}
for _leg in LEGS:
    HEXAPOD_RADII |= {f"{_leg}_femur": 0.014, f"{_leg}_tibia": 0.011, f"{_leg}_foot": 0.007}


@functools.cache
def hexapod_mesh() -> SkinnedMesh:
    """The hexapod's skin: capsules along the leg segments, a thorax and a head ellipsoid."""
    h = BODY_HEIGHT_M
    parts = [
        Ellipsoid("body", (0.0, h, 0.0), (0.19, 0.055, 0.085)),
        Ellipsoid("body", (0.22, h + 0.01, 0.0), (0.05, 0.04, 0.05)),
        Ellipsoid("body", (-0.25, h + 0.005, 0.0), (0.09, 0.05, 0.07)),
    ]
    return build_capsule_mesh(HEXAPOD, HEXAPOD_RADII, ellipsoids=parts)


def __getattr__(name: str) -> Any:
    # HEXAPOD_MESH is built lazily: importing the rig must not pay for meshing.
    if name == "HEXAPOD_MESH":
        return hexapod_mesh()
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


CHANNELS: tuple[str, ...] = tuple(
    f"{leg}_{j}_deg" for leg in LEGS for j in ("coxa", "femur", "tibia")
)


def leg_ik(leg: str, foot_rel_body: NDArray[np.float64]) -> NDArray[np.float64]:
    """Joint angles placing ``leg``'s foot at ``foot_rel_body`` (``(F, 3)`` m, body frame).

    Returns:
        ``(F, 3)`` radians: coxa yaw, femur elevation, tibia bend (module docstring), knee up.

    Raises:
        SimulationError: a target out of the leg's reach.
    """
    d = np.asarray(foot_rel_body, dtype=np.float64) - coxa_position(leg)
    s = side_sign(leg)
    yaw = np.arctan2(d[:, 0], s * d[:, 2])
    rho = np.hypot(d[:, 0], d[:, 2]) - COXA_M
    dist = np.hypot(rho, d[:, 1])
    lo, hi = abs(FEMUR_M - TIBIA_M), FEMUR_M + TIBIA_M
    bad = (dist <= lo + 1e-9) | (dist >= hi - 1e-9) | (np.hypot(d[:, 0], d[:, 2]) < COXA_M)
    if np.any(bad):
        k = int(np.flatnonzero(bad)[0])
        raise SimulationError(
            f"{leg} foot target {np.round(foot_rel_body[k], 3).tolist()} m (body frame) is out of "
            f"reach ({dist[k]:.3f} m from the femur joint; reach {lo:.2f}..{hi:.2f} m)"
        )
    inner = np.arccos((FEMUR_M**2 + TIBIA_M**2 - dist**2) / (2 * FEMUR_M * TIBIA_M))
    bend = np.pi - inner
    elev = np.arctan2(d[:, 1], rho) + np.arccos(
        (FEMUR_M**2 + dist**2 - TIBIA_M**2) / (2 * FEMUR_M * dist)
    )
    return np.stack([yaw, elev, bend], axis=-1)


def clip_from_channels(channels: GaitChannels) -> Clip:
    """Pose :data:`HEXAPOD` with hexapod channels (module docstring for names and signs).

    Args:
        channels: ``character == "hexapod"``, every name in :data:`CHANNELS`, ``root_position_m``
            = the body centre.

    Returns:
        A clip with the channels' segments, events and notes; curves = the angles and signals;
        ``mesh`` = :func:`hexapod_mesh`.

    Raises:
        ValueError: wrong character or a missing channel.
    """
    if channels.character != "hexapod":
        raise ValueError(f"hexapod rig needs hexapod channels, got {channels.character!r}")
    missing = [c for c in CHANNELS if c not in channels.angles]
    if missing:
        raise ValueError(
            f"hexapod rig needs channels {', '.join(CHANNELS)}; missing {', '.join(missing)}"
        )
    skel = HEXAPOD
    local = quat.identity((channels.num_frames, skel.num_joints))
    for leg in LEGS:
        s = side_sign(leg)
        yaw, elev, bend = (
            np.radians(channels.angles[f"{leg}_{j}_deg"]) for j in ("coxa", "femur", "tibia")
        )
        # Right legs point +Z: +yaw about +Y swings them forward, -elev about +X lifts them, +bend
        # about +X turns the tibia down. The left legs (pointing -Z) need the opposite signs.
        local[:, skel.index(f"{leg}_coxa")] = quat.about_y(s * yaw)
        local[:, skel.index(f"{leg}_femur")] = quat.about_x(-s * elev)
        local[:, skel.index(f"{leg}_tibia")] = quat.about_x(s * bend)
    return Clip(
        fps=channels.fps,
        skeleton=skel,
        root_translations=channels.root_position_m,
        local_rotations=local.astype(np.float32),
        segments=channels.segments,
        events=channels.events,
        curves={**channels.angles, **channels.signals},
        mesh=hexapod_mesh(),
        notes=channels.notes,
    )
