"""The weights file: deterministic bytes, strict loading, and the shipped file's reproducibility."""

from __future__ import annotations

import io
import zipfile
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from animstudio.cli import main
from animstudio.errors import DataError
from animstudio.gaitdata import TrainingSet
from animstudio.som.training import TrainingSettings
from animstudio.som.weights import (
    DEFAULT_SEED,
    DEFAULT_WEIGHTS,
    SomWeights,
    load_weights,
    save_weights,
    to_arrays,
    to_bytes,
    train_weights,
)

TRAINING_DATA = Path(__file__).resolve().parents[2] / "training_data"


def test_cli_train_reproduces_the_shipped_weights(tmp_path: Path) -> None:
    out = tmp_path / "W.npz"
    result = CliRunner().invoke(
        main, ["train", str(TRAINING_DATA), "-o", str(out), "--seed", str(DEFAULT_SEED)]
    )
    assert result.exit_code == 0, result.output
    assert out.read_bytes() == DEFAULT_WEIGHTS.read_bytes()
    shipped, again = load_weights(DEFAULT_WEIGHTS), load_weights(out)
    for key, arr in to_arrays(shipped).items():
        np.testing.assert_array_equal(arr, to_arrays(again)[key], err_msg=key)
    assert shipped.settings == TrainingSettings(seed=DEFAULT_SEED)
    assert shipped.gait_names == ("walk", "run", "climb")


def test_round_trip(tmp_path: Path, training_set: TrainingSet) -> None:
    w = train_weights(training_set, TrainingSettings(map_shape=(20, 30), presentations=500))
    save_weights(tmp_path / "w.npz", w)
    back = load_weights(tmp_path / "w.npz")
    assert back.settings == w.settings and back.gait_names == w.gait_names
    for key, arr in to_arrays(w).items():
        np.testing.assert_array_equal(arr, to_arrays(back)[key], err_msg=key)
    assert to_bytes(back) == to_bytes(w)


def _write(path: Path, arrays: dict[str, np.ndarray]) -> Path:
    np.savez(path, **arrays)
    return path


@pytest.fixture()
def arrays(shipped: SomWeights) -> dict[str, np.ndarray]:
    return {k: np.array(v) for k, v in to_arrays(shipped).items()}


def test_corrupt_truncated_and_missing_files(tmp_path: Path) -> None:
    with pytest.raises(DataError, match="not found"):
        load_weights(tmp_path / "none.npz")
    junk = tmp_path / "junk.npz"
    junk.write_bytes(b"this is not a zip file at all" * 10)
    with pytest.raises(DataError, match="corrupt or truncated"):
        load_weights(junk)
    cut = tmp_path / "cut.npz"
    cut.write_bytes(DEFAULT_WEIGHTS.read_bytes()[:50_000])
    with pytest.raises(DataError, match="corrupt or truncated"):
        load_weights(cut)
    pickled = tmp_path / "pickled.npz"
    buf = io.BytesIO()
    np.save(buf, np.array([{"a": 1}], dtype=object), allow_pickle=True)
    with zipfile.ZipFile(pickled, "w") as zf:
        zf.writestr("outputs.npy", buf.getvalue())
    with pytest.raises(DataError):
        load_weights(pickled)


def test_missing_key(tmp_path: Path, arrays: dict[str, np.ndarray]) -> None:
    del arrays["won"]
    with pytest.raises(DataError, match="missing won"):
        load_weights(_write(tmp_path / "w.npz", arrays))


def test_wrong_shapes(tmp_path: Path, arrays: dict[str, np.ndarray]) -> None:
    bad = dict(arrays, outputs=arrays["outputs"][:, :, :5])
    with pytest.raises(DataError, match=r"'outputs' must have shape \(40, 40, 6\)"):
        load_weights(_write(tmp_path / "a.npz", bad))
    bad = dict(arrays, gait_ids=arrays["gait_ids"][:2])
    with pytest.raises(DataError, match="one value per gait"):
        load_weights(_write(tmp_path / "b.npz", bad))
    bad = dict(arrays, won=arrays["won"].astype(np.float64))
    with pytest.raises(DataError, match="'won' must be a 2-D array of kind 'b'"):
        load_weights(_write(tmp_path / "c.npz", bad))


def test_nans_and_version(tmp_path: Path, arrays: dict[str, np.ndarray]) -> None:
    bad = {k: v.copy() for k, v in arrays.items()}
    bad["input_weights"][3, 4, 1] = np.nan
    with pytest.raises(DataError, match="'input_weights' contains NaN"):
        load_weights(_write(tmp_path / "a.npz", bad))
    bad = dict(arrays, format_version=np.array(99, dtype=np.int64))
    with pytest.raises(DataError, match="format version 99 is not supported"):
        load_weights(_write(tmp_path / "b.npz", bad))


def test_cli_train_errors(tmp_path: Path) -> None:
    runner = CliRunner()
    result = runner.invoke(main, ["train", str(tmp_path / "nope"), "-o", str(tmp_path / "w.npz")])
    assert result.exit_code == 1 and "not found" in result.output
    result = runner.invoke(main, ["train", str(TRAINING_DATA), "-o", str(tmp_path / "w.txt")])
    assert result.exit_code == 1 and "must end in .npz" in result.output
    result = runner.invoke(
        main, ["train", str(TRAINING_DATA), "-o", str(tmp_path / "w.npz"), "--map-size", "40"]
    )
    assert result.exit_code == 2 and "ROWSxCOLS" in result.output
    assert not (tmp_path / "w.npz").exists()
    result = runner.invoke(
        main,
        [
            "train",
            str(TRAINING_DATA),
            "-o",
            str(tmp_path / "w.npz"),
            "--map-size",
            "12x9",
            "--presentations",
            "300",
        ],
    )
    assert result.exit_code == 0, result.output
    assert load_weights(tmp_path / "w.npz").trained.won.shape == (12, 9)
