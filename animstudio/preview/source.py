"""What the preview shows: a Clip loaded from a gait script or an exported USD file.

Scripts go through the product's one path (:func:`animstudio.pipeline.load_script` then
:func:`~animstudio.pipeline.render`), USD files through
:func:`animstudio.export.usd_read.read_clip` (UsdSkel), so the preview shows exactly the rig and
mesh an export carries.
"""

from __future__ import annotations

import hashlib
import os
from dataclasses import dataclass
from pathlib import Path
from typing import Literal

from animstudio.core.clip import Clip
from animstudio.engines import EngineOptions
from animstudio.errors import DataError

SourceKind = Literal["script", "usd"]
USD_SUFFIXES = (".usd", ".usda", ".usdc")


def source_kind(path: Path) -> SourceKind:
    """``usd`` for ``.usd/.usda/.usdc`` files, ``script`` for anything else (``.gait``)."""
    return "usd" if path.suffix.lower() in USD_SUFFIXES else "script"


def check_source(path: Path) -> None:
    """Raise :class:`DataError` if ``path`` is not an existing file (before starting a server)."""
    if not path.exists():
        raise DataError(f"{path}: no such file")
    if not path.is_file():
        raise DataError(f"{path}: not a file")


def load_clip(path: Path, *, options: EngineOptions | None = None) -> Clip:
    """Render the script at ``path``, or read the clip of the USD file at ``path``.

    Raises:
        ScriptErrors, ScriptError: the script has located problems.
        DataError: the file is unreadable, or not a valid UsdSkel animation.
        SimulationError: the engine could not run the script's settings.
    """
    if source_kind(path) == "usd":
        from animstudio.export.usd_read import read_clip

        return read_clip(path)
    from animstudio import pipeline

    return pipeline.render(pipeline.load_script(path, options=options), options=options)


@dataclass(frozen=True)
class Fingerprint:
    """Identity of a file's contents, for noticing saves.

    mtime and size are cheap and change on every save (nanosecond timestamps); the hash, taken
    only when they change, tells a real edit from a ``touch`` or a save of unchanged text.
    """

    mtime_ns: int
    size: int
    sha256: str


def fingerprint(path: Path) -> Fingerprint | None:
    """The file's :class:`Fingerprint`, or ``None`` while it is missing (mid-save by some editors)."""
    try:
        st = os.stat(path)
        data = path.read_bytes()
    except OSError:
        return None
    return Fingerprint(st.st_mtime_ns, st.st_size, hashlib.sha256(data).hexdigest())
