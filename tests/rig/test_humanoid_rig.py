"""The humanoid rig: skeleton layout, channel mapping, hand-computed poses."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from animstudio.core.channels import GaitChannels
from animstudio.core.fk import joint_positions, rest_world_transforms, world_transforms
from animstudio.rig import clip_from_channels as dispatch_clip_from_channels
from animstudio.rig import humanoid
from animstudio.rig.humanoid import HUMANOID, clip_from_channels, humanoid_mesh
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

REQUIRED = (
    "pelvis spine chest neck head left_hip left_knee left_ankle left_toe right_hip right_knee "
    "right_ankle right_toe left_shoulder left_elbow left_wrist right_shoulder right_elbow "
    "right_wrist"
).split()


def _pose(
    n: int = 1,
    *,
    thigh: float | np.ndarray = 0.0,
    shank: float | np.ndarray = 0.0,
    foot: float | np.ndarray = FOOT_REST_DEG,
    right_thigh: float | np.ndarray | None = None,
    contact: bool | np.ndarray = False,
    root: tuple[float, float, float] = (0.0, STANDING_HIP_HEIGHT_M, 0.0),
) -> GaitChannels:
    """Both legs posed alike (the right thigh may differ); a static root."""
    full = lambda v: np.broadcast_to(np.asarray(v, dtype=np.float64), (n,))  # noqa: E731
    angles = {}
    for side in ("left", "right"):
        th = thigh if side == "left" or right_thigh is None else right_thigh
        angles[f"{side}_thigh_deg"] = full(th)
        angles[f"{side}_shank_deg"] = full(shank)
        angles[f"{side}_foot_deg"] = full(foot)
    contacts = {f"{s}_foot": np.broadcast_to(np.asarray(contact), (n,)) for s in ("left", "right")}
    return GaitChannels(
        fps=30.0,
        character="humanoid",
        angles=angles,
        root_position_m=np.tile(root, (n, 1)),
        contacts=contacts,
    )


def _world(clip, name: str) -> np.ndarray:  # type: ignore[no-untyped-def]
    return joint_positions(clip)[:, clip.skeleton.index(name)]


def test_skeleton_has_the_required_joints_parents_first_and_rest_layout() -> None:
    for name in REQUIRED:
        HUMANOID.index(name)
    assert HUMANOID.joint_names[0] == "pelvis"
    assert all(p < j for j, p in enumerate(HUMANOID.parents))
    np.testing.assert_allclose(HUMANOID.rest_translations[0], (0.0, STANDING_HIP_HEIGHT_M, 0.0))
    _, pos = rest_world_transforms(HUMANOID)
    at = {n: pos[HUMANOID.index(n)] for n in HUMANOID.joint_names}
    np.testing.assert_allclose(at["left_hip"], (0.0, STANDING_HIP_HEIGHT_M, -HIP_HALF_WIDTH_M))
    np.testing.assert_allclose(at["right_hip"], (0.0, STANDING_HIP_HEIGHT_M, HIP_HALF_WIDTH_M))
    np.testing.assert_allclose(at["left_knee"][1], STANDING_HIP_HEIGHT_M - THIGH_M)
    np.testing.assert_allclose(at["left_ankle"][1], ANKLE_HEIGHT_M, atol=1e-12)
    foot = at["left_toe"] - at["left_ankle"]
    assert np.linalg.norm(foot) == pytest.approx(FOOT_M)
    assert np.degrees(np.arctan2(foot[1], foot[0])) == pytest.approx(FOOT_REST_DEG)
    assert at["left_toe"][1] > 0.0  # toes above the floor, forward of the ankle
    # Winter's fractions of height for the trunk and arms.
    assert at["left_shoulder"][1] == pytest.approx(0.818 * HEIGHT_M)
    assert at["head"][1] == pytest.approx(0.870 * HEIGHT_M)
    assert at["head_end"][1] == pytest.approx(HEIGHT_M)
    upper = np.linalg.norm(at["left_elbow"] - at["left_shoulder"])
    fore = np.linalg.norm(at["left_wrist"] - at["left_elbow"])
    assert upper == pytest.approx(0.186 * HEIGHT_M)
    assert fore == pytest.approx(0.146 * HEIGHT_M)
    assert at["left_shoulder"][2] < 0 < at["right_shoulder"][2]


def test_dispatch_by_character_reaches_this_rig(synthetic_humanoid_channels) -> None:  # type: ignore[no-untyped-def]
    ch = synthetic_humanoid_channels(20)
    a, b = dispatch_clip_from_channels(ch), clip_from_channels(ch)
    np.testing.assert_array_equal(a.local_rotations, b.local_rotations)


def test_clip_copies_labels_curves_and_attaches_the_cached_mesh(
    synthetic_humanoid_channels,
) -> None:  # type: ignore[no-untyped-def]
    ch = synthetic_humanoid_channels(60, 24.0)
    clip = clip_from_channels(ch)
    assert clip.fps == 24.0 and clip.num_frames == 60
    assert clip.segments == ch.segments and clip.events == ch.events and clip.notes == ch.notes
    np.testing.assert_array_equal(clip.root_translations, ch.root_position_m)
    for name in (*ch.angles, *ch.signals, "left_knee_flexion_deg", "right_knee_flexion_deg"):
        assert name in clip.curves
    assert clip.mesh is humanoid_mesh()
    assert humanoid.HUMANOID_MESH is humanoid_mesh()  # built once, lazily


def test_knee_flexion_curve_is_thigh_minus_shank(synthetic_humanoid_channels) -> None:  # type: ignore[no-untyped-def]
    ch = synthetic_humanoid_channels(50)
    clip = clip_from_channels(ch)
    for side in ("left", "right"):
        expected = ch.angles[f"{side}_thigh_deg"] - ch.angles[f"{side}_shank_deg"]
        np.testing.assert_allclose(clip.curves[f"{side}_knee_flexion_deg"], expected)


def test_bone_lengths_are_preserved_in_every_frame(synthetic_humanoid_clip) -> None:  # type: ignore[no-untyped-def]
    clip = synthetic_humanoid_clip(120, start_m=(50.0, -3.0))
    pos = joint_positions(clip)
    _, rest = rest_world_transforms(clip.skeleton)
    for j, p in enumerate(clip.skeleton.parents):
        if p < 0:
            continue
        lengths = np.linalg.norm(pos[:, j] - pos[:, p], axis=-1)
        np.testing.assert_allclose(lengths, np.linalg.norm(rest[j] - rest[p]), atol=1e-6)


def test_known_leg_pose_gives_hand_computed_joint_positions() -> None:
    # Thigh 30 deg forward, shank vertical, foot 10 deg toe-up; root 2 m ahead.
    clip = clip_from_channels(_pose(thigh=30.0, shank=0.0, foot=10.0, root=(2.0, 0.9, 0.5)))
    hip = np.array([2.0, 0.9, 0.5 - HIP_HALF_WIDTH_M])
    a = np.radians(30.0)
    knee = hip + THIGH_M * np.array([np.sin(a), -np.cos(a), 0.0])
    ankle = knee + np.array([0.0, -SHANK_M, 0.0])
    toe = ankle + FOOT_M * np.array([np.cos(np.radians(10.0)), np.sin(np.radians(10.0)), 0.0])
    for name, want in (
        ("left_hip", hip),
        ("left_knee", knee),
        ("left_ankle", ankle),
        ("left_toe", toe),
    ):
        np.testing.assert_allclose(_world(clip, name)[0], want, atol=1e-6, err_msg=name)


def test_known_arm_pose_swings_about_the_thigh_mean_with_elbow_flexion() -> None:
    # Both thighs 8 + 20 sin(2 pi k / 31) at 30 fps: the 31-frame running mean is exactly 8 deg
    # inside the clip, so each shoulder turns 0.6 * 20 sin(...) about +Z and the elbow
    # 10 deg + 0.5 * max(shoulder, 0). Equal thighs: no chest twist; static root: no lean.
    n, period = 93, 31
    k = np.arange(n)
    thigh = 8.0 + 20.0 * np.sin(2.0 * np.pi * k / period)
    clip = clip_from_channels(_pose(n, thigh=thigh))
    _, rest = rest_world_transforms(clip.skeleton)
    sh, el, wr = (clip.skeleton.index(f"left_{n}") for n in ("shoulder", "elbow", "wrist"))

    def rot_z(deg: float, v: np.ndarray) -> np.ndarray:
        c, s = np.cos(np.radians(deg)), np.sin(np.radians(deg))
        return np.array([c * v[0] - s * v[1], s * v[0] + c * v[1], v[2]])

    for frame in (39, 54):  # arm forward, arm back
        shoulder_deg = 0.6 * 20.0 * np.sin(2.0 * np.pi * frame / period)
        elbow_deg = 10.0 + 0.5 * max(shoulder_deg, 0.0)
        elbow = rest[sh] + rot_z(shoulder_deg, rest[el] - rest[sh])
        wrist = elbow + rot_z(shoulder_deg + elbow_deg, rest[wr] - rest[el])
        np.testing.assert_allclose(_world(clip, "left_elbow")[frame], elbow, atol=1e-6)
        np.testing.assert_allclose(_world(clip, "left_wrist")[frame], wrist, atol=1e-6)
    assert _world(clip, "left_wrist")[39, 0] > 0.15 > -0.05 > _world(clip, "left_wrist")[54, 0]


def test_arms_hang_when_the_thighs_hold_still() -> None:
    clip = clip_from_channels(_pose(5, thigh=35.0))
    q = clip.local_rotations[:, clip.skeleton.index("left_shoulder")]
    np.testing.assert_allclose(q, np.tile([1.0, 0, 0, 0], (5, 1)), atol=1e-7)


def test_left_arm_follows_the_right_thigh(synthetic_humanoid_channels) -> None:  # type: ignore[no-untyped-def]
    ch = synthetic_humanoid_channels(90)
    clip = clip_from_channels(ch)
    pos = joint_positions(clip)
    wrist_x = pos[:, clip.skeleton.index("left_wrist"), 0] - pos[:, 0, 0]
    r_thigh = ch.angles["right_thigh_deg"]
    l_thigh = ch.angles["left_thigh_deg"]
    assert np.corrcoef(wrist_x, r_thigh)[0, 1] > 0.95
    assert np.corrcoef(wrist_x, l_thigh)[0, 1] < -0.9


@settings(max_examples=40, deadline=None)
@given(
    thigh=st.floats(-60.0, 60.0),
    shank=st.floats(-80.0, 40.0),
    foot=st.floats(-70.0, 40.0),
)
def test_foot_line_makes_foot_deg_with_the_horizontal(
    thigh: float, shank: float, foot: float
) -> None:
    clip = clip_from_channels(_pose(thigh=thigh, shank=shank, foot=foot))
    pos = joint_positions(clip)[0]
    sk = clip.skeleton
    for side in ("left", "right"):
        d = pos[sk.index(f"{side}_toe")] - pos[sk.index(f"{side}_ankle")]
        assert np.degrees(np.arctan2(d[1], d[0])) == pytest.approx(foot, abs=1e-4)
        shank_vec = pos[sk.index(f"{side}_ankle")] - pos[sk.index(f"{side}_knee")]
        assert np.degrees(np.arctan2(shank_vec[0], -shank_vec[1])) == pytest.approx(shank, abs=1e-4)


def test_feet_are_flat_at_the_rest_foot_angle_whatever_the_leg() -> None:
    n = 40
    rng = np.random.default_rng(3)
    clip = clip_from_channels(
        _pose(n, thigh=rng.uniform(-40, 40, n), shank=rng.uniform(-60, 20, n), contact=True)
    )
    pos = joint_positions(clip)
    sk = clip.skeleton
    _, rest = rest_world_transforms(sk)
    for side in ("left", "right"):
        ankle, toe, tip = (sk.index(f"{side}_{n}") for n in ("ankle", "toe", "toe_end"))
        # The foot has its standing shape relative to the ankle: flat on a floor under the ankle.
        np.testing.assert_allclose(
            pos[:, toe] - pos[:, ankle], np.broadcast_to(rest[toe] - rest[ankle], (n, 3)), atol=1e-6
        )
        np.testing.assert_allclose(pos[:, tip, 1], pos[:, toe, 1], atol=1e-6)


def test_toes_stay_flat_at_push_off_and_relax_after_lift_off() -> None:
    # Heel raised (foot 30 deg steeper than rest) while in contact, then lift-off at frame 10.
    n = 20
    contact = np.arange(n) < 10
    clip = clip_from_channels(_pose(n, foot=FOOT_REST_DEG - 30.0, contact=contact))
    pos = joint_positions(clip)
    sk = clip.skeleton
    toe, tip = sk.index("left_toe"), sk.index("left_toe_end")
    d = pos[:, tip] - pos[:, toe]
    pitch = np.degrees(np.arctan2(d[:, 1], d[:, 0]))
    np.testing.assert_allclose(pitch[:10], 0.0, atol=1e-4)  # flat on the floor
    # In the air the toes return towards the foot's line (-30 deg) smoothly, without a jump.
    assert np.all(np.diff(pitch[9:]) < 0)
    assert np.max(np.abs(np.diff(pitch[9:]))) < 15.0
    assert pitch[-1] == pytest.approx(-30.0, abs=0.5)


def test_toes_are_neutral_without_contact_or_with_the_heel_down() -> None:
    for foot, contact in ((FOOT_REST_DEG - 30.0, False), (FOOT_REST_DEG + 15.0, True)):
        clip = clip_from_channels(_pose(3, foot=foot, contact=contact))
        q = clip.local_rotations[:, clip.skeleton.index("left_toe")]
        np.testing.assert_allclose(q, np.tile([1.0, 0, 0, 0], (3, 1)), atol=1e-7)


def test_trunk_leans_forward_with_speed_only(synthetic_humanoid_clip) -> None:  # type: ignore[no-untyped-def]
    still = synthetic_humanoid_clip(60, speed_mps=0.0)
    moving = synthetic_humanoid_clip(60, speed_mps=3.0)

    def head_ahead(clip) -> np.ndarray:  # type: ignore[no-untyped-def]
        pos = joint_positions(clip)
        return pos[:, clip.skeleton.index("head"), 0] - pos[:, 0, 0]

    _, rest = rest_world_transforms(HUMANOID)
    trunk = rest[HUMANOID.index("head"), 1] - rest[HUMANOID.index("spine"), 1]
    assert np.all(np.abs(head_ahead(still)) < 1e-3)
    # 1.5 deg per m/s about the lumbar joint: 4.5 deg at 3 m/s.
    np.testing.assert_allclose(head_ahead(moving), trunk * np.sin(np.radians(4.5)), atol=1e-3)


def test_missing_channel_is_a_clear_error() -> None:
    ch = _pose()
    angles = {k: v for k, v in ch.angles.items() if k != "right_foot_deg"}
    bad = GaitChannels(
        fps=30.0, character="humanoid", angles=angles, root_position_m=ch.root_position_m
    )
    with pytest.raises(ValueError, match="missing right_foot_deg"):
        clip_from_channels(bad)


def test_single_frame_clip() -> None:
    clip = clip_from_channels(_pose(1, thigh=10.0))
    assert clip.num_frames == 1
    rot, _ = world_transforms(clip.skeleton, clip.local_rotations, clip.local_translations())
    assert np.all(np.isfinite(rot))
