"""CSV export of a clip's joint curves, one row per frame, for analysis (docs/batch.md).

Columns, in order (units in every header name):

- ``frame``: frame index ``k``; ``time_s``: ``k / fps`` seconds;
- ``root_x_m, root_y_m, root_z_m``: the root joint's world translation in metres
  (Y up, +X forward, +Z right; docs/conventions.md);
- every curve of ``clip.curves`` in its own order, under its own name (curve names carry their
  unit by convention: ``left_thigh_deg``);
- for every joint in skeleton order, its local rotation ``T_parent_joint`` as a unit quaternion,
  ``<joint>_quat_w, <joint>_quat_x, <joint>_quat_y, <joint>_quat_z`` (dimensionless, wxyz).

Numbers are written with 9 significant digits (float32 rotations round-trip exactly).
"""

from __future__ import annotations

import io
from pathlib import Path

import numpy as np

from animstudio.core.clip import Clip
from animstudio.errors import ExportError
from animstudio.export import atomic

_FIXED = ("frame", "time_s", "root_x_m", "root_y_m", "root_z_m")


def csv_header(clip: Clip) -> list[str]:
    """The column names of :func:`build_csv` for ``clip``."""
    names = list(_FIXED) + list(clip.curves)
    for joint in clip.skeleton.joint_names:
        names += [f"{joint}_quat_{c}" for c in "wxyz"]
    if len(set(names)) != len(names):
        dup = sorted({n for n in names if names.count(n) > 1})
        raise ExportError(
            f"CSV export: duplicate column names {', '.join(dup)} (a curve shadows a fixed column)"
        )
    return names


def build_csv(clip: Clip) -> str:
    """The CSV text of ``clip`` (columns in the module docstring), ``\\n`` line ends."""
    header = csv_header(clip)
    for name in header:
        if any(ch in name for ch in ',"\n\r'):
            raise ExportError(
                f"CSV export: column name {name!r} contains a comma, quote or line break"
            )
    n = clip.num_frames
    frames = np.arange(n, dtype=np.float64)
    columns = [
        frames[:, None],
        (frames / clip.fps)[:, None],
        clip.root_translations,
    ]
    columns += [np.asarray(v, dtype=np.float64)[:, None] for v in clip.curves.values()]
    columns.append(clip.local_rotations.astype(np.float64).reshape(n, -1))
    table = np.concatenate(columns, axis=1)
    buf = io.StringIO()
    buf.write(",".join(header) + "\n")
    # The frame column is an integer; savetxt with one format per column keeps it so.
    fmt = ["%d"] + ["%.9g"] * (table.shape[1] - 1)
    np.savetxt(buf, table, fmt=fmt, delimiter=",", newline="\n")
    return buf.getvalue()


def write_csv(path: Path, clip: Clip) -> None:
    """Write ``clip`` as CSV to ``path`` atomically."""
    atomic.write_text(Path(path), build_csv(clip))
