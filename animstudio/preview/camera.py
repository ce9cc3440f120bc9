"""Camera follow for one browser client, and telling our camera moves from the user's.

Following keeps the camera's *offset* from its look-at point (so the user's orbit and zoom are
kept) and moves the look-at point onto the character. viser reports every camera change of the
client, including the ones we commanded, so a report is the user's own move when its look-at
point matches none of the points we recently sent: the user panned away and has taken over.
An orbit or zoom keeps the look-at point, so it does not stop following; the new offset is
adopted instead.
"""

from __future__ import annotations

import threading
from collections import deque
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

TAKEOVER_TOLERANCE_M = 0.02
"""A reported look-at point further than this from every recent command is the user's."""

_RECENT = 90  # commands remembered: 3 s at 30 fps covers any reporting delay


@dataclass(frozen=True)
class CameraCommand:
    """Where to put the camera: ``position`` and ``look_at`` ``(3,)`` world metres."""

    position: NDArray[np.float64]
    look_at: NDArray[np.float64]


class CameraFollower:
    """Follow state of one client's camera.

    Args:
        offset: initial ``position - look_at`` ``(3,)`` metres.
    """

    def __init__(self, offset: NDArray[np.float64]) -> None:
        self._lock = threading.Lock()
        self._offset = np.asarray(offset, dtype=np.float64).copy()
        self._sent: deque[NDArray[np.float64]] = deque(maxlen=_RECENT)
        self.following = True
        self.ready = False
        """The client has reported its camera once (viser refuses camera writes before that)."""

    @property
    def offset(self) -> NDArray[np.float64]:
        return self._offset.copy()

    def command(self, target: NDArray[np.float64]) -> CameraCommand | None:
        """The camera pose that looks at ``target`` (``None`` when not following)."""
        with self._lock:
            if not (self.following and self.ready):
                return None
            look_at = np.asarray(target, dtype=np.float64).copy()
            self._sent.append(look_at)
            return CameraCommand(position=look_at + self._offset, look_at=look_at)

    def resume(self) -> None:
        """Follow again (the user ticked *follow camera*)."""
        with self._lock:
            self.following = True
            self._sent.clear()

    def report(self, position: NDArray[np.float64], look_at: NDArray[np.float64]) -> bool:
        """A camera state reported by the client; returns True when the user has just taken over.

        The first report only marks the client :attr:`ready`.
        """
        pos = np.asarray(position, dtype=np.float64)
        look = np.asarray(look_at, dtype=np.float64)
        with self._lock:
            if not self.ready:
                # The client's first report is its default view, not a user's move.
                self.ready = True
                return False
            if not self.following or not self._sent:
                return False
            distances = [float(np.linalg.norm(look - s)) for s in self._sent]
            if min(distances) > TAKEOVER_TOLERANCE_M:
                self.following = False
                return True
            if distances[-1] <= TAKEOVER_TOLERANCE_M:
                # Reported with our latest look-at: its offset is the user's orbit/zoom.
                self._offset = pos - look
            return False
