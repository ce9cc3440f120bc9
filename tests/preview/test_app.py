"""The preview server without a browser: loading, reload, errors, USD input."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from preview_scripts import OBB_SCRIPT, SOM_SCRIPT, free_port

from animstudio import pipeline
from animstudio.export.usd import write_usd
from animstudio.preview import PreviewApp
from animstudio.preview.gui import error_markdown, status_markdown


def _app(path: Path) -> PreviewApp:
    return PreviewApp(path, port=free_port(), watch=False)


def test_reload_keeps_the_frame_and_records_timings(tmp_path: Path) -> None:
    script = tmp_path / "walk.gait"
    script.write_text(SOM_SCRIPT)
    with _app(script) as app:
        assert app.clip is not None and app.clip.num_frames == 120
        assert app.view.has_mesh
        app.seek(70)
        script.write_text(SOM_SCRIPT.replace("walk 2s / run 2s", "walk 3s / run 2s"))
        timing = app.reload()
        assert timing.ok and timing.rendered_s >= timing.detected_s
        assert app.clip.num_frames == 150
        assert app.clock.frame_at(timing.updated_s).frame == 70
        assert app.reloads == [timing]


def test_error_keeps_the_last_good_clip_and_clears_when_fixed(tmp_path: Path) -> None:
    script = tmp_path / "walk.gait"
    script.write_text(SOM_SCRIPT)
    with _app(script) as app:
        good = app.clip
        script.write_text(SOM_SCRIPT.replace("run 2s", "rnu 2s"))
        timing = app.reload()
        assert not timing.ok
        assert app.clip is good
        assert app.error is not None and f"{script}:6:" in app.error and "'rnu'" in app.error
        assert app.gui.error_box.visible and "rnu" in app.gui.error_box.content
        script.write_text(SOM_SCRIPT)
        assert app.reload().ok
        assert app.error is None and not app.gui.error_box.visible


def test_starting_on_a_broken_script_serves_the_error_until_it_is_fixed(tmp_path: Path) -> None:
    script = tmp_path / "walk.gait"
    script.write_text(SOM_SCRIPT.replace("engine som", "engine smo"))
    with _app(script) as app:
        assert app.clip is None
        assert app.error is not None and f"{script}:2:" in app.error
        script.write_text(SOM_SCRIPT)
        app.reload()
        assert app.clip is not None and app.error is None


def test_engine_signals_get_their_own_panel(tmp_path: Path) -> None:
    script = tmp_path / "hexapod.gait"
    script.write_text(OBB_SCRIPT)
    with _app(script) as app:
        assert app.clip is not None
        signals = app.gui.curve_data("signals")
        angles = app.gui.curve_data("angles")
        assert signals is not None and angles is not None
        names = {s["label"].split(" [")[0] for s in app.gui._plots["signals"].series}
        assert "L1_swing_neuron" in names


def test_previews_an_exported_usd_file(tmp_path: Path) -> None:
    script = tmp_path / "walk.gait"
    script.write_text(SOM_SCRIPT)
    clip = pipeline.render(pipeline.load_script(script))
    usd = tmp_path / "walk.usdc"
    write_usd(usd, clip)
    with _app(usd) as app:
        assert app.error is None and app.clip is not None
        assert app.clip.num_frames == clip.num_frames
        assert app.view.has_mesh
        assert np.allclose(app.clip.root_translations, clip.root_translations, atol=1e-5)


def test_a_corrupt_usd_file_is_a_located_error_not_a_crash(tmp_path: Path) -> None:
    usd = tmp_path / "broken.usda"
    usd.write_text("#usda 1.0\n(\n  this is not usd\n")
    with _app(usd) as app:
        assert app.clip is None
        assert app.error is not None and str(usd) in app.error


def test_status_and_error_texts() -> None:
    from preview_synthetic import synthetic_clip

    clip = synthetic_clip()
    text = status_markdown(clip, 100, playing=False)
    assert "Frame 100 / 194" in text and "segment 2/3" in text and "climb" in text
    assert "3.33 s" in text and "30 fps" in text
    box = error_markdown("walk.gait:6:11: unknown gait 'rnu' (did you mean 'run'?)")
    assert "walk.gait:6:11" in box and "last good clip" in box


def test_an_engine_bug_is_reported_in_the_page_and_the_clip_kept(tmp_path: Path) -> None:
    from preview_synthetic import synthetic_clip

    clip = synthetic_clip()
    calls: list[Path] = []

    def loader(path: Path):  # type: ignore[no-untyped-def]
        calls.append(path)
        if len(calls) > 1:
            raise RuntimeError("matrix not positive definite")
        return clip

    script = tmp_path / "x.gait"
    script.write_text("walk 30\n")
    with PreviewApp(script, port=free_port(), watch=False, loader=loader) as app:
        assert app.clip is clip
        assert not app.reload().ok
        assert app.clip is clip
        assert app.error is not None
        assert "internal error" in app.error and "matrix not positive definite" in app.error
        assert app.gui.error_box.visible
