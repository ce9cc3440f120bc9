"""Save a screenshot of the running preview (docs/figures/preview.png), from a real run.

Usage: ``PYTHONPATH=. python tests/preview/screenshot.py [SCRIPT] [FRAME] [OUT]``
(default: scripts_gait/demo.gait at frame 118, mid-climb, to docs/figures/preview.png).
Starts the preview in-process, opens it in headless chromium and captures the page once the
3D view has settled, with the software-rendering notice closed.
"""

from __future__ import annotations

import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).parent
ROOT = HERE.parents[1]
sys.path.insert(0, str(HERE))

from preview_browser import chromium_page, settled_canvas, status_frame, wait_for  # noqa: E402
from preview_scripts import free_port  # noqa: E402

from animstudio.preview import PreviewApp  # noqa: E402


def main() -> None:
    script = Path(sys.argv[1]) if len(sys.argv) > 1 else ROOT / "scripts_gait" / "demo.gait"
    frame = int(sys.argv[2]) if len(sys.argv) > 2 else 118
    out = Path(sys.argv[3]) if len(sys.argv) > 3 else ROOT / "docs" / "figures" / "preview.png"
    app = PreviewApp(script, port=free_port(), watch=False)
    try:
        with tempfile.TemporaryDirectory() as tmp, chromium_page(Path(tmp)) as page:
            page.set_viewport_size({"width": 1280, "height": 800})
            page.goto(app.url)
            wait_for(lambda: status_frame(page), 60.0, "the status line")
            app.seek(frame)
            wait_for(lambda: (status_frame(page) or (-1, 0))[0] == frame, 60.0, "the frame")
            for button in page.locator("button.mantine-Notification-closeButton").all():
                button.click()
            time.sleep(1.0)
            settled_canvas(page)
            out.parent.mkdir(parents=True, exist_ok=True)
            page.screenshot(path=str(out))
    finally:
        app.stop()
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
