"""The preview in a real browser: headless chromium (SwiftShader WebGL) driven by Playwright.

One server and one page for the module (chromium and WebGL take seconds to start); each test
puts the preview into the state it needs first.
"""

from __future__ import annotations

import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from preview_browser import (
    chromium_page,
    page_text,
    settled_canvas,
    status_frame,
    uplot_series,
    wait_for,
)
from preview_scripts import SOM_SCRIPT, free_port

from animstudio.preview import PreviewApp

pytestmark = pytest.mark.browser

SCREENSHOT = Path(__file__).parents[2] / "docs" / "figures" / "preview.png"


@pytest.fixture(scope="module")
def preview(tmp_path_factory: pytest.TempPathFactory) -> Iterator[tuple[PreviewApp, Any, Path]]:
    tmp = tmp_path_factory.mktemp("browser")
    script = tmp / "walk_run.gait"
    script.write_text(SOM_SCRIPT)
    app = PreviewApp(script, port=free_port())
    try:
        with chromium_page(tmp / "profile") as page:
            page.goto(app.url)
            wait_for(lambda: status_frame(page), 30.0, "the status line")
            yield app, page, script
    finally:
        app.stop()


def _pause_at(app: PreviewApp, page: Any, frame: int) -> None:
    app.pause()
    app.seek(frame)
    wait_for(
        lambda: (status_frame(page) or (-1, -1))[0] == frame,
        30.0,
        lambda: f"frame {frame} (server shows {app.shown_frame}, page shows {status_frame(page)})",
    )


def test_page_loads_with_controls_and_curves(preview: tuple[PreviewApp, Any, Path]) -> None:
    _, page, script = preview
    text = page_text(page)
    assert script.name in text
    assert status_frame(page) is not None
    assert status_frame(page)[1] == 119  # type: ignore[index]  # 4 s at 30 fps
    for label in ("Play", "Frame", "Speed", "Loop", "Follow camera", "Joint angles"):
        assert label in text
    assert page.locator("canvas").count() >= 1


def test_canvas_shows_the_character(preview: tuple[PreviewApp, Any, Path]) -> None:
    app, page, _ = preview
    _pause_at(app, page, 30)
    with_character = settled_canvas(page)
    node = app.view.character
    assert node is not None
    node.visible = False
    try:
        without = settled_canvas(page)
    finally:
        node.visible = True
    differs = np.abs(with_character.astype(int) - without.astype(int)).max(axis=2) > 40
    h, w = differs.shape
    assert differs.sum() > 0.005 * h * w, "hiding the character changed almost no pixels"
    # The camera follows the character, so its pixels are around the middle of the view.
    ys, xs = np.nonzero(differs)
    assert abs(xs.mean() - w / 2) < 0.2 * w
    assert abs(ys.mean() - h / 2) < 0.25 * h
    # The character is drawn in colour, not as a washed-out silhouette.
    assert with_character[differs].std() > 10


def test_play_advances_the_frame_at_the_scripts_fps(preview: tuple[PreviewApp, Any, Path]) -> None:
    app, page, _ = preview
    _pause_at(app, page, 0)
    page.get_by_role("button", name="Play").click()
    wait_for(
        lambda: (status_frame(page) or (0, 0))[0] > 0, 30.0, "the page to show frames advancing"
    )
    # The server holds 30 fps on the wall clock: the frames it shows over 2 s, unwrapped (the
    # clip loops every 120 frames), lie on a line of slope 30 / s. A fit, because a single
    # late wake-up (chromium's software rendering shares the CPU) must not decide the test.
    times, frames = [], []
    t_end = time.perf_counter() + 2.0
    while time.perf_counter() < t_end:
        times.append(time.perf_counter())
        frames.append(app.shown_frame)
        time.sleep(0.01)
    unwrapped = np.asarray(frames) + 120 * np.cumsum(np.diff(frames, prepend=frames[0]) < -60)
    slope = np.polyfit(np.asarray(times) - times[0], unwrapped, 1)[0]
    assert slope == pytest.approx(30.0, rel=0.05)
    seen = {(status_frame(page) or (0, 0))[0] for _ in range(3)}
    assert len(seen) > 1, "the page's frame number should keep changing while playing"
    page.get_by_role("button", name="Pause").click()
    wait_for(lambda: not app.clock.playing and "Play" in page_text(page), 30.0, "pause")


def test_saving_the_script_updates_view_and_curves(preview: tuple[PreviewApp, Any, Path]) -> None:
    app, page, script = preview
    script.write_text(SOM_SCRIPT)
    wait_for(lambda: app.error is None and app.clip is not None, 30.0, "a good clip")
    _pause_at(app, page, 45)
    before = settled_canvas(page)
    curves_before = wait_for(lambda: uplot_series(page, "Joint angles"), 30.0, "the curves")
    reloads = len(app.reloads)
    script.write_text(SOM_SCRIPT.replace("walk 2s / run 2s", "run 3s / walk 2s"))
    wait_for(lambda: status_frame(page) == (45, 149), 30.0, "the re-rendered clip (150 frames)")
    assert len(app.reloads) == reloads + 1 and app.reloads[-1].ok
    curves_after = wait_for(
        lambda: (d := uplot_series(page, "Joint angles")) and d != curves_before and d,
        30.0,
        "new curves",
    )
    # The segment boundary moved from 2 s to 3 s (the 4 s window around frame 45 shows 0-4 s).
    boundary = _marks(curves_after, -2)
    assert boundary and all(abs(x - 3.0) < 1e-9 for x in boundary)
    assert all(abs(x - 2.0) < 1e-9 for x in _marks(curves_before, -2))
    after = settled_canvas(page)
    changed = np.abs(after.astype(int) - before.astype(int)).max(axis=2) > 40
    assert changed.mean() > 0.002, "the pose at frame 45 should differ between walk and run"


def test_broken_script_shows_its_error_and_keeps_the_clip(
    preview: tuple[PreviewApp, Any, Path],
) -> None:
    app, page, script = preview
    script.write_text(SOM_SCRIPT.replace("walk 2s / run 2s", "run 3s / walk 2s"))
    wait_for(
        lambda: app.error is None and app.clip is not None and app.clip.num_frames == 150,
        30.0,
        "the good 150-frame clip",
    )
    _pause_at(app, page, 45)
    good = settled_canvas(page)
    script.write_text(SOM_SCRIPT.replace("walk 2s / run 2s", "run 3s / wlak 2s"))
    message = wait_for(lambda: app.error, 30.0, "the error")
    assert f"{script}:6:" in message and "wlak" in message
    wait_for(lambda: "Script error" in page_text(page), 30.0, "the error box in the page")
    text = page_text(page)
    assert f"{script.name}:6:" in text and "wlak" in text
    # The last good clip is still on show.
    assert status_frame(page) == (45, 149)
    still = settled_canvas(page)
    # Around the character: the middle of the view, below the error toast (top left).
    h, w = good.shape[:2]
    middle = (slice(2 * h // 5, 4 * h // 5), slice(3 * w // 10, 3 * w // 5))
    changed = np.abs(still[middle].astype(int) - good[middle].astype(int)).max(axis=2) > 40
    assert changed.mean() < 0.002  # the character covers several % of this region
    page.get_by_role("button", name="Play").click()
    wait_for(lambda: (status_frame(page) or (45, 0))[0] != 45, 30.0, "playback of the kept clip")
    page.get_by_role("button", name="Pause").click()
    # Fixing the script clears the error.
    script.write_text(SOM_SCRIPT)
    wait_for(lambda: "Script error" not in page_text(page), 30.0, "the error box to go")
    wait_for(lambda: (status_frame(page) or (0, 0))[1] == 119, 30.0, "the fixed clip")


def _marks(series: list[list[float | None]], index: int) -> list[float]:
    x = series[0]
    return sorted(
        {
            float(xv)
            for xv, yv in zip(x, series[index], strict=True)
            if yv is not None and xv is not None
        }
    )


def test_user_panning_takes_the_camera_over(preview: tuple[PreviewApp, Any, Path]) -> None:
    app, page, _ = preview
    app.set_follow(True)
    app.gui.set_follow(True)
    _pause_at(app, page, 10)
    assert app.gui.follow_enabled and all(app.camera_following.values())
    # A right-button drag pans the camera (moves its look-at point off the character).
    page.mouse.move(300, 300)
    page.mouse.down(button="right")
    for step in range(1, 11):
        page.mouse.move(300 + 12 * step, 300 + 6 * step)
    page.mouse.up(button="right")
    wait_for(lambda: not app.gui.follow_enabled, 30.0, "the follow box to untick after a pan")
    assert not any(app.camera_following.values())
    assert "Follow camera" in page_text(page)
    # Ticking it again hands the camera back to the character.
    page.get_by_text("Follow camera").click()
    wait_for(lambda: app.gui.follow_enabled, 30.0, "follow to resume")
    wait_for(lambda: all(app.camera_following.values()), 30.0, "the camera to follow again")
