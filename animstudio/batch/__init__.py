"""Batch export: every gait script of a directory tree to USD/BVH/CSV, resumable (docs/batch.md).

Public API: :func:`run_batch` (and its :class:`BatchReport`), the manifest types, and
:func:`find_scripts`.
"""

from animstudio.batch.discovery import find_scripts
from animstudio.batch.manifest import (
    MANIFEST_NAME,
    BatchSettings,
    Entry,
    OutputRecord,
    load_manifest,
)
from animstudio.batch.runner import BatchReport, run_batch

__all__ = [
    "MANIFEST_NAME",
    "BatchReport",
    "BatchSettings",
    "Entry",
    "OutputRecord",
    "find_scripts",
    "load_manifest",
    "run_batch",
]
