"""``animstudio preview`` as a user runs it: URL printed, page served, Ctrl-C exits cleanly."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
import urllib.request
from pathlib import Path

from preview_scripts import SOM_SCRIPT, free_port

ROOT = Path(__file__).parents[2]


def _start(*args: str) -> subprocess.Popen[str]:
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    return subprocess.Popen(
        [sys.executable, "-m", "animstudio", "preview", *args],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env=env,
    )


def _read_url(proc: subprocess.Popen[str]) -> str:
    assert proc.stdout is not None
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline:
        line = proc.stdout.readline()
        if "http://" in line:
            return line.split("at ", 1)[1].split()[0]
        if not line and proc.poll() is not None:
            break
    raise AssertionError(f"no URL printed; stderr: {proc.stderr.read() if proc.stderr else ''}")


def test_serves_the_page_and_stops_cleanly_on_ctrl_c(tmp_path: Path) -> None:
    script = tmp_path / "walk.gait"
    script.write_text(SOM_SCRIPT)
    port = free_port()
    proc = _start(str(script), "--port", str(port))
    try:
        url = _read_url(proc)
        assert url == f"http://127.0.0.1:{port}"
        with urllib.request.urlopen(url, timeout=10) as response:
            assert response.status == 200
            assert b"<html" in response.read().lower()
        proc.send_signal(signal.SIGINT)
        out, err = proc.communicate(timeout=30)
    finally:
        if proc.poll() is None:
            proc.kill()
    assert proc.returncode == 0, err
    assert "Traceback" not in err
    assert "preview stopped" in out
    assert "warning" not in err


def test_non_loopback_host_warns(tmp_path: Path) -> None:
    script = tmp_path / "walk.gait"
    script.write_text(SOM_SCRIPT)
    proc = _start(str(script), "--host", "0.0.0.0", "--port", str(free_port()))
    try:
        _read_url(proc)
        proc.send_signal(signal.SIGINT)
        _, err = proc.communicate(timeout=30)
    finally:
        if proc.poll() is None:
            proc.kill()
    assert proc.returncode == 0
    assert "warning: listening on 0.0.0.0" in err


def test_missing_file_is_an_error_without_a_server(tmp_path: Path) -> None:
    proc = _start(str(tmp_path / "nope.gait"), "--port", str(free_port()))
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 1
    assert "nope.gait: no such file" in err and "Traceback" not in err
