"""Runs INSIDE Blender's Python (.venv-blender/bin/python), not under pytest.

Usage: python blender_import.py FILE JOINT FRAME[,FRAME...]

Imports FILE (.usda/.usdc with ``bpy.ops.wm.usd_import``, .bvh with
``bpy.ops.import_anim.bvh``) into an empty scene and prints one line ``RESULT {json}`` with
the armature's bone count, the scene frame range and fps as Blender set them, the imported
action's keyed frame range, and the world position (Blender's Z-up world, metres) of bone
JOINT's head at each requested file frame ``k``, evaluated at Blender frame
``first keyed frame + k`` (Blender starts BVH motion at frame 1, USD time code k at frame k).
"""

from __future__ import annotations

import json
import sys

import bpy


def main() -> None:
    path, joint, frames_arg = sys.argv[1], sys.argv[2], sys.argv[3]
    frames = [int(f) for f in frames_arg.split(",")]
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    if path.endswith(".bvh"):
        bpy.ops.import_anim.bvh(
            filepath=path,
            frame_start=1,
            update_scene_fps=True,
            update_scene_duration=True,
            rotate_mode="NATIVE",
        )
    else:
        bpy.ops.wm.usd_import(filepath=path, set_frame_range=True, import_skeletons=True)
    armatures = [o for o in scene.objects if o.type == "ARMATURE"]
    assert len(armatures) == 1, [o.name for o in scene.objects]
    arm = armatures[0]
    action = arm.animation_data.action if arm.animation_data else None
    keyed = list(action.frame_range) if action else None
    first = round(keyed[0]) if keyed else 0
    positions = []
    for f in frames:
        scene.frame_set(first + f)
        bpy.context.view_layer.update()
        head = arm.matrix_world @ arm.pose.bones[joint].head
        positions.append([head.x, head.y, head.z])
    result = {
        "blender": bpy.app.version_string,
        "bones": len(arm.data.bones),
        "bone_names": [b.name for b in arm.data.bones],
        "frame_start": scene.frame_start,
        "frame_end": scene.frame_end,
        "fps": scene.render.fps / scene.render.fps_base,
        "keyed_range": keyed,
        "positions": positions,
    }
    print("RESULT " + json.dumps(result), flush=True)


main()
