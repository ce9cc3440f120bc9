"""Driving Debian's chromium through Playwright for the preview's browser tests.

Never ``playwright install``: the installed ``/usr/bin/chromium`` renders WebGL through
SwiftShader with these flags (shared/DESIGN.md).
"""

from __future__ import annotations

import io
import re
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any, TypeVar

import numpy as np
import pytest
from PIL import Image

CHROMIUM = Path("/usr/bin/chromium")
CHROMIUM_ARGS = [
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
]
VIEWPORT = {"width": 1024, "height": 640}
STATUS = re.compile(r"Frame (\d+) / (\d+)")
T = TypeVar("T")


def require_chromium() -> None:
    """Fail (never skip) when the browser the tests need is not installed."""
    if not CHROMIUM.exists():
        pytest.fail(
            f"{CHROMIUM} is missing: the preview's browser tests need Debian's chromium "
            "(apt-get install -y chromium; scripts/test.sh and .ci/run install it)"
        )


@contextmanager
def chromium_page(user_data_dir: Path) -> Iterator[Any]:
    """A fresh headless chromium (its own profile dir) and one page of ``VIEWPORT`` size."""
    require_chromium()
    from playwright.sync_api import sync_playwright

    with sync_playwright() as p:
        context = p.chromium.launch_persistent_context(
            str(user_data_dir),
            executable_path=str(CHROMIUM),
            args=CHROMIUM_ARGS,
            headless=True,
            viewport=VIEWPORT,
        )
        try:
            page = context.pages[0] if context.pages else context.new_page()
            yield page
        finally:
            context.close()


def wait_for(
    fn: Callable[[], T | None],
    timeout_s: float,
    what: str | Callable[[], str],
    period_s: float = 0.1,
) -> T:
    """Poll ``fn`` until it returns something truthy; fail with ``what`` on timeout.

    ``what`` may be a function, called on failure to describe the state then.
    """
    deadline = time.monotonic() + timeout_s
    last: T | None = None
    while time.monotonic() < deadline:
        last = fn()
        if last is not None and (isinstance(last, np.ndarray) or bool(last)):
            return last
        time.sleep(period_s)
    described = what() if callable(what) else what
    pytest.fail(f"timed out after {timeout_s} s waiting for {described} (last: {last!r})")


def page_text(page: Any) -> str:
    return str(page.inner_text("body"))


def status_frame(page: Any) -> tuple[int, int] | None:
    """``(frame, last_frame)`` read from the status line of the page."""
    m = STATUS.search(page_text(page))
    return (int(m.group(1)), int(m.group(2))) if m else None


def panel_left(page: Any) -> int:
    """x of the control panel's left edge (its title bar reads *Connected*)."""
    return int(
        page.evaluate(
            """() => {
                const bars = Array.from(document.querySelectorAll('div')).filter(
                    (e) => e.innerText && e.innerText.trim().startsWith('Connected')
                        && e.getBoundingClientRect().width < 0.6 * window.innerWidth);
                return Math.min(...bars.map((e) => e.getBoundingClientRect().x));
            }"""
        )
    )


def canvas_image(page: Any) -> np.ndarray:
    """The 3D view as ``(H, W, 3) uint8``: the whole viewport, the control panel's column black.

    The 3D canvas fills the viewport under the floating panel, so the image keeps the
    viewport's geometry (its centre is where the camera looks).
    """
    png = page.screenshot()
    image = np.asarray(Image.open(io.BytesIO(png)).convert("RGB")).copy()
    image[:, max(panel_left(page) - 4, 0) :] = 0
    return image


def settled_canvas(page: Any, timeout_s: float = 30.0) -> np.ndarray:
    """The canvas once two screenshots 0.5 s apart agree (new scene nodes fade in)."""
    previous = canvas_image(page)

    def same() -> np.ndarray | None:
        nonlocal previous
        time.sleep(0.5)
        now = canvas_image(page)
        stable = np.abs(now.astype(int) - previous.astype(int)).max() <= 2
        previous = now
        return now if stable else None

    return wait_for(same, timeout_s, "the 3D view to settle", period_s=0.0)


def uplot_series(page: Any, title: str) -> list[list[float | None]]:
    """The data arrays a uPlot chart in the page is drawing (NaN as None)."""
    return page.evaluate(  # type: ignore[no-any-return]
        """(title) => {
            const charts = Object.values(window.__viserTestpoints?.uplots ?? {});
            const chart = charts.find((c) => c.chart.root.innerText.includes(title));
            if (!chart) return null;
            return chart.chart.data.map((a) => Array.from(a, (v) => (Number.isNaN(v) ? null : v)));
        }""",
        title,
    )
