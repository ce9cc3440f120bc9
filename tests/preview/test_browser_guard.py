"""Without chromium the browser tests fail with a message saying what to install (never skip)."""

from __future__ import annotations

from pathlib import Path

import preview_browser
import pytest


def test_missing_chromium_fails_with_the_fix(
    monkeypatch: pytest.MonkeyPatch, tmp_path: Path
) -> None:
    monkeypatch.setattr(preview_browser, "CHROMIUM", tmp_path / "no-chromium")
    with pytest.raises(pytest.fail.Exception, match="apt-get install -y chromium"):
        preview_browser.require_chromium()
    with pytest.raises(pytest.fail.Exception, match="is missing"):
        with preview_browser.chromium_page(tmp_path / "profile"):
            pass
