"""The hexapod rig: skeleton, IK against FK, and channels -> Clip."""

from __future__ import annotations

import numpy as np
import pytest

from animstudio.core.channels import GaitChannels
from animstudio.core.fk import joint_positions
from animstudio.errors import SimulationError
from animstudio.rig import hexapod as rig


def test_skeleton_has_body_and_six_legs_with_usd_names() -> None:
    skel = rig.HEXAPOD
    assert skel.joint_names[0] == "body"
    for leg in ("L1", "L2", "L3", "R1", "R2", "R3"):
        for joint in ("coxa", "femur", "tibia", "foot"):
            skel.index(f"{leg}_{joint}")
    # Left legs at -Z, right legs at +Z (docs/conventions.md).
    assert (
        skel.rest_translations[skel.index("L2_coxa"), 2]
        < 0
        < skel.rest_translations[skel.index("R2_coxa"), 2]
    )


def _channels_for_feet(feet_rel: dict[str, np.ndarray], root: np.ndarray) -> GaitChannels:
    angles = {}
    for leg, target in feet_rel.items():
        q = np.degrees(rig.leg_ik(leg, target))
        for c, joint in enumerate(("coxa", "femur", "tibia")):
            angles[f"{leg}_{joint}_deg"] = q[:, c]
    return GaitChannels(fps=30.0, character="hexapod", angles=angles, root_position_m=root)


def test_ik_then_rig_fk_puts_every_foot_on_its_target() -> None:
    rng = np.random.default_rng(4)
    n = 50
    root = np.column_stack([np.linspace(0, 1, n), np.full(n, rig.BODY_HEIGHT_M), np.zeros(n)])
    targets = {
        leg: rig.neutral_foot(leg)
        + rng.uniform([-0.06, 0.0, -0.03], [0.06, 0.04, 0.03], size=(n, 3))
        for leg in rig.LEGS
    }
    clip = rig.clip_from_channels(_channels_for_feet(targets, root))
    pos = joint_positions(clip)
    for leg in rig.LEGS:
        got = pos[:, clip.skeleton.index(f"{leg}_foot")]
        np.testing.assert_allclose(got, root + targets[leg], atol=1e-5)


def test_positive_coxa_moves_the_foot_forward_on_both_sides() -> None:
    root = np.array([[0.0, rig.BODY_HEIGHT_M, 0.0]] * 2)
    feet = {leg: np.stack([rig.neutral_foot(leg), rig.neutral_foot(leg)]) for leg in rig.LEGS}
    ch = _channels_for_feet(feet, root)
    angles = dict(ch.angles)
    for leg in rig.LEGS:
        angles[f"{leg}_coxa_deg"] = angles[f"{leg}_coxa_deg"] + np.array([0.0, 10.0])
    clip = rig.clip_from_channels(
        GaitChannels(fps=30.0, character="hexapod", angles=angles, root_position_m=root)
    )
    pos = joint_positions(clip)
    for leg in rig.LEGS:
        x = pos[:, clip.skeleton.index(f"{leg}_foot"), 0]
        assert x[1] > x[0] + 0.01, leg


def test_out_of_reach_is_a_simulation_error() -> None:
    with pytest.raises(SimulationError, match="out of reach"):
        rig.leg_ik("L1", np.array([[1.0, -0.1, -0.2]]))


def test_wrong_character_or_missing_channel_is_rejected() -> None:
    root = np.zeros((1, 3))
    with pytest.raises(ValueError, match="hexapod"):
        rig.clip_from_channels(
            GaitChannels(fps=30.0, character="humanoid", angles={}, root_position_m=root)
        )
    with pytest.raises(ValueError, match="missing"):
        rig.clip_from_channels(
            GaitChannels(fps=30.0, character="hexapod", angles={}, root_position_m=root)
        )


def test_mesh_is_bound_to_the_hexapod() -> None:
    mesh = rig.hexapod_mesh()
    assert mesh.joint_indices.max() < rig.HEXAPOD.num_joints
    assert len(mesh.vertices) > 500
