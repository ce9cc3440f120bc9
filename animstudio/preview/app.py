"""The preview server: a viser app that plays a Clip, follows it with the camera and live-reloads.

Threads: viser runs its own server threads and calls GUI/camera callbacks from a thread pool;
the :class:`FileWatcher` reloads on its thread; one playback thread shows frames on the wall
clock (:class:`~animstudio.preview.playback.PlaybackClock`). All shared state sits behind one
lock, and every scene change for a frame is sent as one atomic batch, so a client never draws
half-updated bones.
"""

from __future__ import annotations

import contextlib
import functools
import io
import logging
import threading
import time
import warnings
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import viser

from animstudio.core.clip import Clip
from animstudio.engines import EngineOptions
from animstudio.errors import AnimstudioError
from animstudio.preview.camera import CameraFollower
from animstudio.preview.gui import PreviewGui
from animstudio.preview.playback import PlaybackClock
from animstudio.preview.pose import PosedClip, pose_clip
from animstudio.preview.scene import CharacterView
from animstudio.preview.source import load_clip
from animstudio.preview.watch import FileWatcher
from animstudio.rig.proportions import HEIGHT_M

log = logging.getLogger(__name__)

# A browser tab closed while a frame was being sent is normal here; viser warns about the
# camera writes that raced with the disconnect. Only that message is silenced.
warnings.filterwarnings(
    "ignore", message=r"Queued a \w+ on a closed connection", category=UserWarning
)

CAMERA_DIRECTION = np.array([1.2, 0.6, -3.6]) / np.linalg.norm([1.2, 0.6, -3.6])
"""From the followed root towards the camera at start: ahead, above and to the character's left."""

CAMERA_DISTANCE_PER_SIZE = 2.2
"""Start distance in character sizes (largest extent of the rest pose): the whole body in view."""

CURVE_UPDATE_PERIOD_S = 0.1
"""The curves panel follows the playhead at most 10 times a second while playing."""


@dataclass(frozen=True)
class ReloadTiming:
    """Server-side timings of one reload, ``time.perf_counter()`` seconds.

    Attributes:
        detected_s: the watcher saw the new file contents.
        rendered_s: the clip was rendered (or the error was known).
        updated_s: the scene, GUI and curves updates were queued to the clients.
        ok: the script rendered (False: an error is shown and the last good clip kept).
    """

    detected_s: float
    rendered_s: float
    updated_s: float
    ok: bool

    @property
    def render_ms(self) -> float:
        return 1e3 * (self.rendered_s - self.detected_s)

    @property
    def total_ms(self) -> float:
        return 1e3 * (self.updated_s - self.detected_s)


class PreviewApp:
    """A running preview of one script or USD file.

    Args:
        path: a gait script (re-rendered on every save) or an exported ``.usd/.usda/.usdc``.
        host: interface to bind (``127.0.0.1``: this machine only).
        port: TCP port of the page and websocket.
        options: engine options (Kohonen weights) for rendering scripts.
        watch: re-render when the file changes.
        loader: how the file becomes a Clip (default :func:`~animstudio.preview.source.load_clip`
            with ``options``); it raises an :class:`AnimstudioError` for a bad file.

    The server starts in the constructor; call :meth:`stop` (or use ``with``) to end it.
    """

    def __init__(
        self,
        path: Path,
        *,
        host: str = "127.0.0.1",
        port: int = 8080,
        options: EngineOptions | None = None,
        watch: bool = True,
        loader: Callable[[Path], Clip] | None = None,
    ) -> None:
        self.path = Path(path)
        self._loader = loader or functools.partial(load_clip, options=options)
        self._lock = threading.RLock()
        self._wake = threading.Event()
        self._stop = threading.Event()
        self._posed: PosedClip | None = None
        self._shown_frame = -1
        self._curves_frame = -1
        self._curves_time = 0.0
        self._followers: dict[int, CameraFollower] = {}
        self.error: str | None = None
        self.reloads: list[ReloadTiming] = []
        self.clock = PlaybackClock(1, 30.0, time.perf_counter())

        # viser prints a banner on start and a line on stop whatever ``verbose`` says; the
        # library never prints (the CLI prints the URL), so those go to a discarded buffer.
        with contextlib.redirect_stdout(io.StringIO()):
            self.server = viser.ViserServer(host=host, port=port, verbose=False)
        try:
            self.server.scene.set_up_direction("+y")
            self.view = CharacterView(self.server)
            self.gui = PreviewGui(self.server, self)
            self.server.on_client_connect(self._on_connect)
            self.server.on_client_disconnect(self._on_disconnect)
            first = self._load()
            if isinstance(first, Clip):
                self._install(first, keep_frame=False)
        except BaseException:
            # Never leave a server thread behind a failed start (the process would not exit).
            with contextlib.redirect_stdout(io.StringIO()):
                self.server.stop()
            raise
        self._reload_lock = threading.Lock()
        self._watcher = FileWatcher(self.path, self.reload) if watch else None
        self._player = threading.Thread(target=self._play_loop, name="animstudio-play", daemon=True)
        self._player.start()
        if self._watcher is not None:
            self._watcher.start()

    # -- public -----------------------------------------------------------------------------

    @property
    def url(self) -> str:
        host = self.server.get_host()
        shown = "127.0.0.1" if host in ("0.0.0.0", "") else host
        if ":" in shown:
            shown = f"[{shown}]"
        return f"http://{shown}:{self.server.get_port()}"

    @property
    def clip(self) -> Clip | None:
        """The clip on show (the last one that rendered)."""
        with self._lock:
            return None if self._posed is None else self._posed.clip

    @property
    def camera_following(self) -> dict[int, bool]:
        """Per connected client: whether its camera follows the character."""
        with self._lock:
            return {cid: f.following for cid, f in self._followers.items()}

    @property
    def shown_frame(self) -> int:
        return self._shown_frame

    def reload(self, detected_s: float | None = None) -> ReloadTiming:
        """Re-render the file and update every client, keeping the current frame.

        A failing script leaves the last good clip on show and displays the error.
        """
        detected = time.perf_counter() if detected_s is None else detected_s
        with self._reload_lock:  # one reload at a time, so clips are installed in save order
            result = self._load()
            rendered = time.perf_counter()
            ok = isinstance(result, Clip)
            if isinstance(result, Clip):
                self._install(result, keep_frame=True)
            updated = time.perf_counter()
        timing = ReloadTiming(detected, rendered, updated, ok)
        with self._lock:
            self.reloads.append(timing)
        log.info("reload of %s: %.0f ms (ok=%s)", self.path, timing.total_ms, ok)
        return timing

    def play(self) -> None:
        self.clock.play(time.perf_counter())
        self._changed()

    def pause(self) -> None:
        self.clock.pause(time.perf_counter())
        self._changed()

    def toggle_play(self) -> None:
        if self.clock.playing:
            self.pause()
        else:
            self.play()

    def seek(self, frame: int) -> None:
        self.clock.seek(frame, time.perf_counter())
        self._changed()

    def step(self, delta: int) -> None:
        self.clock.step(delta, time.perf_counter())
        self._changed()

    def set_speed(self, speed: float) -> None:
        self.clock.set_speed(speed, time.perf_counter())
        self._changed()

    def set_loop(self, loop: bool) -> None:
        self.clock.loop = loop
        self._changed()

    def set_follow(self, follow: bool) -> None:
        with self._lock:
            for follower in self._followers.values():
                if follow:
                    follower.resume()
                else:
                    follower.following = False
        self._changed()

    def stop(self) -> None:
        """Stop watching, playing and serving (idempotent)."""
        if self._stop.is_set():
            return
        self._stop.set()
        self._wake.set()
        if self._watcher is not None:
            self._watcher.stop()
        self._player.join(timeout=2.0)
        with contextlib.redirect_stdout(io.StringIO()):
            self.server.stop()

    def __enter__(self) -> PreviewApp:
        return self

    def __exit__(self, *exc: object) -> None:
        self.stop()

    # -- loading ----------------------------------------------------------------------------

    def _load(self) -> Clip | Exception:
        try:
            clip = self._loader(self.path)
        except Exception as exc:
            if isinstance(exc, AnimstudioError):
                message = str(exc)
            else:
                # Not the script's fault: an engine or rig bug. Keep serving the last good clip
                # and say what happened; the traceback goes to the log for a bug report.
                log.exception("rendering %s failed", self.path)
                message = (
                    f"{self.path}: internal error while rendering "
                    f"({type(exc).__name__}: {exc}); please report it"
                )
            with self._lock:
                self.error = message
            self.gui.show_error(message, self.server.get_clients().values())
            return exc
        with self._lock:
            self.error = None
        self.gui.show_error(None, ())
        return clip

    def _install(self, clip: Clip, *, keep_frame: bool) -> None:
        posed = pose_clip(clip)
        now = time.perf_counter()
        with self._lock:
            if keep_frame:
                self.clock.retarget(clip.num_frames, clip.fps, now)
            else:
                self.clock = PlaybackClock(clip.num_frames, clip.fps, now)
            self._posed = posed
            frame = self.clock.frame_at(now).frame
            with self.server.atomic():
                self.view.set_clip(posed)
                self.gui.set_clip(clip)
                self._show(frame, force_curves=True)

    # -- playback ---------------------------------------------------------------------------

    def _changed(self) -> None:
        # A control moved: redraw now rather than at the next frame time.
        with self._lock:
            self._shown_frame = -1
        self._wake.set()

    def _play_loop(self) -> None:
        while not self._stop.is_set():
            try:
                wait = self._play_once()
            except Exception:  # a failed frame must not end playback for the session
                log.exception("showing a frame failed")
                wait = CURVE_UPDATE_PERIOD_S
            self._wake.wait(wait)
            self._wake.clear()

    def _play_once(self) -> float:
        # Show the frame due now; return how long to sleep before the next one.
        now = time.perf_counter()
        with self._lock:
            if self._posed is None:
                return CURVE_UPDATE_PERIOD_S
            status = self.clock.frame_at(now)
            if status.frame != self._shown_frame:
                with self.server.atomic():
                    self._show(status.frame, force_curves=not status.playing)
            elif self._curves_frame != status.frame and (
                not status.playing or now - self._curves_time >= CURVE_UPDATE_PERIOD_S
            ):
                self.gui.set_curves_frame(status.frame)
                self._curves_frame, self._curves_time = status.frame, now
            if status.finished:
                self.gui.set_playing(False)
            next_s = self.clock.next_frame_time(now)
        return min(max(next_s - time.perf_counter(), 0.0), CURVE_UPDATE_PERIOD_S)

    def _show(self, frame: int, *, force_curves: bool) -> None:
        # Caller holds the lock and an atomic() block.
        posed = self._posed
        assert posed is not None
        self.view.show_frame(posed, frame)
        self.gui.set_frame(posed.clip, frame, playing=self.clock.playing)
        now = time.perf_counter()
        if force_curves or now - self._curves_time >= CURVE_UPDATE_PERIOD_S:
            self.gui.set_curves_frame(frame)
            self._curves_frame, self._curves_time = frame, now
        target = posed.focus_point(frame)
        for client_id, follower in self._followers.items():
            command = follower.command(target)
            client = self.server.get_clients().get(client_id)
            if command is None or client is None:
                continue
            client.camera.position = command.position
            client.camera.look_at = command.look_at
        self._shown_frame = frame

    # -- clients ----------------------------------------------------------------------------

    def _on_connect(self, client: viser.ClientHandle) -> None:
        follower = CameraFollower(self._initial_camera_offset())
        follower.following = self.gui.follow_enabled
        with self._lock:
            self._followers[client.client_id] = follower
            self._shown_frame = -1  # place the new client's camera now
            if self.error is not None:
                self.gui.notify_error(self.error, (client,))

        @client.camera.on_update
        def _(camera: viser.CameraHandle) -> None:
            was_ready = follower.ready
            if follower.report(camera.position, camera.look_at):
                self.gui.set_follow(False)
            if not was_ready:
                self._changed()  # the camera can be placed now

        self._wake.set()

    def _initial_camera_offset(self) -> np.ndarray:
        # Frame the character by its size: a hexapod is a third of a humanoid's height.
        with self._lock:
            posed = self._posed
        size = HEIGHT_M  # before the first clip: the shipped humanoid
        if posed is not None:
            mesh = posed.clip.mesh
            points = mesh.vertices if mesh is not None else posed.bind_positions
            size = float(np.max(np.ptp(points, axis=0)))
        return CAMERA_DIRECTION * CAMERA_DISTANCE_PER_SIZE * max(size, 0.1)

    def _on_disconnect(self, client: viser.ClientHandle) -> None:
        with self._lock:
            self._followers.pop(client.client_id, None)
