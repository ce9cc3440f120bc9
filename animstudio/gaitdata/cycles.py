"""The training-cycle file format (one CSV per gait) and the training set built from it.

A cycle file (``training_data/<gait>.csv``, documented in training_data/README.md) is UTF-8 text:

* a header of ``# key: value`` lines (free ``#`` comment lines may sit among them). Required keys:
  ``format`` (``animstudio-gait-cycle 1``), ``gait`` (a lowercase name), ``gait_id`` (in (0, 1)),
  ``fps`` (30), ``frames`` (N), ``thigh_length_m`` (the subject's thigh, > 0);
* the column line :data:`COLUMNS`;
* N rows, row ``k`` being the thesis's training pattern for frame ``k``: input (gait id from the
  header, ``completion = k/N``), output (``thigh_deg``, ``shank_deg``, ``foot_deg``,
  ``hip_dx_thigh``, ``hip_dy_thigh`` — hip displacement from frame k to k+1 in the subject's
  thigh lengths — and ``next_completion = ((k+1) mod N)/N``), plus ``stance`` (1 while the
  foot is on the ground, between heel strike and toe-off).
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from animstudio.errors import DataError

FORMAT = "animstudio-gait-cycle 1"
COLUMNS = (
    "frame",
    "completion",
    "thigh_deg",
    "shank_deg",
    "foot_deg",
    "hip_dx_thigh",
    "hip_dy_thigh",
    "next_completion",
    "stance",
)
FPS = 30
"""The thesis's rate: one Markov state every 1/30 s."""

REQUIRED_KEYS = ("format", "gait", "gait_id", "fps", "frames", "thigh_length_m")
_NAME = re.compile(r"[a-z][a-z0-9_]*\Z")
_COMPLETION_TOL = 5e-7  # completions are written with 6 decimals


@dataclass(frozen=True)
class Cycle:
    """One gait's closed cycle, as written to / read from a cycle file.

    Attributes:
        gait: the gait's name (the script vocabulary).
        gait_id: the thesis's gait identifier, in (0, 1).
        thigh_length_m: the subject's thigh length (hip deltas are in these units).
        angles_deg: ``(N, 3)`` Q, F, Y per frame (degrees).
        hip_delta_thigh: ``(N, 2)`` hip Δx, Δy from frame k to k+1 (subject thigh lengths).
        stance: ``(N,)`` bool, foot on the ground.
        header: ``key -> value`` metadata lines in file order (provenance, licence, derivation).
    """

    gait: str
    gait_id: float
    thigh_length_m: float
    angles_deg: NDArray[np.float64]
    hip_delta_thigh: NDArray[np.float64]
    stance: NDArray[np.bool_]
    header: Mapping[str, str]

    @property
    def num_frames(self) -> int:
        return int(self.angles_deg.shape[0])


@dataclass(frozen=True, eq=False)
class TrainingSet:
    """All training patterns, gaits in ascending gait-id order, frames in cycle order.

    Attributes:
        gait_names: ``(G,)`` names.
        gait_ids: ``(G,)`` identifiers (thesis: walk 0.2, run 0.4, climb 0.6).
        inputs: ``(P, 2) float64`` (gait id, completion ``k/N``).
        outputs: ``(P, 6) float64`` (Q deg, F deg, Y deg, hip Δx, Δy in thigh lengths, next completion).
        stance: ``(P,) bool`` the pattern's foot is on the ground.
        gait_index: ``(P,) int64`` index into ``gait_names`` of each pattern.
        cycle_frames: ``(G,)`` N per gait.
        thigh_lengths_m: ``(G,)`` the subjects' thigh lengths.
    """

    gait_names: tuple[str, ...]
    gait_ids: NDArray[np.float64]
    inputs: NDArray[np.float64]
    outputs: NDArray[np.float64]
    stance: NDArray[np.bool_]
    gait_index: NDArray[np.int64]
    cycle_frames: NDArray[np.int64]
    thigh_lengths_m: NDArray[np.float64]

    def __post_init__(self) -> None:
        p = self.inputs.shape[0]
        assert self.inputs.shape == (p, 2) and self.outputs.shape == (p, 6)
        assert self.stance.shape == (p,) and self.gait_index.shape == (p,)
        assert int(self.cycle_frames.sum()) == p
        for arr in (self.gait_ids, self.inputs, self.outputs, self.stance, self.gait_index):
            arr.setflags(write=False)
        self.cycle_frames.setflags(write=False)
        self.thigh_lengths_m.setflags(write=False)

    @property
    def num_patterns(self) -> int:
        return int(self.inputs.shape[0])

    def patterns_of(self, gait: str) -> slice:
        """The rows of ``inputs``/``outputs`` that belong to ``gait`` (contiguous)."""
        g = self.gait_names.index(gait)
        start = int(self.cycle_frames[:g].sum())
        return slice(start, start + int(self.cycle_frames[g]))


def format_cycle(cycle: Cycle) -> str:
    """The text of a cycle file (deterministic: fixed decimals, keys in ``cycle.header`` order)."""
    n = cycle.num_frames
    lines = [f"# {key}: {value}" for key, value in cycle.header.items()]
    lines.append(",".join(COLUMNS))
    for k in range(n):
        q, f, y = cycle.angles_deg[k]
        dx, dy = cycle.hip_delta_thigh[k]
        lines.append(
            f"{k},{k / n:.6f},{q:.4f},{f:.4f},{y:.4f},{dx:.6f},{dy:.6f},"
            f"{((k + 1) % n) / n:.6f},{int(bool(cycle.stance[k]))}"
        )
    return "\n".join(lines) + "\n"


def parse_cycle(text: str, *, path: str) -> Cycle:
    """Read a cycle file's text; every problem is a :class:`DataError` ``path:line: ...``."""
    header: dict[str, str] = {}
    header_line: dict[str, int] = {}
    lines = text.splitlines()
    row_start = None
    for i, line in enumerate(lines, start=1):
        if line.startswith("#"):
            m = re.match(r"#\s*([A-Za-z_][A-Za-z0-9_]*)\s*:\s*(.*?)\s*\Z", line)
            if m and m.group(1) not in header:
                header[m.group(1)] = m.group(2)
                header_line[m.group(1)] = i
            continue
        if line.strip() == "":
            continue
        if line.strip() != ",".join(COLUMNS):
            raise DataError(f"{path}:{i}: expected the column line {','.join(COLUMNS)!r}")
        row_start = i
        break
    if row_start is None:
        raise DataError(f"{path}: no column line {','.join(COLUMNS)!r} found")
    for key in REQUIRED_KEYS:
        if key not in header:
            raise DataError(f"{path}: header key '# {key}: ...' is missing")

    def number(key: str) -> float:
        try:
            value = float(header[key])
        except ValueError:
            raise DataError(f"{path}:{header_line[key]}: {key} must be a number") from None
        if not math.isfinite(value):
            raise DataError(f"{path}:{header_line[key]}: {key} must be finite")
        return value

    if header["format"] != FORMAT:
        raise DataError(f"{path}:{header_line['format']}: unsupported format, expected {FORMAT!r}")
    gait = header["gait"]
    if not _NAME.match(gait):
        raise DataError(
            f"{path}:{header_line['gait']}: gait name {gait!r} must match [a-z][a-z0-9_]*"
        )
    gait_id = number("gait_id")
    if not 0.0 < gait_id < 1.0:
        raise DataError(
            f"{path}:{header_line['gait_id']}: gait_id must be in (0, 1), got {gait_id}"
        )
    if number("fps") != FPS:
        raise DataError(f"{path}:{header_line['fps']}: fps must be {FPS} (the thesis's rate)")
    n_float = number("frames")
    if n_float != int(n_float) or n_float < 2:
        raise DataError(f"{path}:{header_line['frames']}: frames must be an integer >= 2")
    n = int(n_float)
    thigh = number("thigh_length_m")
    if not thigh > 0:
        raise DataError(f"{path}:{header_line['thigh_length_m']}: thigh_length_m must be > 0")

    rows: list[list[float]] = []
    for i, line in enumerate(lines[row_start:], start=row_start + 1):
        if line.strip() == "":
            continue
        fields = line.split(",")
        if len(fields) != len(COLUMNS):
            raise DataError(f"{path}:{i}: expected {len(COLUMNS)} fields, got {len(fields)}")
        try:
            values = [float(v) for v in fields]
        except ValueError:
            raise DataError(f"{path}:{i}: non-numeric field in {line!r}") from None
        if not all(math.isfinite(v) for v in values):
            raise DataError(f"{path}:{i}: non-finite value in {line!r}")
        k = len(rows)
        if values[0] != k:
            raise DataError(f"{path}:{i}: frame must be {k}, got {fields[0]}")
        if abs(values[1] - k / n) > _COMPLETION_TOL:
            raise DataError(f"{path}:{i}: completion must be {k}/{n} = {k / n:.6f}")
        if abs(values[7] - ((k + 1) % n) / n) > _COMPLETION_TOL:
            raise DataError(f"{path}:{i}: next_completion must be {((k + 1) % n) / n:.6f}")
        if values[8] not in (0.0, 1.0):
            raise DataError(f"{path}:{i}: stance must be 0 or 1, got {fields[8]}")
        rows.append(values)
    if len(rows) != n:
        raise DataError(f"{path}: header says {n} frames, found {len(rows)} rows")
    data = np.array(rows, dtype=np.float64)
    return Cycle(
        gait=gait,
        gait_id=gait_id,
        thigh_length_m=thigh,
        angles_deg=data[:, 2:5],
        hip_delta_thigh=data[:, 5:7],
        stance=data[:, 8] == 1.0,
        header=header,
    )


def build_training_set(cycles: Sequence[Cycle]) -> TrainingSet:
    """Patterns of ``cycles`` in ascending gait-id order (names and ids must be unique)."""
    ordered = sorted(cycles, key=lambda c: c.gait_id)
    names = [c.gait for c in ordered]
    if len(set(names)) != len(names):
        raise DataError(f"gait names must be unique, got {names}")
    ids = [c.gait_id for c in ordered]
    if len(set(ids)) != len(ids):
        raise DataError(f"gait ids must be unique, got {dict(zip(names, ids, strict=True))}")
    inputs, outputs, stance, index = [], [], [], []
    for g, c in enumerate(ordered):
        n = c.num_frames
        k = np.arange(n)
        inputs.append(np.column_stack([np.full(n, c.gait_id), k / n]))
        outputs.append(np.column_stack([c.angles_deg, c.hip_delta_thigh, ((k + 1) % n) / n]))
        stance.append(c.stance)
        index.append(np.full(n, g, dtype=np.int64))
    return TrainingSet(
        gait_names=tuple(names),
        gait_ids=np.array(ids, dtype=np.float64),
        inputs=np.concatenate(inputs),
        outputs=np.concatenate(outputs),
        stance=np.concatenate(stance).astype(bool),
        gait_index=np.concatenate(index),
        cycle_frames=np.array([c.num_frames for c in ordered], dtype=np.int64),
        thigh_lengths_m=np.array([c.thigh_length_m for c in ordered], dtype=np.float64),
    )


def load_training_set(directory: Path) -> TrainingSet:
    """Every ``*.csv`` cycle file in ``directory`` as one :class:`TrainingSet`.

    Raises:
        DataError: no cycle files, unreadable or malformed files (located ``file:line``),
            duplicate gait names or ids.
    """
    directory = Path(directory)
    if not directory.is_dir():
        raise DataError(f"{directory}: training data directory not found")
    files = sorted(directory.glob("*.csv"))
    if not files:
        raise DataError(f"{directory}: no *.csv cycle files (see training_data/README.md)")
    cycles = []
    for path in files:
        try:
            text = path.read_text(encoding="utf-8")
        except UnicodeDecodeError as exc:
            raise DataError(f"{path}: not UTF-8 text ({exc.reason})") from None
        except OSError as exc:
            raise DataError(f"{path}: cannot read: {exc.strerror or exc}") from None
        cycles.append(parse_cycle(text, path=str(path)))
    return build_training_set(cycles)
