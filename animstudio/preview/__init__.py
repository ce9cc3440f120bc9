"""Browser preview of gait scripts and exported USD files (viser), with live reload on save.

``PreviewApp(path)`` starts the server; ``animstudio preview SCRIPT`` is the command-line shell.
"""

from animstudio.preview.app import PreviewApp, ReloadTiming
from animstudio.preview.source import load_clip

__all__ = ["PreviewApp", "ReloadTiming", "load_clip"]
