"""The preview's control panel: playback controls, status line, error box and curves panels.

Every control calls back into the app (:class:`~animstudio.preview.app.PreviewApp`); the app
calls :meth:`PreviewGui.set_frame` and friends to show its state. viser also runs a control's
callback when the *server* sets its value (with ``event.client`` = ``None``); those echoes are
ignored so that showing frame 12 on the slider never seeks back to frame 12 later.
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import TYPE_CHECKING, Any, cast

import viser

from animstudio.core.clip import Clip
from animstudio.preview.curves import (
    ALL_LIMBS,
    CurveGroup,
    curve_names,
    limbs,
    plot_data,
    plot_options,
)
from animstudio.preview.playback import MAX_SPEED, MIN_SPEED

if TYPE_CHECKING:
    from animstudio.preview.app import PreviewApp

CURVE_WINDOWS: dict[str, float | None] = {"4 s": 4.0, "10 s": 10.0, "whole clip": None}
PANEL_TITLES: dict[CurveGroup, str] = {"angles": "Joint angles", "signals": "Engine signals"}
PANEL_UNITS: dict[CurveGroup, str] = {"angles": "degrees", "signals": "scaled to range"}


def status_markdown(clip: Clip, frame: int, *, playing: bool) -> str:
    """The status line: ``Frame 12 / 300 · 0.40 s · segment 2/3 · gait run`` (frames from 0)."""
    seg = clip.segment_at(frame)
    where = ""
    if seg is not None:
        index = clip.segments.index(seg) + 1
        where = f" · segment {index}/{len(clip.segments)} · gait **{seg.gait}**"
    state = "playing" if playing else "paused"
    return (
        f"**Frame {frame} / {clip.num_frames - 1}** · {frame / clip.fps:.2f} s"
        f" of {clip.duration_s:.2f} s{where} · {state} at {clip.fps:g} fps"
    )


def error_markdown(message: str) -> str:
    """The error box: the located message verbatim, in a code block so columns line up."""
    fence = "~~~~" if "```" in message else "```"
    return f"**Script error** — showing the last good clip\n\n{fence}\n{message}\n{fence}"


class PreviewGui:
    """GUI handles of one preview server."""

    def __init__(self, server: viser.ViserServer, app: PreviewApp) -> None:
        self._server = server
        self._app = app
        gui = server.gui
        gui.configure_theme(control_width="large")
        self.error_box = gui.add_markdown("", visible=False)
        self.title = gui.add_markdown(f"**{app.path.name}**")
        self.notes = gui.add_markdown("", visible=False)
        self.status = gui.add_markdown("loading…")
        with gui.add_folder("Playback"):
            self.play_button = gui.add_button("Play", icon=viser.Icon.PLAYER_PLAY)
            self.step_buttons = gui.add_button_group("Step", ("◀ 1 frame", "1 frame ▶"))
            self.frame_slider = gui.add_slider("Frame", min=0, max=1, step=1, initial_value=0)
            self.speed_slider = gui.add_slider(
                "Speed", min=MIN_SPEED, max=MAX_SPEED, step=0.25, initial_value=1.0
            )
            self.loop_box = gui.add_checkbox("Loop", initial_value=True)
            self.follow_box = gui.add_checkbox("Follow camera", initial_value=True)
        self._curves_folder = gui.add_folder("Curves")
        with self._curves_folder:
            self.window_dropdown = gui.add_dropdown(
                "Window", tuple(CURVE_WINDOWS), initial_value="4 s"
            )
            self.limb_dropdown = gui.add_dropdown("Limb", (ALL_LIMBS,), initial_value=ALL_LIMBS)
            self._plots: dict[CurveGroup, viser.GuiUplotHandle] = {}
            self._plot_names: dict[CurveGroup, tuple[str, ...]] = {}
        self._clip: Clip | None = None
        self._connect()

    @property
    def follow_enabled(self) -> bool:
        return bool(self.follow_box.value)

    def _connect(self) -> None:
        app = self._app

        @self.play_button.on_click
        def _(event: viser.GuiEvent[Any]) -> None:
            app.toggle_play()
            self.set_playing(app.clock.playing)

        @self.step_buttons.on_click
        def _(event: viser.GuiEvent[Any]) -> None:
            app.step(-1 if self.step_buttons.value.startswith("◀") else 1)
            self.set_playing(False)

        @self.frame_slider.on_update
        def _(event: viser.GuiEvent[Any]) -> None:
            if event.client is not None:
                app.seek(int(self.frame_slider.value))

        @self.speed_slider.on_update
        def _(event: viser.GuiEvent[Any]) -> None:
            if event.client is not None:
                app.set_speed(float(self.speed_slider.value))

        @self.loop_box.on_update
        def _(event: viser.GuiEvent[Any]) -> None:
            if event.client is not None:
                app.set_loop(bool(self.loop_box.value))

        @self.follow_box.on_update
        def _(event: viser.GuiEvent[Any]) -> None:
            if event.client is not None:
                app.set_follow(bool(self.follow_box.value))

        @self.window_dropdown.on_update
        def _(event: viser.GuiEvent[Any]) -> None:
            if event.client is not None and self._clip is not None:
                self.set_curves_frame(max(app.shown_frame, 0))

        @self.limb_dropdown.on_update
        def _(event: viser.GuiEvent[Any]) -> None:
            if event.client is not None and self._clip is not None:
                with self._server.atomic():
                    self._set_panels(self._clip)
                    self.set_curves_frame(max(app.shown_frame, 0))

    # -- called by the app --------------------------------------------------------------------

    def set_playing(self, playing: bool) -> None:
        label = "Pause" if playing else "Play"
        if self.play_button.label != label:  # called every frame: send only real changes
            self.play_button.label = label
            self.play_button.icon = viser.Icon.PLAYER_PAUSE if playing else viser.Icon.PLAYER_PLAY

    def set_follow(self, follow: bool) -> None:
        self.follow_box.value = follow  # type: ignore[misc]  # viser's setter

    def set_clip(self, clip: Clip) -> None:
        """A new clip: slider range, notes, curve panels (frame shown later by :meth:`set_frame`)."""
        self._clip = clip
        self.frame_slider.max = max(clip.num_frames - 1, 1)
        self.frame_slider.disabled = clip.num_frames < 2
        self.notes.content = "\n\n".join(f"⚠ {n}" for n in clip.notes)
        self.notes.visible = bool(clip.notes)
        choices = limbs(clip)
        if tuple(self.limb_dropdown.options) != choices:
            keep = self.limb_dropdown.value if self.limb_dropdown.value in choices else ALL_LIMBS
            self.limb_dropdown.options = choices
            self.limb_dropdown.value = keep  # type: ignore[misc]  # viser's setter
        self._set_panels(clip)

    def _set_panels(self, clip: Clip) -> None:
        # One panel per curve group the clip has (after the limb filter); others are hidden.
        limb = str(self.limb_dropdown.value)
        groups: tuple[CurveGroup, ...] = ("angles", "signals")
        for group in groups:
            names = curve_names(clip, group, limb=limb)
            handle = self._plots.get(group)
            if not names:
                if handle is not None:
                    handle.visible = False
                continue
            self._plot_names[group] = names
            if handle is None:
                data = plot_data(
                    clip,
                    names,
                    playhead_frame=0,
                    window_s=self.window_s,
                    normalize=group == "signals",
                )
                # Created lazily (a clip may have no signals), inside the Curves folder.
                with self._curves_folder:
                    self._plots[group] = self._server.gui.add_uplot(
                        data=data.data,
                        series=cast("tuple[Any, ...]", data.series),
                        title=PANEL_TITLES[group],
                        aspect=1.6,
                        **plot_options(PANEL_UNITS[group]),
                    )
            else:
                handle.visible = True

    def set_frame(self, clip: Clip, frame: int, *, playing: bool) -> None:
        self.status.content = status_markdown(clip, frame, playing=playing)
        self.frame_slider.value = frame  # type: ignore[misc]  # viser's setter
        self.set_playing(playing)

    def set_curves_frame(self, frame: int) -> None:
        """Move the curves panels' playhead (and window) to ``frame``."""
        clip = self._clip
        if clip is None:
            return
        frame = min(frame, clip.num_frames - 1)
        for group, handle in self._plots.items():
            names = self._plot_names.get(group, ())
            if not handle.visible or not names:
                continue
            data = plot_data(
                clip,
                names,
                playhead_frame=frame,
                window_s=self.window_s,
                normalize=group == "signals",
            )
            if tuple(s.get("label") for s in handle.series) != tuple(
                s.get("label") for s in data.series
            ):
                handle.series = cast("tuple[Any, ...]", data.series)
            handle.data = data.data

    @property
    def window_s(self) -> float | None:
        return CURVE_WINDOWS[str(self.window_dropdown.value)]

    def curve_data(self, group: CurveGroup) -> tuple[Any, ...] | None:
        """What the panel ``group`` currently shows (tests and the benchmark read it)."""
        handle = self._plots.get(group)
        return None if handle is None else tuple(handle.data)

    def show_error(self, message: str | None, clients: Iterable[viser.ClientHandle]) -> None:
        """Show ``message`` in the error box (``None`` hides it) and notify ``clients``."""
        if message is None:
            self.error_box.visible = False
            self.error_box.content = ""
            return
        self.error_box.content = error_markdown(message)
        self.error_box.visible = True
        self.notify_error(message, clients)

    def notify_error(self, message: str, clients: Iterable[viser.ClientHandle]) -> None:
        first = message.splitlines()[0] if message else "error"
        for client in clients:
            client.add_notification(
                "Script error", first, color="red", with_close_button=True, auto_close_seconds=8.0
            )
