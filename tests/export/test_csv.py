"""CSV export: header with units, one row per frame, values equal to the clip's."""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np
import pytest

from animstudio.core import quat
from animstudio.core.clip import Clip
from animstudio.core.skeleton import Skeleton
from animstudio.errors import ExportError
from animstudio.export.csv import build_csv, csv_header, write_csv


def _clip(rng: np.random.Generator, frames: int = 12, curves: dict | None = None) -> Clip:
    skel = Skeleton(
        ("pelvis", "thigh", "shank"), (-1, 0, 1), [[0, 0.9, 0], [0, -0.1, 0.09], [0, -0.43, 0]]
    )
    rot = quat.normalize(rng.normal(size=(frames, 3, 4))).astype(np.float32)
    root = rng.normal(size=(frames, 3))
    if curves is None:
        curves = {
            "left_thigh_deg": rng.normal(size=frames) * 30,
            "neuron_u1": rng.normal(size=frames),
        }
    return Clip(fps=25.0, skeleton=skel, root_translations=root, local_rotations=rot, curves=curves)


def test_columns_and_values_round_trip(tmp_path: Path) -> None:
    clip = _clip(np.random.default_rng(0))
    path = tmp_path / "a" / "clip.csv"
    write_csv(path, clip)
    with open(path, newline="") as fh:
        rows = list(csv.reader(fh))
    header, body = rows[0], rows[1:]
    assert header[:5] == ["frame", "time_s", "root_x_m", "root_y_m", "root_z_m"]
    assert header[5:7] == ["left_thigh_deg", "neuron_u1"]
    assert header[7:11] == ["pelvis_quat_w", "pelvis_quat_x", "pelvis_quat_y", "pelvis_quat_z"]
    assert len(header) == 5 + 2 + 3 * 4
    assert len(body) == clip.num_frames
    table = np.array(body, dtype=float)
    assert [r[0] for r in body] == [str(k) for k in range(clip.num_frames)]  # integers, not 0.0
    assert np.allclose(table[:, 1], np.arange(clip.num_frames) / 25.0, rtol=0, atol=1e-12)
    assert np.allclose(table[:, 2:5], clip.root_translations, rtol=1e-8)
    assert np.allclose(table[:, 5], clip.curves["left_thigh_deg"], rtol=1e-8)
    rot = table[:, 7:].reshape(clip.num_frames, 3, 4).astype(np.float32)
    assert np.array_equal(rot, clip.local_rotations)  # 9 significant digits round-trip float32


def test_curve_shadowing_a_fixed_column_is_a_typed_error(tmp_path: Path) -> None:
    clip = _clip(np.random.default_rng(1), curves={"time_s": np.zeros(12)})
    with pytest.raises(ExportError, match="duplicate column names time_s"):
        write_csv(tmp_path / "x.csv", clip)
    assert list(tmp_path.iterdir()) == []


def test_curve_name_with_comma_is_refused() -> None:
    clip = _clip(np.random.default_rng(2), curves={"a,b": np.zeros(12)})
    with pytest.raises(ExportError, match="comma"):
        build_csv(clip)


def test_humanoid_clip_columns(synthetic_humanoid_clip) -> None:  # type: ignore[no-untyped-def]
    clip = synthetic_humanoid_clip(30, 25.0)
    rows = list(csv.reader(build_csv(clip).splitlines()))
    assert rows[0] == csv_header(clip)
    assert len(rows) == 31 and len(rows[0]) == 5 + len(clip.curves) + 4 * clip.skeleton.num_joints
    assert "left_thigh_deg" in rows[0] and "left_toe_quat_w" in rows[0]
