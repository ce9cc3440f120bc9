"""Polling file watcher: calls back when a file's contents change.

Polling (mtime + size, then a content hash) rather than inotify: it works the same on every
platform and file system, including network mounts and editors that save by writing a new file
and renaming it over the old one. A stat every 25 ms costs microseconds.
"""

from __future__ import annotations

import logging
import threading
import time
from collections.abc import Callable
from pathlib import Path

from animstudio.preview.source import Fingerprint, fingerprint

log = logging.getLogger(__name__)

POLL_INTERVAL_S = 0.025
SETTLE_S = 0.015
"""A change is reported once the file has kept the same contents this long: an editor that
truncates and then writes would otherwise be caught between the two (an empty script)."""


class FileWatcher:
    """Watch ``path`` on a daemon thread; ``on_change(detected_at_s)`` runs on that thread.

    ``detected_at_s`` is the ``time.perf_counter()`` at which the change was seen, so callers can
    time their reaction from it.

    Args:
        path: the file to watch.
        on_change: called once per distinct new content (not for a missing file).
        interval_s: polling period.
    """

    def __init__(
        self,
        path: Path,
        on_change: Callable[[float], object],
        *,
        interval_s: float = POLL_INTERVAL_S,
    ) -> None:
        self._path = path
        self._on_change = on_change
        self._interval_s = interval_s
        self._stop = threading.Event()
        self._last: Fingerprint | None = fingerprint(path)
        self._thread = threading.Thread(target=self._run, name="animstudio-watch", daemon=True)

    def start(self) -> None:
        self._thread.start()

    def stop(self) -> None:
        self._stop.set()
        if self._thread.is_alive():
            self._thread.join(timeout=2.0)

    def poll(self) -> bool:
        """Check once; call ``on_change`` and return True if the contents changed."""
        last = self._last
        try:
            st = self._path.stat()
        except OSError:
            return False
        if last is not None and (st.st_mtime_ns, st.st_size) == (last.mtime_ns, last.size):
            return False
        detected = time.perf_counter()
        now = fingerprint(self._path)
        while True:
            time.sleep(SETTLE_S)
            again = fingerprint(self._path)
            if again == now:
                break
            now = again
        if now is None:
            return False
        self._last = now
        if last is not None and now.sha256 == last.sha256:
            return False  # touched, or rewritten with the same bytes
        self._on_change(detected)
        return True

    def _run(self) -> None:
        while not self._stop.wait(self._interval_s):
            try:
                self.poll()
            except Exception:  # the watcher must outlive a failing reload
                log.exception("reloading %s failed", self._path)
