"""Playback state of the preview: which frame shows when, driven by the wall clock.

The frame shown is computed from a wall-clock *anchor* (``anchor_time_s``, ``anchor_frame``)
rather than by counting sleeps, so a slow redraw or a late wake-up never makes playback drift
from the script's fps: ``frame = anchor_frame + (now - anchor_time_s) * fps * speed``.
Every change of speed, seek or play/pause re-anchors at the current frame.

This module is pure bookkeeping (no threads, no viser); :mod:`animstudio.preview.app` owns the
thread that asks :meth:`PlaybackClock.frame_at` what to show.
"""

from __future__ import annotations

import math
import threading
from dataclasses import dataclass

MIN_SPEED = 0.25
MAX_SPEED = 2.0


@dataclass(frozen=True)
class PlaybackStatus:
    """A snapshot of the clock at one instant.

    Attributes:
        frame: the frame to show, ``0 <= frame < num_frames``.
        playing: whether the clock advances.
        finished: playback reached the last frame with looping off (and stopped there).
    """

    frame: int
    playing: bool
    finished: bool = False


class PlaybackClock:
    """Maps wall-clock time to a frame of a clip of ``num_frames`` frames at ``fps``.

    Thread-safe: the GUI callbacks (viser's thread pool) and the playback thread both use it.

    Args:
        num_frames: frames in the clip (>= 1).
        fps: the clip's frame rate.
        now_s: the current wall-clock time (``time.perf_counter()``), so tests can inject time.
    """

    def __init__(self, num_frames: int, fps: float, now_s: float) -> None:
        if num_frames < 1 or not fps > 0:
            raise ValueError(f"need num_frames >= 1 and fps > 0, got {num_frames}, {fps}")
        self._lock = threading.Lock()
        self._num_frames = num_frames
        self._fps = float(fps)
        self._speed = 1.0
        self.loop = True
        self._playing = False
        self._anchor_time_s = now_s
        self._anchor_frame = 0.0

    @property
    def num_frames(self) -> int:
        return self._num_frames

    @property
    def fps(self) -> float:
        return self._fps

    @property
    def speed(self) -> float:
        return self._speed

    @property
    def playing(self) -> bool:
        return self._playing

    def _position(self, now_s: float) -> float:
        # Fractional frame position, not yet wrapped or clamped.
        if not self._playing:
            return self._anchor_frame
        return self._anchor_frame + (now_s - self._anchor_time_s) * self._fps * self._speed

    def _reanchor(self, now_s: float, frame: float) -> None:
        self._anchor_time_s = now_s
        self._anchor_frame = frame

    def frame_at(self, now_s: float) -> PlaybackStatus:
        """The frame to show at ``now_s``; at the end it wraps (loop) or stops on the last frame."""
        with self._lock:
            pos = self._position(now_s)
            last = self._num_frames - 1
            if pos <= last + 1 - 1e-9 or not self._playing:
                return PlaybackStatus(min(math.floor(pos + 1e-9), last), self._playing)
            if self.loop:
                wrapped = math.fmod(pos, self._num_frames)
                # Re-anchor on wrap so the float position never grows without bound.
                self._reanchor(now_s, wrapped)
                return PlaybackStatus(math.floor(wrapped + 1e-9), True)
            self._playing = False
            self._reanchor(now_s, float(last))
            return PlaybackStatus(last, False, finished=True)

    def play(self, now_s: float) -> None:
        """Start advancing from the current frame (from frame 0 if playback had finished)."""
        with self._lock:
            if self._playing:
                return
            start = self._anchor_frame
            if start >= self._num_frames - 1 and not self.loop:
                start = 0.0
            self._playing = True
            self._reanchor(now_s, start)

    def pause(self, now_s: float) -> None:
        """Stop on the frame showing at ``now_s``."""
        with self._lock:
            if not self._playing:
                return
            pos = self._position(now_s)
            frame = (
                math.fmod(pos, self._num_frames) if self.loop else min(pos, self._num_frames - 1)
            )
            self._playing = False
            self._reanchor(now_s, float(math.floor(frame + 1e-9)))

    def seek(self, frame: int, now_s: float) -> None:
        """Jump to ``frame`` (clamped into the clip); playing continues from there."""
        with self._lock:
            self._reanchor(now_s, float(min(max(int(frame), 0), self._num_frames - 1)))

    def step(self, delta: int, now_s: float) -> int:
        """Pause and move ``delta`` frames (wrapping when looping, else clamped); returns the frame."""
        with self._lock:
            pos = self._position(now_s)
            current = math.floor(math.fmod(pos, self._num_frames) + 1e-9)
            target = current + delta
            if self.loop:
                target %= self._num_frames
            else:
                target = min(max(target, 0), self._num_frames - 1)
            self._playing = False
            self._reanchor(now_s, float(target))
            return target

    def set_speed(self, speed: float, now_s: float) -> None:
        """Playback speed factor, ``MIN_SPEED..MAX_SPEED`` (1 = the clip's fps)."""
        if not MIN_SPEED <= speed <= MAX_SPEED:
            raise ValueError(f"speed must be in [{MIN_SPEED}, {MAX_SPEED}], got {speed}")
        with self._lock:
            self._reanchor(now_s, self._position(now_s))
            self._speed = float(speed)

    def retarget(self, num_frames: int, fps: float, now_s: float) -> None:
        """Switch to a re-rendered clip, keeping the current frame (clamped to the new length)."""
        if num_frames < 1 or not fps > 0:
            raise ValueError(f"need num_frames >= 1 and fps > 0, got {num_frames}, {fps}")
        with self._lock:
            pos = self._position(now_s)
            frame = math.fmod(pos, self._num_frames) if self._playing else pos
            self._num_frames = num_frames
            self._fps = float(fps)
            self._reanchor(now_s, float(min(math.floor(frame + 1e-9), num_frames - 1)))

    def next_frame_time(self, now_s: float) -> float:
        """Wall-clock time at which the shown frame next changes (``inf`` when paused)."""
        with self._lock:
            if not self._playing:
                return math.inf
            pos = self._position(now_s)
            step = 1.0 / (self._fps * self._speed)
            return now_s + (math.floor(pos + 1e-9) + 1.0 - pos) * step
