"""Which scripts a batch renders, where their outputs go, and leftovers of a killed batch.

Inputs are every ``*.gait`` file under ``INPUT_DIR`` (recursively, hidden directories
included only if named explicitly as INPUT_DIR); each is known by its POSIX path relative to
``INPUT_DIR`` (``shots/a.gait``), and its outputs keep that relative path with the format's
extension (``OUT_DIR/shots/a.usdc``).
"""

from __future__ import annotations

import re
from pathlib import Path, PurePosixPath

from animstudio.errors import DataError

SCRIPT_SUFFIX = ".gait"

# animstudio.export.atomic.temporary_sibling names: ".{stem}.tmp-{pid}-{6 hex}{suffix}".
_TEMPORARY = re.compile(r"^\..*\.tmp-\d+-[0-9a-f]{6}(\.[A-Za-z0-9]+)*$")


def find_scripts(input_dir: Path) -> tuple[str, ...]:
    """Relative POSIX paths of every ``*.gait`` file under ``input_dir``, sorted.

    Files inside hidden directories (``.git``, ``.cache`` ...) below ``input_dir`` are skipped.

    Raises:
        DataError: ``input_dir`` is not a directory or holds no script.
    """
    if not input_dir.is_dir():
        what = "does not exist" if not input_dir.exists() else "is not a directory"
        raise DataError(f"{input_dir}: input directory {what}")
    found: list[str] = []
    for path in input_dir.rglob(f"*{SCRIPT_SUFFIX}"):
        rel = path.relative_to(input_dir)
        if not path.is_file() or any(part.startswith(".") for part in rel.parts[:-1]):
            continue
        found.append(rel.as_posix())
    if not found:
        raise DataError(f"{input_dir}: no *{SCRIPT_SUFFIX} scripts found (searched recursively)")
    return tuple(sorted(found))


def output_relpath(script_rel: str, fmt: str) -> str:
    """``shots/a.gait`` with format ``usdc`` -> ``shots/a.usdc``."""
    return PurePosixPath(script_rel).with_suffix(f".{fmt}").as_posix()


def is_temporary(path: Path) -> bool:
    """Whether ``path`` is named like a temporary of :mod:`animstudio.export.atomic`."""
    return bool(_TEMPORARY.match(path.name))


def remove_temporaries(out_dir: Path) -> list[Path]:
    """Delete leftover atomic-write temporaries under ``out_dir`` (a killed batch's in-flight work).

    Only names matching :func:`is_temporary` are touched. Call this only while holding the
    batch lock (:mod:`animstudio.batch.runner`), when no writer of this directory is running.
    """
    removed: list[Path] = []
    if not out_dir.is_dir():
        return removed
    for path in out_dir.rglob(".*.tmp-*"):
        if path.is_file() and is_temporary(path):
            path.unlink(missing_ok=True)
            removed.append(path)
    return removed
