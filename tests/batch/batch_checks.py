"""Shared by the batch tests: a script tree of real gait scripts, and readers checking outputs.

Each reader parses a whole file with an independent tool (pxr for USD, a token reader for BVH,
the csv module for CSV) and returns what it found, so a truncated or garbled file fails loudly.
"""

from __future__ import annotations

import csv
import json
from pathlib import Path

# Real scripts for the real pipeline (Kohonen engine, humanoid), short so the suite stays fast.
SCRIPTS = {
    "walk.gait": "engine som\ncharacter humanoid\nfps 30\n\nwalk 1s / run 20\n",
    "shots/a.gait": "# shot 10\nwalk 2s\n",
    "shots/deep/b.gait": "engine som\nfps 30\nrun 1s / climb 15\n",
    "shots/c.gait": "walk 30 / climb 30\n",
}
BAD = {"shots/bad.gait": "walk 10\nwlak 10\n"}  # line 2, column 1: unknown gait
FRAMES_30 = {"walk.gait": 50, "shots/a.gait": 60, "shots/deep/b.gait": 45, "shots/c.gait": 60}


def make_tree(root: Path, scripts: dict[str, str]) -> Path:
    for rel, text in scripts.items():
        path = root / rel
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text)
    return root


def read_manifest(out_dir: Path) -> dict:
    return json.loads((out_dir / "manifest.json").read_text())["entries"]


def check_usd(path: Path) -> dict:
    """Open a USD export with pxr and return its frame count, fps and joint count."""
    from pxr import Usd, UsdSkel

    stage = Usd.Stage.Open(str(path))
    assert stage is not None, path
    anims = [UsdSkel.Animation(p) for p in stage.Traverse() if p.IsA(UsdSkel.Animation)]
    skels = [UsdSkel.Skeleton(p) for p in stage.Traverse() if p.IsA(UsdSkel.Skeleton)]
    assert len(anims) == 1 and len(skels) == 1, path
    rot_times = anims[0].GetRotationsAttr().GetTimeSamples()
    joints = skels[0].GetJointsAttr().Get()
    frames = int(stage.GetEndTimeCode() - stage.GetStartTimeCode()) + 1
    assert stage.GetStartTimeCode() == 0
    assert len(rot_times) == frames, (path, len(rot_times), frames)
    assert stage.GetTimeCodesPerSecond() == stage.GetFramesPerSecond()
    rots = anims[0].GetRotationsAttr().Get(frames - 1)
    assert len(rots) == len(joints)
    return {"frames": frames, "fps": stage.GetTimeCodesPerSecond(), "joints": len(joints)}


def check_bvh(path: Path) -> dict:
    """Parse a BVH file fully; return frames, fps and joint count."""
    tokens = path.read_text().split()
    m = tokens.index("MOTION")
    joints = sum(1 for t in tokens[:m] if t in ("ROOT", "JOINT"))
    channels = sum(int(tokens[i + 1]) for i, t in enumerate(tokens[:m]) if t == "CHANNELS")
    assert tokens[m + 1] == "Frames:" and tokens[m + 3 : m + 5] == ["Frame", "Time:"]
    frames = int(tokens[m + 2])
    frame_time = float(tokens[m + 5])
    values = tokens[m + 6 :]
    assert len(values) == frames * channels, (path, len(values), frames * channels)
    [float(v) for v in values]
    assert tokens[:m].count("{") == tokens[:m].count("}")
    return {"frames": frames, "fps": round(1.0 / frame_time, 3), "joints": joints}


def check_csv(path: Path) -> dict:
    """Parse a CSV export fully; return frames and fps (from the time column)."""
    with open(path, newline="") as fh:
        rows = list(csv.reader(fh))
    header = rows[0]
    assert header[:2] == ["frame", "time_s"]
    body = [[float(v) for v in r] for r in rows[1:]]
    assert all(len(r) == len(header) for r in body)
    assert [int(r[0]) for r in body] == list(range(len(body)))
    fps = round(1.0 / body[1][1], 3) if len(body) > 1 else None
    joints = sum(1 for h in header if h.endswith("_quat_w"))
    return {"frames": len(body), "fps": fps, "joints": joints}


CHECKERS = {"usdc": check_usd, "usda": check_usd, "bvh": check_bvh, "csv": check_csv}


def check_output(path: Path) -> dict:
    return CHECKERS[path.suffix.lstrip(".")](path)
