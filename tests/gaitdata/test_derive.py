"""The committed training cycles are what the derivation makes of the real reference trials."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from animstudio.gaitdata import load_training_set
from animstudio.gaitdata.cycles import format_cycle
from animstudio.gaitdata.derive import SOURCES, derive_all, main, read_reference
from animstudio.gaitdata.events import detect_events

ROOT = Path(__file__).resolve().parents[2]
TRAINING_DATA = ROOT / "training_data"
# The workplace lays shared/ beside the checkout (for CI too: a copy beside the clean clone).
REFERENCE = ROOT.parent / "shared" / "reference_gait"

needs_reference = pytest.mark.skipif(
    not REFERENCE.is_dir(),
    reason=f"the shared reference trials ({REFERENCE}) are not on this machine",
)


@needs_reference
def test_regenerated_cycles_equal_the_committed_files(tmp_path: Path) -> None:
    assert main([str(REFERENCE), str(tmp_path)]) == 0
    for source in SOURCES:
        name = f"{source.gait}.csv"
        assert (tmp_path / name).read_text() == (TRAINING_DATA / name).read_text(), name
    assert sorted(p.name for p in TRAINING_DATA.glob("*.csv")) == sorted(
        f"{s.gait}.csv" for s in SOURCES
    )


@needs_reference
def test_events_agree_with_sources_md() -> None:
    found = {}
    for s in SOURCES:
        data = read_reference(REFERENCE / s.file)
        ev = detect_events(data[:, 2:5], data[:, 6], thigh_length_m=s.thigh_length_m, fps=30)
        found[s.gait] = (ev.heel_strikes / 30.0, ev.toe_offs / 30.0)
    # SOURCES.md: walk heel strikes ~0.2, 1.4, 2.6 s (stride 1.20 s).
    np.testing.assert_allclose(found["walk"][0], [0.2, 1.4, 2.6], atol=0.04)
    # Run: stride 0.733 s (sd 0.016).
    assert abs(np.mean(np.diff(found["run"][0])) - 0.733) < 0.01
    # Climb: contact ~0.35-0.4 s and ~1.8 s, toe-off ~1.27 s.
    hs, to = found["climb"]
    assert 0.33 <= hs[0] <= 0.42 and abs(hs[1] - 1.8) < 0.05
    assert abs(to[0] - 1.27) < 0.07


@needs_reference
def test_cycles_close_and_stance_is_untouched() -> None:
    for cycle, derivation in derive_all(REFERENCE):
        a = cycle.angles_deg
        steps = np.abs(np.diff(a, axis=0))
        wrap = np.abs(a[0] - a[-1])
        # The last frame flows into the first: the wrap step is an ordinary step of the cycle.
        assert np.all(wrap <= steps.max(axis=0) + 1e-9), cycle.gait
        assert derivation.frames == round(derivation.period_s * 30)
        assert cycle.stance.sum() == int(np.ceil(derivation.toe_off_completion * cycle.num_frames))
        # Level gaits: the hip comes back to its height every cycle; stairs: it rises.
        rise = cycle.hip_delta_thigh[:, 1].sum() * cycle.thigh_length_m
        if cycle.gait == "climb":
            assert 0.15 < rise < 0.35
        else:
            assert abs(rise) < 1e-5


def test_committed_cycles_carry_provenance_and_attribution() -> None:
    ts = load_training_set(TRAINING_DATA)
    assert ts.gait_names == tuple(s.gait for s in sorted(SOURCES, key=lambda s: s.gait_id))
    texts = {p.stem: p.read_text() for p in TRAINING_DATA.glob("*.csv")}
    assert "Fukuchi" in texts["run"] and "CC BY 4.0" in texts["run"]
    assert "mocap.cs.cmu.edu" in texts["climb"] and "NSF EIA-0196217" in texts["climb"]
    assert "Apache License 2.0" in texts["walk"]
    for text in texts.values():
        assert "# ground_speed_correction_m_s:" in text


def test_format_round_trips() -> None:
    from animstudio.gaitdata.cycles import parse_cycle

    path = TRAINING_DATA / "walk.csv"
    text = path.read_text()
    assert format_cycle(parse_cycle(text, path=str(path))) == text


def test_derive_entry_point_reports_a_missing_source(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main([str(tmp_path / "nowhere"), str(tmp_path / "out")]) == 1
    assert "reference gait directory not found" in capsys.readouterr().err
    assert not (tmp_path / "out").exists()
    assert main(["only-one-argument"]) == 2


def test_bad_reference_rows_are_located(tmp_path: Path) -> None:
    from animstudio.errors import DataError

    bad = tmp_path / "walk_csuhmc.csv"
    bad.write_text("frame,time_s,thigh_deg,shank_deg,foot_deg,hip_x,hip_y\n0,0,1,2,x,4,5\n")
    with pytest.raises(DataError, match=r"walk_csuhmc.csv:2: non-numeric field"):
        read_reference(bad)
