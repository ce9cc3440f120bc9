"""The command line as an animator uses it: exit codes, messages on stderr, files written or not."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest
from click.testing import CliRunner

from animstudio.cli import main

REPO = Path(__file__).resolve().parents[2]
DEMO = REPO / "scripts_gait" / "demo.gait"


def run(*args: str) -> tuple[int, str, str]:
    result = CliRunner().invoke(main, list(args))
    return result.exit_code, result.stdout, result.stderr


def test_help_reads_well() -> None:
    code, out, _ = run("--help")
    assert code == 0
    for command in ("render", "check", "train"):
        assert command in out
    assert "walk 60 / run 2s / climb 45" in out


def test_render_demo_to_usda(tmp_path: Path) -> None:
    from pxr import Usd, UsdSkel

    out = tmp_path / "demo.usda"
    code, stdout, stderr = run("render", str(DEMO), "-o", str(out))
    assert code == 0, stderr
    assert f"wrote {out}" in stdout
    stage = Usd.Stage.Open(str(out))
    skel_roots = [p for p in stage.Traverse() if p.IsA(UsdSkel.Root)]
    assert len(skel_roots) == 1
    # demo.gait: walk 60 / run 30 / climb 45 / walk 2s at 30 fps
    assert stage.GetStartTimeCode() == 0
    assert stage.GetEndTimeCode() == 60 + 30 + 45 + 60 - 1
    assert stage.GetTimeCodesPerSecond() == 30


def test_render_default_output_is_exports_stem_usda(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(tmp_path)
    script = tmp_path / "short.gait"
    script.write_text("walk 10\n")
    code, _, stderr = run("render", str(script))
    assert code == 0, stderr
    assert (tmp_path / "exports" / "short.usda").is_file()


def test_unknown_gait_is_located_and_nothing_is_written(tmp_path: Path) -> None:
    script = tmp_path / "walk.gait"
    script.write_text("walk 60\nrun 30 / wlak 45\n")
    out = tmp_path / "walk.usda"
    code, _, stderr = run("render", str(script), "-o", str(out))
    assert code == 1
    assert f"{script}:2:10: unknown gait 'wlak' (did you mean 'walk'?)" in stderr
    assert "Traceback" not in stderr
    assert not out.exists()
    assert list(tmp_path.iterdir()) == [script]  # no temporary files either


def test_failed_render_leaves_existing_output_untouched(tmp_path: Path) -> None:
    out = tmp_path / "shot.usda"
    out.write_text("previous good export")
    script = tmp_path / "bad.gait"
    script.write_text("walk 0\n")
    code, _, stderr = run("render", str(script), "-o", str(out))
    assert code == 1
    assert f"{script}:1:6:" in stderr
    assert out.read_text() == "previous good export"


def test_unknown_output_extension_fails_before_rendering(tmp_path: Path) -> None:
    out = tmp_path / "demo.fbx"
    code, _, stderr = run("render", str(DEMO), "-o", str(out))
    assert code == 1
    assert "unknown output format '.fbx'" in stderr and ".usda" in stderr
    assert not out.exists()


def test_missing_script_is_a_clear_error(tmp_path: Path) -> None:
    code, _, stderr = run("render", str(tmp_path / "nope.gait"))
    assert code == 1
    assert "nope.gait" in stderr and "cannot read script" in stderr


def test_non_utf8_script_is_located(tmp_path: Path) -> None:
    script = tmp_path / "latin1.gait"
    script.write_bytes(b"walk 60\nrun 3\xff0\n")
    code, _, stderr = run("check", str(script))
    assert code == 1
    assert f"{script}:2:6:" in stderr and "UTF-8" in stderr


def test_check_reports_every_unknown_gait(tmp_path: Path) -> None:
    script = tmp_path / "two.gait"
    script.write_text("wlak 60 / rnu 30\n")
    code, out, stderr = run("check", str(script))
    assert code == 1
    assert f"{script}:1:1: unknown gait 'wlak'" in stderr
    assert f"{script}:1:11: unknown gait 'rnu'" in stderr
    assert out == ""


def test_check_ok_summarises(tmp_path: Path) -> None:
    code, out, stderr = run("check", str(DEMO))
    assert code == 0, stderr
    assert "ok (4 segments, 195 frames" in out


def test_check_several_files_fails_if_any_fails(tmp_path: Path) -> None:
    bad = tmp_path / "bad.gait"
    bad.write_text("walk\n")
    code, out, stderr = run("check", str(DEMO), str(bad))
    assert code == 1
    assert "demo.gait: ok" in out
    assert stderr.startswith(f"{bad}:1:1: ")  # located, like a compiler: no "error:" prefix


def test_console_entry_point_never_shows_a_traceback(tmp_path: Path) -> None:
    script = tmp_path / "s.gait"
    script.write_text("fps 24\nwalk 60 ; run 30\n")
    proc = subprocess.run(
        [sys.executable, "-m", "animstudio", "render", str(script), "-o", str(tmp_path / "s.usda")],
        capture_output=True,
        text=True,
        check=False,
    )
    assert proc.returncode == 1
    assert proc.stderr.startswith(f"{script}:2:9: ")
    assert "Traceback" not in proc.stderr
    assert proc.stdout == ""  # piped: no progress bar noise
