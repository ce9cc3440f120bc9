"""One lookup from an output file's extension to its writer, shared by ``render`` and ``batch``."""

from __future__ import annotations

import importlib
from collections.abc import Callable
from pathlib import Path

from animstudio.core.clip import Clip
from animstudio.errors import ExportError

# extension -> (module, writer function); modules import lazily (pxr is slow to import).
_WRITERS: dict[str, tuple[str, str]] = {
    ".usda": ("animstudio.export.usd", "write_usd"),
    ".usdc": ("animstudio.export.usd", "write_usd"),
    ".usd": ("animstudio.export.usd", "write_usd"),
    ".bvh": ("animstudio.export.bvh", "write_bvh"),
    ".csv": ("animstudio.export.csv", "write_csv"),
}

FORMATS: tuple[str, ...] = tuple(ext.lstrip(".") for ext in _WRITERS)
"""Output formats by extension, without the dot."""


def writer_for(path: Path) -> Callable[[Path, Clip], None]:
    """The atomic writer for ``path``'s extension.

    Raises:
        ExportError: the extension is not one we write (the message lists the valid ones).
    """
    ext = path.suffix.lower()
    if ext not in _WRITERS:
        valid = ", ".join(_WRITERS)
        shown = ext or "(none)"
        raise ExportError(f"{path}: unknown output format '{shown}'; valid extensions are {valid}")
    module_name, func_name = _WRITERS[ext]
    func: Callable[[Path, Clip], None] = getattr(importlib.import_module(module_name), func_name)
    return func


def write_clip(path: Path, clip: Clip) -> None:
    """Write ``clip`` to ``path`` in the format its extension names, atomically."""
    writer_for(path)(path, clip)
