"""Generation + USD export of a 10-minute Kohonen script (18,000 frames at 30 fps).

Target (issue 2): under 1 s in total on the 2-core machine. Prints the split between
control (the Kohonen controller), rig (channels -> Clip) and export (Clip -> .usdc / .usda),
as the median over repeats, beside a baseline measured in the same process: writing the same
number of frames with the plain per-frame ``UsdSkel.Animation.SetRotationsAttr().Set(v, t)`` loop
that the USD docs show (what our exporter is compared against).

Run:  python benchmarks/bench_render.py [--repeats 5]
"""

from __future__ import annotations

import argparse
import statistics
import tempfile
import time
from pathlib import Path

from animstudio import pipeline
from animstudio.export.usd import write_usd
from animstudio.rig import clip_from_channels

SCRIPT = """# 10 minutes: the three gaits in turn
engine som
walk 60s / run 30s / climb 30s
walk 120s / run 60s / walk 120s / climb 60s / walk 120s
"""


def naive_usd_export(clip, path: Path) -> None:  # type: ignore[no-untyped-def]
    """Baseline: author every frame through the high-level attribute API, one Set per sample."""
    from pxr import Gf, Usd, UsdSkel, Vt

    stage = Usd.Stage.CreateNew(str(path))
    anim = UsdSkel.Animation.Define(stage, "/Anim")
    anim.CreateJointsAttr(Vt.TokenArray(list(clip.skeleton.joint_paths)))
    rot_attr = anim.CreateRotationsAttr()
    trans_attr = anim.CreateTranslationsAttr()
    local_t = clip.local_translations()
    for f in range(clip.num_frames):
        q = clip.local_rotations[f]
        rot_attr.Set(Vt.QuatfArray([Gf.Quatf(*map(float, r)) for r in q]), Usd.TimeCode(f))
        trans_attr.Set(
            Vt.Vec3fArray([Gf.Vec3f(*map(float, t)) for t in local_t[f]]), Usd.TimeCode(f)
        )
    stage.Save()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()

    script = pipeline.parse_script(SCRIPT, path="bench.gait")
    assert script.total_frames == 18_000, script.total_frames
    pipeline.render(script)  # warm-up: imports, JIT compilation, cached meshes

    times: dict[str, list[float]] = {
        "control": [],
        "rig": [],
        "export .usdc": [],
        "export .usda": [],
    }
    baseline: list[float] = []
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp)
        for _ in range(args.repeats):
            t0 = time.perf_counter()
            channels = pipeline.generate(script)
            t1 = time.perf_counter()
            clip = clip_from_channels(channels)
            t2 = time.perf_counter()
            write_usd(out / "bench.usdc", clip)
            t3 = time.perf_counter()
            write_usd(out / "bench.usda", clip)
            t4 = time.perf_counter()
            times["control"].append(t1 - t0)
            times["rig"].append(t2 - t1)
            times["export .usdc"].append(t3 - t2)
            times["export .usda"].append(t4 - t3)
        for _ in range(max(1, args.repeats // 2)):
            t0 = time.perf_counter()
            naive_usd_export(clip, out / "naive.usdc")
            baseline.append(time.perf_counter() - t0)

    med = {k: statistics.median(v) for k, v in times.items()}
    total = med["control"] + med["rig"] + med["export .usdc"]
    print(
        f"10-minute script: {script.total_frames} frames, {clip.skeleton.num_joints} joints, "
        f"median of {args.repeats}"
    )
    for name, value in med.items():
        print(f"  {name:<14} {value * 1000:8.1f} ms")
    print(
        f"  {'total (usdc)':<14} {total * 1000:8.1f} ms   target < 1000 ms -> "
        f"{'PASS' if total < 1.0 else 'FAIL'}"
    )
    naive = statistics.median(baseline)
    print(
        f"  baseline: per-frame Attribute.Set export of the same frames: {naive * 1000:.1f} ms "
        f"({naive / med['export .usdc']:.1f}x our .usdc export)"
    )


if __name__ == "__main__":
    main()
