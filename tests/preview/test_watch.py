"""The polling watcher reports content changes once, not touches."""

from __future__ import annotations

import os
from pathlib import Path

from animstudio.preview.watch import FileWatcher


def test_change_is_reported_once_and_touch_is_ignored(tmp_path: Path) -> None:
    path = tmp_path / "a.gait"
    path.write_text("walk 30\n")
    seen: list[float] = []
    watcher = FileWatcher(path, seen.append)
    assert watcher.poll() is False
    path.write_text("walk 45\n")
    assert watcher.poll() is True
    assert watcher.poll() is False
    st = path.stat()
    os.utime(path, ns=(st.st_atime_ns, st.st_mtime_ns + 10_000_000))
    assert watcher.poll() is False  # same bytes
    assert len(seen) == 1


def test_missing_file_mid_save_is_not_a_change(tmp_path: Path) -> None:
    path = tmp_path / "a.gait"
    path.write_text("walk 30\n")
    calls: list[float] = []
    watcher = FileWatcher(path, calls.append)
    path.unlink()
    assert watcher.poll() is False
    path.write_text("walk 60\n")  # an editor that deletes then writes
    assert watcher.poll() is True
    assert len(calls) == 1
