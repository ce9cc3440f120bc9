"""The cycle-file format and its loader: shapes of the real set, located errors for bad files."""

from __future__ import annotations

import shutil
from pathlib import Path

import numpy as np
import pytest

from animstudio.errors import DataError
from animstudio.gaitdata import load_training_set
from animstudio.gaitdata.cycles import COLUMNS, parse_cycle

TRAINING_DATA = Path(__file__).resolve().parents[2] / "training_data"


def test_shipped_training_set_has_the_thesis_patterns() -> None:
    ts = load_training_set(TRAINING_DATA)
    assert ts.gait_names == ("walk", "run", "climb")
    assert ts.gait_ids.tolist() == [0.2, 0.4, 0.6]
    p = ts.num_patterns
    assert ts.inputs.shape == (p, 2) and ts.outputs.shape == (p, 6) and ts.stance.shape == (p,)
    assert int(ts.cycle_frames.sum()) == p
    for g, name in enumerate(ts.gait_names):
        rows = ts.patterns_of(name)
        n = int(ts.cycle_frames[g])
        k = np.arange(n)
        np.testing.assert_array_equal(ts.inputs[rows, 0], ts.gait_ids[g])
        np.testing.assert_array_equal(ts.inputs[rows, 1], k / n)
        np.testing.assert_array_equal(ts.outputs[rows, 5], ((k + 1) % n) / n)
        # Each cycle has a stance phase that starts at heel strike (frame 0) and a swing.
        assert ts.stance[rows][0] and not ts.stance[rows][-1]
    assert ts.thigh_lengths_m.tolist() == [0.405, 0.475, 0.3765]


def _copy(tmp_path: Path) -> Path:
    out = tmp_path / "data"
    shutil.copytree(TRAINING_DATA, out)
    return out


def _edit(path: Path, old: str, new: str) -> None:
    text = path.read_text()
    assert old in text
    path.write_text(text.replace(old, new, 1))


def _line_of(path: Path, needle: str) -> int:
    for i, line in enumerate(path.read_text().splitlines(), start=1):
        if line.startswith(needle):
            return i
    raise AssertionError(needle)


@pytest.mark.parametrize(
    ("needle", "old", "new", "message"),
    [
        ("3,", "3,", "3,x", "non-numeric field"),
        ("3,", "3,", "4,", "frame must be 3"),
        ("5,", ",1\n", ",2\n", "stance must be 0 or 1"),
        ("2,", "2,", "2,0.5,", "expected 9 fields"),
        ("# gait_id", "# gait_id: 0.2", "# gait_id: 1.5", "gait_id must be in (0, 1)"),
        ("# fps", "# fps: 30", "# fps: 25", "fps must be 30"),
        ("# gait:", "# gait: walk", "# gait: Walk", "gait name 'Walk'"),
        ("frame,", "frame,completion", "frame,time", "expected the column line"),
    ],
)
def test_bad_rows_and_headers_are_located(
    tmp_path: Path, needle: str, old: str, new: str, message: str
) -> None:
    data = _copy(tmp_path)
    walk = data / "walk.csv"
    line = _line_of(walk, needle)
    lines = walk.read_text().splitlines(keepends=True)
    assert old in lines[line - 1]
    lines[line - 1] = lines[line - 1].replace(old, new, 1)
    walk.write_text("".join(lines))
    with pytest.raises(DataError) as err:
        load_training_set(data)
    assert f"{walk}:{line}:" in str(err.value)
    assert message in str(err.value)


def test_wrong_completion_is_located(tmp_path: Path) -> None:
    data = _copy(tmp_path)
    walk = data / "walk.csv"
    line = _line_of(walk, "7,")
    lines = walk.read_text().splitlines(keepends=True)
    fields = lines[line - 1].split(",")
    fields[1] = "0.5"
    lines[line - 1] = ",".join(fields)
    walk.write_text("".join(lines))
    with pytest.raises(DataError, match=rf"{walk}:{line}: completion must be 7/"):
        load_training_set(data)


def test_missing_rows_missing_keys_duplicates_and_encoding(tmp_path: Path) -> None:
    data = _copy(tmp_path)
    walk = data / "walk.csv"
    original = walk.read_text()
    walk.write_text(original.rsplit("\n", 2)[0] + "\n")  # drop the last row
    with pytest.raises(DataError, match=r"header says \d+ frames, found \d+ rows"):
        load_training_set(data)
    walk.write_text(original.replace("# thigh_length_m: 0.405\n", ""))
    with pytest.raises(DataError, match=r"thigh_length_m: \.\.\.' is missing"):
        load_training_set(data)
    walk.write_text(original.replace("# gait_id: 0.2", "# gait_id: 0.4"))
    with pytest.raises(DataError, match="gait ids must be unique"):
        load_training_set(data)
    walk.write_text(original.replace("# gait: walk", "# gait: run"))
    with pytest.raises(DataError, match="gait names must be unique"):
        load_training_set(data)
    walk.write_bytes(b"\xff\xfe" + original.encode())
    with pytest.raises(DataError, match="not UTF-8"):
        load_training_set(data)


def test_empty_or_missing_directory(tmp_path: Path) -> None:
    with pytest.raises(DataError, match=r"no \*\.csv cycle files"):
        load_training_set(tmp_path)
    with pytest.raises(DataError, match="not found"):
        load_training_set(tmp_path / "nope")


def test_non_finite_values_are_rejected() -> None:
    text = (TRAINING_DATA / "run.csv").read_text()
    header, rows = text.split(",".join(COLUMNS) + "\n")
    first, rest = rows.split("\n", 1)
    fields = first.split(",")
    fields[2] = "nan"
    bad = header + ",".join(COLUMNS) + "\n" + ",".join(fields) + "\n" + rest
    with pytest.raises(DataError, match="non-finite"):
        parse_cycle(bad, path="run.csv")
