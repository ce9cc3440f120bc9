"""Blender, a real consumer, imports our USD and BVH exports of a real script.

Blender runs as a module (``bpy``) in ``.venv-blender`` (``scripts/setup_blender.sh``): it pins
numpy<2, so it cannot share the main environment. Each import runs ``blender_import.py`` in a
subprocess and compares what Blender built with our clip:

- joint (bone) count and names;
- frame range: USD time codes ``0..F-1`` land on Blender frames ``0..F-1``; Blender's BVH
  importer keys BVH frames on ``1..F`` (its convention, ``frame_start=1``);
- fps: Blender reads BVH's ``Frame Time`` into the scene fps. Blender's USD importer (4.5 LTS,
  and 5.0 likewise) does not read ``timeCodesPerSecond``: it keys time code ``k`` on frame ``k``
  and leaves the scene fps alone, so for USD the fps is checked on the file with pxr and the
  frame mapping in Blender;
- world position of a distal joint (the left toe: every rotation of the leg chain and the root
  path act on it) at sampled frames, within ``TOLERANCE_M``.

``TOLERANCE_M = 1e-4`` m: USD stores float32 rotations/translations and Blender composes its
bone matrices in float32; with the root up to a few metres from the origin float32 resolution
is ~2.4e-7 m per operation, and a 6-joint chain accumulates ~1e-6..1e-5 m (measured: 5e-7 m
for USD, 1.1e-6 m for BVH, over a 5 m walk).
BVH stores 6 decimals (1e-6 m, 1e-6 degree). 0.1 mm is ten times the worst expected error and
far below anything visible, while a wrong axis, rotation order or rest-rotation fold moves the
toe by centimetres.
"""

from __future__ import annotations

import json
import subprocess
from pathlib import Path

import numpy as np
import pytest

from animstudio import pipeline
from animstudio.core.clip import Clip
from animstudio.core.fk import joint_positions
from animstudio.core.resample import resample_clip
from animstudio.export.bvh import write_bvh
from animstudio.export.usd import write_usd

pytestmark = pytest.mark.blender

REPO = Path(__file__).resolve().parents[2]
BLENDER_PYTHON = REPO / ".venv-blender" / "bin" / "python"
IMPORT_SCRIPT = Path(__file__).parent / "blender_import.py"
SCRIPT = "engine som\ncharacter humanoid\nfps 30\n\nwalk 1s / run 1s / climb 20\n"
JOINT = "left_toe"
TOLERANCE_M = 1e-4


def _blender_python() -> Path:
    if not BLENDER_PYTHON.exists():
        pytest.fail(
            f"{BLENDER_PYTHON} is missing: run scripts/setup_blender.sh (creates .venv-blender "
            "with bpy; .ci/run does this through scripts/setup-dev.sh)"
        )
    return BLENDER_PYTHON


def _import_in_blender(path: Path, frames: list[int]) -> dict:
    proc = subprocess.run(
        [str(_blender_python()), str(IMPORT_SCRIPT), str(path), JOINT, ",".join(map(str, frames))],
        capture_output=True,
        text=True,
        timeout=180,
    )
    lines = [ln for ln in proc.stdout.splitlines() if ln.startswith("RESULT ")]
    assert proc.returncode == 0 and lines, f"Blender import failed:\n{proc.stdout}\n{proc.stderr}"
    return json.loads(lines[-1][len("RESULT ") :])


@pytest.fixture(scope="module")
def clip() -> Clip:
    script = pipeline.parse_script(SCRIPT, path="blender_test.gait")
    return pipeline.render(script)


def _blender_axes(p: np.ndarray) -> np.ndarray:
    # Both importers turn Y-up files into Blender's Z-up world: (x, y, z) -> (x, -z, y).
    return np.stack([p[..., 0], -p[..., 2], p[..., 1]], axis=-1)


def _sample_frames(n: int) -> list[int]:
    return sorted({0, 1, n // 3, n // 2, (2 * n) // 3, n - 2, n - 1})


def _check_pose(result: dict, clip: Clip, frames: list[int]) -> None:
    ours = _blender_axes(joint_positions(clip)[frames, clip.skeleton.index(JOINT)])
    theirs = np.array(result["positions"])
    err = np.abs(theirs - ours).max()
    assert err < TOLERANCE_M, f"{JOINT} differs by {err:.2e} m:\nours {ours}\nBlender {theirs}"
    # The sampled joint really moves: the comparison is not between two rest poses.
    assert np.ptp(ours, axis=0).max() > 0.3


@pytest.mark.parametrize("ext", ["usda", "usdc"])
def test_usd_imports_with_same_joints_frames_and_pose(clip: Clip, ext: str, tmp_path: Path) -> None:
    from pxr import Usd

    path = tmp_path / f"walk.{ext}"
    write_usd(path, clip)
    stage = Usd.Stage.Open(str(path))
    assert stage.GetTimeCodesPerSecond() == stage.GetFramesPerSecond() == clip.fps
    frames = _sample_frames(clip.num_frames)
    result = _import_in_blender(path, frames)
    assert result["bones"] == clip.skeleton.num_joints
    assert sorted(result["bone_names"]) == sorted(clip.skeleton.joint_names)
    assert result["keyed_range"] == [0.0, clip.num_frames - 1.0]
    assert (result["frame_start"], result["frame_end"]) == (0, clip.num_frames - 1)
    _check_pose(result, clip, frames)


@pytest.mark.parametrize("fps", [30, 25])
def test_bvh_imports_with_same_joints_frames_fps_and_pose(
    clip: Clip, fps: int, tmp_path: Path
) -> None:
    resampled = resample_clip(clip, fps)
    path = tmp_path / f"walk_{fps}.bvh"
    write_bvh(path, resampled)
    frames = _sample_frames(resampled.num_frames)
    result = _import_in_blender(path, frames)
    assert result["bones"] == clip.skeleton.num_joints
    assert sorted(result["bone_names"]) == sorted(clip.skeleton.joint_names)
    assert result["keyed_range"] == [1.0, float(resampled.num_frames)]
    assert abs(result["fps"] - fps) < 1e-4 * fps
    _check_pose(result, resampled, frames)
