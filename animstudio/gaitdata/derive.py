"""Derive the training cycles in ``training_data/`` from the shared reference trials.

``python -m animstudio.gaitdata.derive SRC_DIR OUT_DIR`` regenerates ``OUT_DIR/<gait>.csv`` from
``SRC_DIR`` (``../shared/reference_gait``: one real trial per gait, right leg, sagittal plane,
30 fps; see its SOURCES.md). Per gait (docs/training-data.md has the numbers):

1. Detect heel strikes and toe-offs (:mod:`animstudio.gaitdata.events`).
2. Pick ONE real stride, heel strike to heel strike: the one whose end pose is closest to its
   start pose (smallest RMS of the Q, F, Y mismatch), so the least correction is needed. No
   averaging: every frame comes from one stride of one recording.
3. Resample it to ``N = round(period * 30)`` frames spanning exactly one period (cubic spline
   through the 30 fps samples, at ``t0 + k * period / N``, k = 0..N) — sub-frame heel strikes
   make the cycle an exact period, at the cost of a time scale of N/(30 period) (< 1.5 %).
4. Close the cycle: the end-to-start mismatch ``m = x(N) - x(0)`` of Q, F, Y (and of the hip
   height for level gaits) is removed with a ramp that is 0 through stance and grows linearly
   over the swing, ``x'(k) = x(k) - m * clip((k - k_toe_off) / (N - k_toe_off), 0, 1)``. Stance
   frames stay exactly as measured (a correction there would make the planted foot slide), and
   frame N - 1 flows into frame 0. The hip's forward displacement is never corrected (its sum
   over the cycle is the measured stride length); on the stairs the measured hip rise is kept.
5. Ground-speed calibration: the thesis's hip deltas in thigh lengths presume the character is
   the subject scaled. Posing the character's leg (its proportions scaled to the subject's thigh)
   with the recorded angles over the recorded hip path, the planted foot still creeps (walk:
   the treadmill belt speed is an estimate, and the subject's shank/thigh ratio is unknown).
   A constant forward speed is added to the hip path so the planted foot's mean slip over the
   stance frames is zero (least squares) when the root moves as the controller moves it (the
   mean of both legs' hip deltas, half a cycle apart); the value is in each file's header.
6. Express hip displacements per frame in the subject's thigh lengths (SOURCES.md values).
"""

from __future__ import annotations

import sys
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray
from scipy.interpolate import CubicSpline

from animstudio.errors import DataError
from animstudio.export.atomic import write_text
from animstudio.gaitdata.cycles import FORMAT, FPS, Cycle, format_cycle
from animstudio.gaitdata.events import detect_events
from animstudio.gaitdata.legs import leg_points
from animstudio.rig.proportions import THIGH_M

REFERENCE_COLUMNS = ("frame", "time_s", "thigh_deg", "shank_deg", "foot_deg", "hip_x", "hip_y")
CHANNELS = ("thigh_deg", "shank_deg", "foot_deg", "hip_x", "hip_y")


@dataclass(frozen=True)
class GaitSource:
    """One reference trial and what SOURCES.md says about it.

    Attributes:
        gait: the gait name the cycle file gets.
        file: the reference CSV's name in the source directory.
        gait_id: the thesis's identifier (walk 0.2, run 0.4, climb 0.6).
        thigh_length_m: the subject's thigh length stated in SOURCES.md.
        level: level ground (the hip height closes over a cycle) vs stairs (the rise is kept).
        source: provenance line. licence: licence line. attribution: required acknowledgement.
    """

    gait: str
    file: str
    gait_id: float
    thigh_length_m: float
    level: bool
    source: str
    licence: str
    attribution: str


SOURCES: tuple[GaitSource, ...] = (
    GaitSource(
        gait="walk",
        file="walk_csuhmc.csv",
        gait_id=0.2,
        thigh_length_m=0.405,
        level=True,
        source="treadmill walking, subject 7 (67.2 kg), test data rawdata.txt of GaitAnalysisToolKit "
        "0.2.0 (csu-hmc/GaitAnalysisToolKit, Cleveland State University Human Motion and Control "
        "lab, A. J. van den Bogert); markers RGTRO/RLEK/RLM/RMT5, 100 Hz, 6 Hz low-pass, belt "
        "speed 0.98 m/s added to hip_x",
        licence="Apache License 2.0 (GaitAnalysisToolKit, Copyright 2014-2025 "
        "GaitAnalysisToolKit Authors)",
        attribution="Derived from GaitAnalysisToolKit test data (Apache-2.0), "
        "https://github.com/csu-hmc/GaitAnalysisToolKit",
    ),
    GaitSource(
        gait="run",
        file="run_rbds.csv",
        gait_id=0.4,
        thigh_length_m=0.475,
        level=True,
        source="treadmill running at 3.5 m/s, RBDS0041runT35 of the Running Biomechanics Data "
        "Set (regifukuchi/BMC-RIC-running-biomechanics, commit 29027fbb); 150 Hz markers, "
        "Harrington hip joint centre, 10 Hz low-pass, belt speed 3.5 m/s added to hip_x",
        licence="Creative Commons Attribution 4.0 International (CC BY 4.0)",
        attribution="Fukuchi RK, Fukuchi CA, Duarte M (2017) A public dataset of running "
        "biomechanics and the effects of running speed on lower extremity kinematics and "
        "kinetics. PeerJ 5:e3298, doi:10.7717/peerj.3298; data doi:10.6084/m9.figshare.4543435",
    ),
    GaitSource(
        gait="climb",
        file="climb_cmu.csv",
        gait_id=0.6,
        thigh_length_m=0.3765,
        level=False,
        source="stair ascent, CMU Graphics Lab Motion Capture Database subject 83 trial 30 "
        "('walk forward stepping up stairs'), cgspeed BVH 83_30.bvh frames ~643-874 "
        "(una-dinosauria/cmu-mocap), 120 Hz, 6 Hz low-pass",
        licence="CMU terms: free for research and for inclusion in commercial products; the "
        "data may not be resold directly, even in converted form",
        attribution="The data used in this project was obtained from mocap.cs.cmu.edu. The "
        "database was created with funding from NSF EIA-0196217.",
    ),
)


@dataclass(frozen=True)
class Derivation:
    """The numbers behind one derived cycle (for the header and docs/training-data.md).

    Attributes:
        heel_strikes_s: all heel strikes found in the trial.
        toe_offs_s: the toe-off of each complete stride.
        stride: index of the chosen stride; period_s: its duration; frames: N.
        toe_off_completion: toe-off as a fraction of the cycle.
        mismatch: ``channel -> end - start`` removed by the closure ramp (0 for uncorrected ones).
        wrap_velocity_jump: ``channel -> per-frame step change across the wrap`` after closing.
        ground_speed_correction_m_s: speed added to the hip's forward motion (step 5).
    """

    heel_strikes_s: tuple[float, ...]
    toe_offs_s: tuple[float, ...]
    stride: int
    period_s: float
    frames: int
    toe_off_completion: float
    mismatch: dict[str, float]
    wrap_velocity_jump: dict[str, float]
    ground_speed_correction_m_s: float


def read_reference(path: Path) -> NDArray[np.float64]:
    """``(F, 7)`` rows of a reference CSV (columns :data:`REFERENCE_COLUMNS`)."""
    try:
        lines = path.read_text(encoding="utf-8").splitlines()
    except (OSError, UnicodeDecodeError) as exc:
        raise DataError(f"{path}: cannot read reference trial: {exc}") from None
    if not lines or lines[0].strip() != ",".join(REFERENCE_COLUMNS):
        raise DataError(f"{path}:1: expected the column line {','.join(REFERENCE_COLUMNS)!r}")
    rows = []
    for i, line in enumerate(lines[1:], start=2):
        try:
            values = [float(v) for v in line.split(",")]
        except ValueError:
            raise DataError(f"{path}:{i}: non-numeric field") from None
        if len(values) != len(REFERENCE_COLUMNS) or not np.all(np.isfinite(values)):
            raise DataError(f"{path}:{i}: expected {len(REFERENCE_COLUMNS)} finite numbers")
        rows.append(values)
    data = np.array(rows, dtype=np.float64)
    if len(data) < 4 or not np.allclose(np.diff(data[:, 1]), 1.0 / FPS, atol=1e-3):
        raise DataError(f"{path}: expected at least 4 rows at {FPS} fps")
    return data


def derive_cycle(source: GaitSource, data: NDArray[np.float64]) -> tuple[Cycle, Derivation]:
    """The closed cycle of one reference trial (module docstring: the steps)."""
    events = detect_events(data[:, 2:5], data[:, 6], thigh_length_m=source.thigh_length_m, fps=FPS)
    hs, to = events.heel_strikes, events.toe_offs
    if len(hs) < 2:
        raise DataError(f"{source.file}: fewer than two heel strikes, no complete stride")
    frames = np.arange(len(data), dtype=np.float64)
    splines = [CubicSpline(frames, data[:, c]) for c in range(2, 7)]

    def sample(i: int) -> tuple[int, NDArray[np.float64]]:
        n = round(hs[i + 1] - hs[i])  # the trials are at 30 fps already
        times = hs[i] + np.arange(n + 1) * (hs[i + 1] - hs[i]) / n
        return n, np.column_stack([s(times) for s in splines])  # (N + 1, 5)

    def angle_mismatch(i: int) -> float:
        x = sample(i)[1]
        return float(np.sqrt(np.mean((x[-1, :3] - x[0, :3]) ** 2)))

    best = min(range(len(hs) - 1), key=angle_mismatch)
    n, x = sample(best)
    k_to = (to[best] - hs[best]) * n / (hs[best + 1] - hs[best])
    ramp = np.clip((np.arange(n + 1) - k_to) / (n - k_to), 0.0, 1.0)
    corrected = [0, 1, 2, 4] if source.level else [0, 1, 2]
    mismatch = {name: 0.0 for name in CHANNELS}
    for c in corrected:
        m = x[-1, c] - x[0, c]
        mismatch[CHANNELS[c]] = float(m)
        x[:, c] -= ramp * m
    stance = np.arange(n) < k_to
    slip = _stance_slip(x, stance, source.thigh_length_m)
    x[:, 3] -= slip * np.arange(n + 1)
    step = np.diff(x, axis=0)  # (N, 5) per-frame steps; step[k] is frame k -> k + 1
    wrap = {name: float(step[0, c] - step[-1, c]) for c, name in enumerate(CHANNELS)}
    derivation = Derivation(
        heel_strikes_s=tuple(float(v) / FPS for v in hs),
        toe_offs_s=tuple(float(v) / FPS for v in to),
        stride=best,
        period_s=float(hs[best + 1] - hs[best]) / FPS,
        frames=n,
        toe_off_completion=float(k_to / n),
        mismatch=mismatch,
        wrap_velocity_jump=wrap,
        ground_speed_correction_m_s=float(-slip * n / (hs[best + 1] - hs[best]) * FPS),
    )
    header = {
        "format": FORMAT,
        "gait": source.gait,
        "gait_id": f"{source.gait_id:g}",
        "fps": str(FPS),
        "frames": str(n),
        "period_s": f"{derivation.period_s:.4f}",
        "thigh_length_m": f"{source.thigh_length_m:g}",
        "toe_off_completion": f"{derivation.toe_off_completion:.4f}",
        "source": source.source,
        "source_file": f"{source.file} (shared reference_gait, SOURCES.md)",
        "licence": source.licence,
        "attribution": source.attribution,
        "heel_strikes_s": " ".join(f"{v:.3f}" for v in derivation.heel_strikes_s),
        "toe_offs_s": " ".join(f"{v:.3f}" for v in derivation.toe_offs_s),
        "stride_used": f"{best + 1} of {len(hs) - 1} "
        f"({hs[best] / FPS:.3f} s to {hs[best + 1] / FPS:.3f} s), smallest end-to-start mismatch",
        "closure_mismatch_end_minus_start": ", ".join(
            f"{name} {mismatch[name]:+.4f}" for name in CHANNELS if name in mismatch
        )
        + " (ramp over swing; hip_x never corrected"
        + ("" if source.level else "; stair rise of hip_y kept")
        + ")",
        "ground_speed_correction_m_s": f"{derivation.ground_speed_correction_m_s:+.4f} "
        "(makes the planted foot's mean slip zero; docs/training-data.md)",
        "derived_by": "python -m animstudio.gaitdata.derive (docs/training-data.md)",
    }
    cycle = Cycle(
        gait=source.gait,
        gait_id=source.gait_id,
        thigh_length_m=source.thigh_length_m,
        angles_deg=x[:n, :3].copy(),
        hip_delta_thigh=step[:, 3:5] / source.thigh_length_m,
        stance=stance,
        header=header,
    )
    return cycle, derivation


def _stance_slip(x: NDArray[np.float64], stance: NDArray[np.bool_], thigh_m: float) -> float:
    """Mean per-frame forward slip (m) of the planted foot's ground contact during stance.

    The hip moves as the controller moves the root (:mod:`animstudio.som.motion`): the mean of
    the hip steps of both legs, which run half a cycle apart (for an odd N the two nearest
    half-cycle offsets are averaged). The contact point is whichever of heel and toe joint is
    lower at frame k, followed to k + 1 (so the hand-over from heel to toe is not a jump).
    """
    n = len(stance)
    hip_step = np.diff(x[:, 3])  # (N,) step k is frame k -> k + 1
    k = np.arange(n)
    other = 0.5 * (hip_step[(k + n // 2) % n] + hip_step[(k + (n + 1) // 2) % n])
    root_step = 0.5 * (hip_step + other)
    pts = leg_points(x[:, :3], scale=thigh_m / THIGH_M)
    use_heel = pts.heel[:, 1] <= pts.toe[:, 1]
    here = np.where(use_heel, pts.heel[:, 0], pts.toe[:, 0])
    there = np.where(use_heel[:-1], pts.heel[1:, 0], pts.toe[1:, 0])
    slip = root_step + there - here[:-1]
    return float(np.mean(slip[stance]))


def derive_all(
    source_dir: Path, sources: Sequence[GaitSource] = SOURCES
) -> list[tuple[Cycle, Derivation]]:
    """Derive every gait of ``sources`` from the trials in ``source_dir``."""
    source_dir = Path(source_dir)
    if not source_dir.is_dir():
        raise DataError(f"{source_dir}: reference gait directory not found")
    return [derive_cycle(s, read_reference(source_dir / s.file)) for s in sources]


def write_training_data(source_dir: Path, out_dir: Path) -> list[Path]:
    """Regenerate ``out_dir/<gait>.csv`` from ``source_dir``; returns the files written."""
    written = []
    for cycle, _ in derive_all(source_dir):
        target = Path(out_dir) / f"{cycle.gait}.csv"
        write_text(target, format_cycle(cycle))
        written.append(target)
    return written


def main(argv: Sequence[str]) -> int:
    """``python -m animstudio.gaitdata.derive SRC_DIR OUT_DIR``."""
    if len(argv) != 2:
        sys.stderr.write("usage: python -m animstudio.gaitdata.derive SRC_DIR OUT_DIR\n")
        return 2
    try:
        paths = write_training_data(Path(argv[0]), Path(argv[1]))
    except DataError as exc:
        sys.stderr.write(f"error: {exc}\n")
        return 1
    for p in paths:
        sys.stdout.write(f"wrote {p}\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
