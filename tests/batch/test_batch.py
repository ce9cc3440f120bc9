"""``run_batch`` / ``animstudio batch`` on real scripts through the real pipeline."""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from batch_checks import BAD, FRAMES_30, SCRIPTS, check_output, make_tree, read_manifest

from animstudio.batch import BatchReport, run_batch
from animstudio.batch.manifest import sha256_file
from animstudio.core.resample import resampled_frame_count

REPO = Path(__file__).resolve().parents[2]
FORMATS = ("usdc", "usda", "bvh", "csv")


def cli(*args: str) -> subprocess.CompletedProcess[str]:
    env = {
        **os.environ,
        "PYTHONPATH": os.pathsep.join([str(REPO), os.environ.get("PYTHONPATH", "")]),
    }
    return subprocess.run(
        [sys.executable, "-m", "animstudio", "batch", *args],
        capture_output=True,
        text=True,
        env=env,
        timeout=300,
    )


@pytest.fixture(scope="module")
def first(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Path, BatchReport]:
    root = tmp_path_factory.mktemp("batch")
    inp = make_tree(root / "in", {**SCRIPTS, **BAD})
    out = root / "out"
    report = run_batch(inp, out, formats=FORMATS, fps=24, jobs=2)
    return inp, out, report


def test_every_output_is_complete_and_matches_the_manifest(
    first: tuple[Path, Path, BatchReport],
) -> None:
    inp, out, report = first
    manifest = read_manifest(out)
    assert sorted(manifest) == sorted({**SCRIPTS, **BAD})
    for rel, frames_30 in FRAMES_30.items():
        entry = manifest[rel]
        assert entry["status"] == "ok" and entry["error"] is None
        frames = resampled_frame_count(frames_30, 30, 24)
        assert (entry["engine"], entry["frames"], entry["fps"], entry["source_fps"]) == (
            "som",
            frames,
            24.0,
            30.0,
        )
        assert entry["duration_s"] == pytest.approx(frames / 24)
        assert entry["input_sha256"] == sha256_file(inp / rel)
        assert entry["settings"] == {"formats": list(FORMATS), "fps": 24, "weights_sha256": None}
        assert sorted(entry["outputs"]) == sorted(FORMATS)
        joints = set()
        for fmt, rec in entry["outputs"].items():
            path = out / rec["path"]
            assert rec["path"] == rel.removesuffix(".gait") + "." + fmt  # relative path kept
            assert rec["bytes"] == path.stat().st_size and rec["sha256"] == sha256_file(path)
            found = check_output(path)
            assert found["frames"] == frames and found["fps"] == 24.0, (path, found)
            joints.add(found["joints"])
        assert len(joints) == 1  # every format carries the whole skeleton
        assert entry["worker"].split(":")[1] != str(os.getpid())  # rendered in a worker process
    assert report.count("rendered") == len(SCRIPTS) and report.count("failed") == 1


def test_bad_script_is_located_and_does_not_stop_the_batch(
    first: tuple[Path, Path, BatchReport],
) -> None:
    inp, out, report = first
    (bad,) = report.failed
    assert bad.input == "shots/bad.gait"
    assert bad.error is not None and bad.error.startswith(f"{inp / 'shots' / 'bad.gait'}:2:1:")
    assert "wlak" in bad.error and "walk" in bad.error  # names the gait and suggests the fix
    assert read_manifest(out)["shots/bad.gait"]["error"] == bad.error
    assert not list((out / "shots").glob("bad.*"))  # nothing written for it


@pytest.mark.slow  # five batches, each paying worker start-up (imports, JIT) of ~5-8 s
def test_rerun_skips_up_to_date_and_redoes_exactly_what_changed(
    first: tuple[Path, Path, BatchReport], tmp_path: Path
) -> None:
    inp0, out0, _ = first
    inp, out = tmp_path / "in", tmp_path / "out"
    shutil.copytree(inp0, inp)
    shutil.copytree(out0, out)
    stamp = {p: p.stat().st_mtime_ns for p in out.rglob("*") if p.suffix.lstrip(".") in FORMATS}

    again = run_batch(inp, out, formats=FORMATS, fps=24, jobs=2)
    outcome = dict(zip([e.input for e in again.entries], again.outcomes, strict=True))
    assert outcome == {**dict.fromkeys(SCRIPTS, "skipped"), "shots/bad.gait": "failed"}
    assert {p: p.stat().st_mtime_ns for p in stamp} == stamp  # nothing rewritten

    (inp / "shots" / "a.gait").write_text(SCRIPTS["shots/a.gait"] + "walk 10\n")  # edited
    (out / "walk.bvh").write_text("HIERARCHY\n")  # damaged output
    (out / "shots" / "c.csv").unlink()  # lost output
    (inp / "shots" / "bad.gait").unlink()  # removed script: dropped from the manifest
    third = run_batch(inp, out, formats=FORMATS, fps=24, jobs=2)
    outcome = dict(zip([e.input for e in third.entries], third.outcomes, strict=True))
    assert outcome == {
        "shots/a.gait": "rendered",
        "shots/c.gait": "rendered",
        "shots/deep/b.gait": "skipped",
        "walk.gait": "rendered",
    }
    manifest = read_manifest(out)
    assert "shots/bad.gait" not in manifest
    assert manifest["shots/a.gait"]["frames"] == resampled_frame_count(70, 30, 24)
    assert check_output(out / "walk.bvh")["frames"] == manifest["walk.gait"]["frames"]
    assert (out / "shots" / "c.csv").is_file()

    other_fps = run_batch(inp, out, formats=FORMATS, fps=25, jobs=2)  # settings changed
    assert set(other_fps.outcomes) == {"rendered"}
    forced = run_batch(inp, out, formats=FORMATS, fps=25, jobs=2, force=True)
    assert set(forced.outcomes) == {"rendered"}
    assert set(run_batch(inp, out, formats=FORMATS, fps=25, jobs=1).outcomes) == {"skipped"}


@pytest.mark.slow  # two CLI batches in subprocesses
def test_cli_summary_and_exit_status(first: tuple[Path, Path, BatchReport], tmp_path: Path) -> None:
    inp0, _, _ = first
    inp = tmp_path / "in"
    shutil.copytree(inp0, inp)
    out = tmp_path / "out"
    proc = cli(str(inp), "-o", str(out), "--format", "usdc,bvh", "-j", "2")
    assert proc.returncode == 1, proc.stderr
    header = proc.stdout.splitlines()[0].split()
    assert header == ["script", "status", "engine", "frames", "fps", "seconds", "outputs"]
    assert re.search(r"^shots/bad\.gait +FAILED +- +- +- +[0-9.]+ +-$", proc.stdout, re.M)
    assert re.search(r"^shots/deep/b\.gait +ok +som +45 +30 +[0-9.]+ +usdc,bvh$", proc.stdout, re.M)
    assert "4 rendered, 0 up to date, 1 failed" in proc.stdout
    assert f"{inp / 'shots' / 'bad.gait'}:2:1: unknown gait 'wlak'" in proc.stderr
    assert "it/s" not in proc.stderr and "script/s" not in proc.stderr  # no progress bar when piped
    assert sorted(p.name for p in (out / "shots").iterdir() if p.is_file()) == [
        "a.bvh",
        "a.usdc",
        "c.bvh",
        "c.usdc",
    ]

    (inp / "shots" / "bad.gait").unlink()
    code, stdout, bar = cli_on_terminal(str(inp), "-o", str(out), "--format", "usdc,bvh")
    assert code == 0, bar
    assert "0 rendered, 4 up to date, 0 failed" in stdout
    assert "0/4 [" in bar and "script/s" in bar  # the progress bar, on a terminal only


def cli_on_terminal(*args: str) -> tuple[int, str, str]:
    """Run ``animstudio batch`` with stderr on a pseudo-terminal of 100 columns."""
    import fcntl
    import pty
    import struct
    import termios

    env = {
        **os.environ,
        "PYTHONPATH": os.pathsep.join([str(REPO), os.environ.get("PYTHONPATH", "")]),
    }
    leader, follower = pty.openpty()
    fcntl.ioctl(follower, termios.TIOCSWINSZ, struct.pack("HHHH", 40, 100, 0, 0))
    proc = subprocess.Popen(
        [sys.executable, "-m", "animstudio", "batch", *args],
        stdout=subprocess.PIPE,
        stderr=follower,
        env=env,
    )
    os.close(follower)
    chunks = []
    while True:
        try:
            data = os.read(leader, 4096)
        except OSError:  # EIO: the child closed the terminal
            break
        if not data:
            break
        chunks.append(data)
    os.close(leader)
    stdout = proc.stdout.read().decode() if proc.stdout else ""
    proc.wait(timeout=300)
    return proc.returncode, stdout, b"".join(chunks).decode(errors="replace")


def test_cli_rejects_bad_arguments_before_any_work(tmp_path: Path) -> None:
    make_tree(tmp_path / "in", SCRIPTS)
    proc = cli(str(tmp_path / "in"), "-o", str(tmp_path / "out"), "--format", "usdc,fbx")
    assert proc.returncode == 1
    assert "unknown format 'fbx'" in proc.stderr and "Traceback" not in proc.stderr
    assert not (tmp_path / "out").exists()
    proc = cli(str(tmp_path / "nope"), "-o", str(tmp_path / "out"))
    assert proc.returncode == 1 and "input directory does not exist" in proc.stderr
    proc = cli(str(tmp_path / "in"), "-o", str(tmp_path / "out"), "--fps", "23")
    assert proc.returncode == 2 and "'23' is not one of" in proc.stderr
