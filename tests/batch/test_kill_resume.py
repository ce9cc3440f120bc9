"""Crash safety for real: SIGKILL a running batch, check every file, re-run, check again."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
from batch_checks import check_output, make_tree, read_manifest

from animstudio.batch.discovery import is_temporary
from animstudio.batch.manifest import sha256_file
from animstudio.export.atomic import temporary_sibling

REPO = Path(__file__).resolve().parents[2]
FORMATS = "usdc,usda,bvh,csv"
# 12 real Kohonen scripts of 2-4 s; with 2 workers the batch runs long enough to be killed mid-way.
SCRIPTS = {
    f"{'shots/' if i % 2 else ''}s{i:02d}.gait": f"walk {2 + i % 3}s / run 30 / climb 20\n"
    for i in range(12)
}
KILL_AFTER = 3  # finished scripts in the manifest before the kill


def _start(inp: Path, out: Path) -> subprocess.Popen[bytes]:
    env = {
        **os.environ,
        "PYTHONPATH": os.pathsep.join([str(REPO), os.environ.get("PYTHONPATH", "")]),
    }
    cmd = [sys.executable, "-m", "animstudio", "batch", str(inp), "-o", str(out)]
    # Own session: the kill takes the whole process group (CLI and its workers), like a crash.
    return subprocess.Popen(
        [*cmd, "--format", FORMATS, "-j", "2"],
        env=env,
        start_new_session=True,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
    )


def _finished(out: Path) -> dict:
    # A half-written manifest would raise JSONDecodeError here and fail the test.
    try:
        return {k: v for k, v in read_manifest(out).items() if v["status"] == "ok"}
    except FileNotFoundError:
        return {}


def _check_all_files(out: Path) -> list[Path]:
    """Every non-temporary file under ``out`` is complete; returns the temporaries found."""
    temporaries = []
    for path in out.rglob("*"):
        if not path.is_file():
            continue
        if is_temporary(path):
            temporaries.append(path)
        elif path.suffix.lstrip(".") in FORMATS.split(","):
            found = check_output(path)
            assert found["frames"] > 0, path
    json.loads((out / "manifest.json").read_text())
    return temporaries


def _run_until_killed(inp: Path, out: Path, finished: int) -> dict:
    """Start a batch, SIGKILL its process group once ``finished`` scripts are in the manifest."""
    proc = _start(inp, out)
    deadline = time.monotonic() + 240
    while len(_finished(out)) < finished:
        assert proc.poll() is None, f"batch ended before the kill: {proc.communicate()}"
        assert time.monotonic() < deadline, "batch made no progress"
        time.sleep(0.01)
    os.killpg(proc.pid, signal.SIGKILL)
    proc.communicate()
    assert proc.returncode == -signal.SIGKILL
    done = _finished(out)
    assert finished <= len(done) < len(SCRIPTS), "the kill did not land mid-way"
    _check_all_files(out)  # no truncated output anywhere, whatever was in flight
    for entry in done.values():
        for rec in entry["outputs"].values():
            assert sha256_file(out / rec["path"]) == rec["sha256"]
    return done


@pytest.mark.slow
def test_sigkill_mid_batch_then_resume(tmp_path: Path) -> None:
    inp = make_tree(tmp_path / "in", SCRIPTS)
    out = tmp_path / "out"
    first = _run_until_killed(inp, out, KILL_AFTER)
    # Killed again while resuming: the first kill's finished work must survive a second kill.
    before = _run_until_killed(inp, out, len(first) + 3)
    for rel, entry in first.items():
        assert before[rel] == entry
    stamps = {
        rec["path"]: (out / rec["path"]).stat().st_ino
        for e in before.values()
        for rec in e["outputs"].values()
    }
    # A stray temporary as an interrupted writer leaves it (half a file), whatever the timing was.
    stray = temporary_sibling(out / "s00.usdc")
    stray.write_bytes(b"PXR-USDC\x00half")

    proc = _start(inp, out)
    stdout, stderr = proc.communicate(timeout=300)
    assert proc.returncode == 0, stderr.decode()
    summary = stdout.decode()
    rendered = len(SCRIPTS) - len(before)
    assert f"{rendered} rendered, {len(before)} up to date, 0 failed" in summary
    assert "leftover temporary file(s)" in summary

    after = read_manifest(out)
    assert sorted(after) == sorted(SCRIPTS) and all(e["status"] == "ok" for e in after.values())
    for rel, entry in before.items():
        assert after[rel] == entry  # the same record: skipped, not re-rendered
    for path, inode in stamps.items():
        assert (out / path).stat().st_ino == inode  # an atomic re-render would be a new inode
    assert _check_all_files(out) == []  # temporaries cleaned
    for entry in after.values():
        for rec in entry["outputs"].values():
            assert sha256_file(out / rec["path"]) == rec["sha256"]
            assert check_output(out / rec["path"])["frames"] == entry["frames"]


@pytest.mark.slow
def test_a_killed_worker_fails_only_its_jobs(tmp_path: Path) -> None:
    # The out-of-memory killer takes one worker process: the pool breaks; the jobs it had in
    # flight are reported failed, a fresh pool renders the rest, and a re-run completes them.
    from animstudio.batch import run_batch

    inp = make_tree(tmp_path / "in", SCRIPTS)
    out = tmp_path / "out"
    killed: list[int] = []

    def on_entry(entry, outcome):  # type: ignore[no-untyped-def]
        if not killed and entry.worker:
            pid = int(entry.worker.split(":")[1])
            os.kill(pid, signal.SIGKILL)
            killed.append(pid)

    report = run_batch(inp, out, formats=("usdc",), jobs=2, on_entry=on_entry)
    assert killed
    failed = report.failed
    assert 1 <= len(failed) <= 4  # at most the window of 2 jobs per worker was in flight
    assert all("worker process died" in (e.error or "") for e in failed)
    assert report.count("rendered") == len(SCRIPTS) - len(failed)
    again = run_batch(inp, out, formats=("usdc",), jobs=2)
    assert again.count("rendered") == len(failed) and again.count("failed") == 0
    assert again.count("skipped") == len(SCRIPTS) - len(failed)
