"""Script discovery, temporary-file recognition and the manifest's skip rule (no rendering)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from batch_checks import make_tree

from animstudio.batch.discovery import (
    find_scripts,
    is_temporary,
    output_relpath,
    remove_temporaries,
)
from animstudio.batch.manifest import (
    BatchSettings,
    Entry,
    OutputRecord,
    is_up_to_date,
    load_manifest,
    save_manifest,
    sha256_file,
)
from animstudio.errors import DataError
from animstudio.export.atomic import temporary_sibling


def test_find_scripts_recursive_sorted_relative(tmp_path: Path) -> None:
    make_tree(
        tmp_path,
        {"b.gait": "", "a/z.gait": "", "a/b/c.gait": "", "notes.txt": "", ".git/x.gait": ""},
    )
    (tmp_path / "dir.gait").mkdir()
    assert find_scripts(tmp_path) == ("a/b/c.gait", "a/z.gait", "b.gait")
    assert output_relpath("a/b/c.gait", "usdc") == "a/b/c.usdc"
    assert output_relpath("x.y.gait", "bvh") == "x.y.bvh"


def test_find_scripts_errors(tmp_path: Path) -> None:
    with pytest.raises(DataError, match="does not exist"):
        find_scripts(tmp_path / "nope")
    (tmp_path / "f").write_text("")
    with pytest.raises(DataError, match="is not a directory"):
        find_scripts(tmp_path / "f")
    with pytest.raises(DataError, match=r"no \*\.gait scripts found"):
        find_scripts(tmp_path)


def test_temporaries_are_exactly_atomic_writer_names(tmp_path: Path) -> None:
    for name in ("a.usdc", "a.bvh", "manifest.json", "x.tar.gz"):
        tmp = temporary_sibling(tmp_path / "sub" / name)
        assert is_temporary(tmp), tmp.name
        assert not is_temporary(tmp_path / name)
    assert not is_temporary(Path(".hidden.usdc"))
    assert not is_temporary(Path(".a.tmp-12-zzzzzz.usdc"))
    sub = tmp_path / "sub"
    sub.mkdir()
    keep = sub / "a.usdc"
    keep.write_text("x")
    stray = temporary_sibling(keep)
    stray.write_text("half")
    assert remove_temporaries(tmp_path) == [stray]
    assert sorted(p.name for p in sub.iterdir()) == ["a.usdc"]


def _entry(out: Path, settings: BatchSettings) -> Entry:
    f = out / "s" / "a.usdc"
    f.parent.mkdir(parents=True, exist_ok=True)
    f.write_bytes(b"usd bytes")
    rec = OutputRecord("s/a.usdc", f.stat().st_size, sha256_file(f))
    return Entry(
        "s/a.gait", "abc", "0.1.0", settings, "ok", engine="som", frames=3, outputs={"usdc": rec}
    )


def test_manifest_round_trip_and_skip_rule(tmp_path: Path) -> None:
    settings = BatchSettings(("usdc",), 24, None)
    entry = _entry(tmp_path, settings)
    save_manifest(tmp_path, {"s/a.gait": entry})
    loaded = load_manifest(tmp_path)
    assert loaded == {"s/a.gait": entry}
    ok = {"input_sha256": "abc", "settings": settings, "version": "0.1.0", "out_dir": tmp_path}
    assert is_up_to_date(entry, **ok)
    assert not is_up_to_date(None, **ok)
    assert not is_up_to_date(entry, **{**ok, "input_sha256": "abd"})
    assert not is_up_to_date(entry, **{**ok, "version": "0.2.0"})
    assert not is_up_to_date(entry, **{**ok, "settings": BatchSettings(("usdc",), 25, None)})
    assert not is_up_to_date(entry, **{**ok, "settings": BatchSettings(("usdc", "bvh"), 24, None)})
    assert not is_up_to_date(entry, **{**ok, "settings": BatchSettings(("usdc",), 24, "w1")})
    # Same size, different content: the hash catches it.
    (tmp_path / "s" / "a.usdc").write_bytes(b"USD bytes")
    assert not is_up_to_date(entry, **ok)
    (tmp_path / "s" / "a.usdc").unlink()
    assert not is_up_to_date(entry, **ok)


def test_corrupt_manifest_is_a_data_error(tmp_path: Path) -> None:
    (tmp_path / "manifest.json").write_text("{not json")
    with pytest.raises(DataError, match=r"not an animstudio batch manifest.*--force"):
        load_manifest(tmp_path)
    (tmp_path / "manifest.json").write_text(json.dumps({"manifest_version": 99, "entries": {}}))
    with pytest.raises(DataError, match="manifest_version 99"):
        load_manifest(tmp_path)


def test_bad_arguments_are_refused_before_any_work(tmp_path: Path) -> None:
    from animstudio.batch import run_batch
    from animstudio.errors import UnknownName

    make_tree(tmp_path / "in", {"a.gait": "walk 10\n"})
    with pytest.raises(DataError, match="weights file not found"):
        run_batch(tmp_path / "in", tmp_path / "out", weights=tmp_path / "none.npz")
    with pytest.raises(UnknownName, match="unknown format 'usdz'"):
        run_batch(tmp_path / "in", tmp_path / "out", formats=("usdc", "usdz"))
    assert not (tmp_path / "out").exists()


def test_second_batch_on_the_same_output_directory_is_refused(tmp_path: Path) -> None:
    import fcntl
    import os

    from animstudio.batch import run_batch
    from animstudio.batch.runner import LOCK_NAME
    from animstudio.errors import ExportError

    make_tree(tmp_path / "in", {"a.gait": "walk 10\n"})
    out = tmp_path / "out"
    out.mkdir()
    fd = os.open(out / LOCK_NAME, os.O_RDWR | os.O_CREAT)
    fcntl.flock(fd, fcntl.LOCK_EX)  # as a running batch holds it
    try:
        with pytest.raises(ExportError, match="another animstudio batch is writing"):
            run_batch(tmp_path / "in", out)
    finally:
        os.close(fd)
    assert not (out / "manifest.json").exists()
