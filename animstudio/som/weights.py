"""The Kohonen weights file: a deterministic ``.npz`` read with ``allow_pickle=False``.

Arrays (``R x C`` map, ``G`` gaits):

=====================  ============  ==================================================
key                    shape, dtype  meaning
=====================  ============  ==================================================
format_version         () int64      :data:`FORMAT_VERSION`
input_weights          (R, C, 2) f8  competitive layer (gait id, completion)
outputs                (R, C, 6) f8  Q, F, Y deg; hip Δx, Δy (thigh lengths); next completion
won                    (R, C) bool   the unit won at least one training presentation
pattern_winner         (R, C) bool   the unit wins a training pattern with the final weights
stance                 (R, C) bool   the foot is on the ground in the unit's pattern
gait_names             (G,) <U       the script vocabulary, ascending gait id
gait_ids               (G,) f8       thesis identifiers (walk 0.2, run 0.4, climb 0.6)
thigh_lengths_m        (G,) f8       training subjects' thigh lengths
cycle_frames           (G,) int64    frames per training cycle
map_shape              (2,) int64    R, C
learning_rate          () f8         initial learning rate
radius                 () int64      initial neighbourhood radius (units)
presentations          () int64      pattern presentations
seed                   () int64      PCG64 seed
=====================  ============  ==================================================

The zip container is written by hand (members stored uncompressed, sorted, with a fixed
1980-01-01 timestamp) so the same weights always give the same bytes; ``numpy.savez`` stamps
the current time into every member.
"""

from __future__ import annotations

import io
import zipfile
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from animstudio.errors import DataError
from animstudio.export.atomic import write_bytes
from animstudio.gaitdata.cycles import TrainingSet
from animstudio.som.training import TrainedMap, TrainingSettings, train

FORMAT_VERSION = 1
_ZIP_TIME = (1980, 1, 1, 0, 0, 0)


@dataclass(frozen=True, eq=False)
class SomWeights:
    """A trained map plus what a controller needs to drive a character with it.

    Attributes:
        trained: the map (input weights, outputs, won and stance masks).
        gait_names: script vocabulary, ascending gait id.
        gait_ids: ``(G,)`` identifiers.
        thigh_lengths_m: ``(G,)`` subjects' thigh lengths.
        cycle_frames: ``(G,)`` frames of each training cycle.
        settings: how the map was trained.
    """

    trained: TrainedMap
    gait_names: tuple[str, ...]
    gait_ids: NDArray[np.float64]
    thigh_lengths_m: NDArray[np.float64]
    cycle_frames: NDArray[np.int64]
    settings: TrainingSettings

    def gait_id(self, gait: str) -> float:
        """The identifier of ``gait`` (a name from :attr:`gait_names`)."""
        return float(self.gait_ids[self.gait_names.index(gait)])


def train_weights(
    data: TrainingSet,
    settings: TrainingSettings | None = None,
    *,
    progress: Callable[[int], None] | None = None,
) -> SomWeights:
    """Train a map on ``data`` and bundle it with the gait vocabulary (what ``animstudio train`` writes)."""
    settings = settings or TrainingSettings()
    return SomWeights(
        trained=train(data, settings, progress=progress),
        gait_names=data.gait_names,
        gait_ids=np.array(data.gait_ids, dtype=np.float64),
        thigh_lengths_m=np.array(data.thigh_lengths_m, dtype=np.float64),
        cycle_frames=np.array(data.cycle_frames, dtype=np.int64),
        settings=settings,
    )


def to_arrays(weights: SomWeights) -> dict[str, NDArray[np.generic]]:
    """The file's arrays (module docstring table)."""
    s = weights.settings
    return {
        "format_version": np.array(FORMAT_VERSION, dtype=np.int64),
        "input_weights": np.asarray(weights.trained.input_weights, dtype=np.float64),
        "outputs": np.asarray(weights.trained.outputs, dtype=np.float64),
        "won": np.asarray(weights.trained.won, dtype=bool),
        "stance": np.asarray(weights.trained.stance, dtype=bool),
        "pattern_winner": np.asarray(weights.trained.pattern_winner, dtype=bool),
        "gait_names": np.array(weights.gait_names, dtype=np.str_),
        "gait_ids": np.asarray(weights.gait_ids, dtype=np.float64),
        "thigh_lengths_m": np.asarray(weights.thigh_lengths_m, dtype=np.float64),
        "cycle_frames": np.asarray(weights.cycle_frames, dtype=np.int64),
        "map_shape": np.array(s.map_shape, dtype=np.int64),
        "learning_rate": np.array(s.learning_rate, dtype=np.float64),
        "radius": np.array(s.radius, dtype=np.int64),
        "presentations": np.array(s.presentations, dtype=np.int64),
        "seed": np.array(s.seed, dtype=np.int64),
    }


def to_bytes(weights: SomWeights) -> bytes:
    """The ``.npz`` file's bytes (deterministic)."""
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w", compression=zipfile.ZIP_STORED) as zf:
        for key, arr in sorted(to_arrays(weights).items()):
            member = io.BytesIO()
            np.lib.format.write_array(member, np.asarray(arr, order="C"), allow_pickle=False)
            info = zipfile.ZipInfo(f"{key}.npy", date_time=_ZIP_TIME)
            info.external_attr = 0o644 << 16
            zf.writestr(info, member.getvalue())
    return buf.getvalue()


def save_weights(path: Path, weights: SomWeights) -> None:
    """Write ``weights`` to ``path`` atomically (never a partial file)."""
    write_bytes(Path(path), to_bytes(weights))


_EXPECTED: dict[str, tuple[str, int]] = {
    # key: (dtype kind, ndim)
    "format_version": ("i", 0),
    "input_weights": ("f", 3),
    "outputs": ("f", 3),
    "won": ("b", 2),
    "stance": ("b", 2),
    "pattern_winner": ("b", 2),
    "gait_names": ("U", 1),
    "gait_ids": ("f", 1),
    "thigh_lengths_m": ("f", 1),
    "cycle_frames": ("i", 1),
    "map_shape": ("i", 1),
    "learning_rate": ("f", 0),
    "radius": ("i", 0),
    "presentations": ("i", 0),
    "seed": ("i", 0),
}


def load_weights(path: Path) -> SomWeights:
    """Read and validate a weights file.

    Raises:
        DataError: missing, unreadable, corrupt or truncated file, missing keys, wrong dtypes or
            shapes, NaNs, or an unsupported format version (the message says which).
    """
    path = Path(path)
    if not path.is_file():
        raise DataError(f"{path}: weights file not found")
    try:
        with np.load(path, allow_pickle=False) as npz:
            arrays = {key: npz[key] for key in npz.files}
    except (OSError, ValueError, EOFError, zipfile.BadZipFile, KeyError) as exc:
        raise DataError(
            f"{path}: not a readable weights file (corrupt or truncated?): {exc}"
        ) from None
    return from_arrays(arrays, source=str(path))


def from_arrays(arrays: dict[str, NDArray[np.generic]], *, source: str) -> SomWeights:
    """Validate the arrays of a weights file (see :func:`load_weights`)."""
    missing = sorted(set(_EXPECTED) - set(arrays))
    if missing:
        raise DataError(f"{source}: not an animstudio weights file, missing {', '.join(missing)}")
    for key, (kind, ndim) in _EXPECTED.items():
        arr = arrays[key]
        if arr.dtype.kind != kind or arr.ndim != ndim:
            raise DataError(
                f"{source}: '{key}' must be a {ndim}-D array of kind '{kind}', "
                f"got {arr.ndim}-D {arr.dtype}"
            )
    version = int(arrays["format_version"])
    if version != FORMAT_VERSION:
        raise DataError(
            f"{source}: weights format version {version} is not supported "
            f"(this animstudio reads version {FORMAT_VERSION}; retrain with 'animstudio train')"
        )
    shape = tuple(int(v) for v in arrays["map_shape"])
    if len(shape) != 2 or min(shape) < 1:
        raise DataError(f"{source}: map_shape must be two positive integers, got {shape}")
    rows, cols = shape
    for key, want in (
        ("input_weights", (rows, cols, 2)),
        ("outputs", (rows, cols, 6)),
        ("won", (rows, cols)),
        ("stance", (rows, cols)),
        ("pattern_winner", (rows, cols)),
    ):
        if arrays[key].shape != want:
            raise DataError(f"{source}: '{key}' must have shape {want}, got {arrays[key].shape}")
    names = tuple(str(n) for n in arrays["gait_names"])
    g = len(names)
    if g == 0 or len(set(names)) != g:
        raise DataError(f"{source}: gait_names must be non-empty and unique, got {list(names)}")
    for key in ("gait_ids", "thigh_lengths_m", "cycle_frames"):
        if arrays[key].shape != (g,):
            raise DataError(
                f"{source}: '{key}' must have one value per gait ({g}), got {arrays[key].shape}"
            )
    for key in ("input_weights", "outputs", "gait_ids", "thigh_lengths_m", "learning_rate"):
        if not np.all(np.isfinite(arrays[key])):
            raise DataError(f"{source}: '{key}' contains NaN or infinite values")
    if not np.any(arrays["pattern_winner"]):
        raise DataError(f"{source}: no unit wins a training pattern; the map is unusable")
    if np.any(
        np.asarray(arrays["pattern_winner"], dtype=bool) & ~np.asarray(arrays["won"], dtype=bool)
    ):
        raise DataError(f"{source}: 'pattern_winner' marks units that never won")
    if np.any(np.asarray(arrays["thigh_lengths_m"], dtype=np.float64) <= 0.0):
        raise DataError(f"{source}: thigh_lengths_m must be positive")
    try:
        settings = TrainingSettings(
            map_shape=(rows, cols),
            learning_rate=float(arrays["learning_rate"]),
            radius=int(arrays["radius"]),
            presentations=int(arrays["presentations"]),
            seed=int(arrays["seed"]),
        )
    except ValueError as exc:
        raise DataError(f"{source}: bad training settings: {exc}") from None
    trained = TrainedMap(
        input_weights=np.asarray(arrays["input_weights"], dtype=np.float64),
        outputs=np.asarray(arrays["outputs"], dtype=np.float64),
        won=np.asarray(arrays["won"], dtype=bool),
        stance=np.asarray(arrays["stance"], dtype=bool),
        pattern_winner=np.asarray(arrays["pattern_winner"], dtype=bool),
    )
    for arr in (
        trained.input_weights,
        trained.outputs,
        trained.won,
        trained.stance,
        trained.pattern_winner,
    ):
        arr.setflags(write=False)
    return SomWeights(
        trained=trained,
        gait_names=names,
        gait_ids=np.asarray(arrays["gait_ids"], dtype=np.float64),
        thigh_lengths_m=np.asarray(arrays["thigh_lengths_m"], dtype=np.float64),
        cycle_frames=np.asarray(arrays["cycle_frames"], dtype=np.int64),
        settings=settings,
    )


DEFAULT_WEIGHTS = Path(__file__).resolve().parent.parent / "data" / "som_default.npz"
"""The shipped weights: ``animstudio train training_data --seed`` :data:`DEFAULT_SEED`."""

DEFAULT_SEED = 0
"""Seed of the shipped weights (also :class:`TrainingSettings`'s default)."""
