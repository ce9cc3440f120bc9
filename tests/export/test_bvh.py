"""BVH export: parsed back by an independent reader, FK must match animstudio.core.fk."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from animstudio.core import quat
from animstudio.core.clip import Clip
from animstudio.core.fk import joint_positions
from animstudio.core.skeleton import Skeleton
from animstudio.export.bvh import build_bvh, euler_zxy_deg, write_bvh

# Depth-first order (0, 1, 3, 5, 2, 4) differs from joint order, rest rotations are far from identity.
PARENTS = (-1, 0, 0, 1, 2, 3)
NAMES = ("pelvis", "left_hip", "right_hip", "left_knee", "right_knee", "left_ankle")


def _random_clip(rng: np.random.Generator, frames: int = 40, fps: float = 30.0) -> Clip:
    rest_t = rng.uniform(-0.4, 0.4, size=(len(NAMES), 3))
    rest_r = quat.normalize(rng.normal(size=(len(NAMES), 4)))
    skel = Skeleton(NAMES, PARENTS, rest_t, rest_r)
    # Smooth but large motion: angles sweep more than 180 degrees about random axes.
    axes = quat.normalize(rng.normal(size=(len(NAMES), 3)))
    phase = np.linspace(0.0, 2.0 * np.pi, frames)[:, None]
    angles = 2.0 * np.sin(phase + rng.uniform(0, 6, size=len(NAMES)))
    motion = quat.from_axis_angle(axes[None], angles)
    rot = quat.multiply(rest_r[None], motion)
    root = np.stack(
        [np.linspace(0, 2, frames), 0.9 + 0.05 * np.sin(3 * phase[:, 0]), 0.1 * phase[:, 0]], 1
    )
    return Clip(fps=fps, skeleton=skel, root_translations=root, local_rotations=rot)


def read_bvh(text: str) -> tuple[list[str], np.ndarray]:
    """A small independent BVH reader: joint names (hierarchy order) and world positions (F, J, 3).

    Implements the BVH spec directly (channel order as listed, intrinsic rotations), with scipy
    for Euler angles; it shares no code with animstudio.
    """
    tokens = text.split()
    pos = 0
    joints: list[dict] = []

    def take() -> str:
        nonlocal pos
        pos += 1
        return tokens[pos - 1]

    assert take() == "HIERARCHY"

    def parse_joint(parent: int) -> None:
        kind = take()
        assert kind in ("ROOT", "JOINT"), kind
        name = take()
        assert take() == "{"
        assert take() == "OFFSET"
        offset = np.array([float(take()) for _ in range(3)])
        assert take() == "CHANNELS"
        channels = [take() for _ in range(int(take()))]
        joints.append({"name": name, "parent": parent, "offset": offset, "channels": channels})
        me = len(joints) - 1
        while True:
            tok = tokens[pos]
            if tok == "}":
                take()
                return
            if tok == "End":
                take(), take(), take(), take()  # End Site { OFFSET
                [take() for _ in range(3)]
                assert take() == "}"
                continue
            parse_joint(me)

    parse_joint(-1)
    assert take() == "MOTION"
    assert take() == "Frames:"
    frames = int(take())
    assert (take(), take()) == ("Frame", "Time:")
    float(take())
    n_ch = sum(len(j["channels"]) for j in joints)
    data = np.array([float(t) for t in tokens[pos:]]).reshape(frames, n_ch)

    world_r = np.empty((frames, len(joints), 3, 3))
    world_p = np.empty((frames, len(joints), 3))
    col = 0
    for i, j in enumerate(joints):
        translation = np.tile(j["offset"], (frames, 1))
        rot_axes = ""
        rot_cols = []
        for ch in j["channels"]:
            if ch.endswith("position"):
                translation[:, "XYZ".index(ch[0])] = data[:, col]
            else:
                rot_axes += ch[0]
                rot_cols.append(col)
            col += 1
        local = Rotation.from_euler(rot_axes, data[:, rot_cols], degrees=True).as_matrix()
        if j["parent"] < 0:
            world_r[:, i], world_p[:, i] = local, translation
        else:
            p = j["parent"]
            world_r[:, i] = world_r[:, p] @ local
            world_p[:, i] = world_p[:, p] + np.einsum("fij,fj->fi", world_r[:, p], translation)
    return [j["name"] for j in joints], world_p


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_fk_of_parsed_bvh_matches_clip(seed: int) -> None:
    clip = _random_clip(np.random.default_rng(seed))
    names, world = read_bvh(build_bvh(clip))
    assert sorted(names) == sorted(NAMES)
    assert names != list(NAMES)  # the hierarchy order really is a permutation here
    ours = joint_positions(clip)
    idx = [NAMES.index(n) for n in names]
    err = np.abs(world - ours[:, idx]).max()
    assert err < 1e-4, f"max FK difference {err:.2e} m"


def test_rest_pose_writes_zero_rotations_and_world_aligned_offsets() -> None:
    clip = _random_clip(np.random.default_rng(3), frames=2)
    rest = np.broadcast_to(clip.skeleton.rest_rotations, clip.local_rotations.shape)
    still = Clip(
        fps=clip.fps,
        skeleton=clip.skeleton,
        root_translations=clip.root_translations,
        local_rotations=rest,
    )
    text = build_bvh(still)
    motion = text.split("Frame Time:")[1].split("\n", 1)[1].split()
    values = np.array(motion, dtype=float).reshape(2, -1)
    # Root rotation is its rest rotation folded away too; only the root position remains.
    assert np.allclose(values[:, 3:], 0.0, atol=1e-4)
    assert np.allclose(values[:, :3], clip.root_translations, atol=1e-6)


def test_header_frame_time_and_channels(tmp_path: Path) -> None:
    clip = _random_clip(np.random.default_rng(4), frames=7, fps=24.0)
    path = tmp_path / "out" / "clip.bvh"
    write_bvh(path, clip)
    text = path.read_text()
    assert [p.name for p in path.parent.iterdir()] == ["clip.bvh"]  # no temporary left behind
    assert "Frames: 7\n" in text
    assert "Frame Time: 0.0416666667\n" in text
    assert text.count("CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation") == 1
    assert text.count("CHANNELS 3 Zrotation Xrotation Yrotation") == len(NAMES) - 1
    assert text.count("End Site") == 2  # the leaves right_knee and left_ankle
    assert "ROOT pelvis" in text
    assert text.split("OFFSET")[1].split()[:3] == ["0.000000"] * 3


@pytest.mark.parametrize("x_deg", [-90.0, -89.99, 0.0, 45.0, 89.99, 90.0])
def test_euler_zxy_round_trip_including_gimbal_lock(x_deg: float) -> None:
    rng = np.random.default_rng(5)
    for _ in range(20):
        z, y = rng.uniform(-180, 180, size=2)
        m = Rotation.from_euler("ZXY", [z, x_deg, y], degrees=True).as_matrix()
        back = Rotation.from_euler("ZXY", euler_zxy_deg(m), degrees=True).as_matrix()
        assert np.allclose(back, m, atol=1e-9)


def test_fk_of_parsed_bvh_matches_the_humanoid_rig(synthetic_humanoid_clip) -> None:  # type: ignore[no-untyped-def]
    # The shipped humanoid (its own rest rotations, 24 joints), 20 km from the origin so the
    # 6-decimal text format is exercised at large coordinates too.
    clip = synthetic_humanoid_clip(60, 30.0, start_m=(20_000.0, 5.0))
    names, world = read_bvh(build_bvh(clip))
    ours = joint_positions(clip)
    idx = [clip.skeleton.index(n) for n in names]
    assert len(names) == clip.skeleton.num_joints
    assert np.abs(world - ours[:, idx]).max() < 1e-4
