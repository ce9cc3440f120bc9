"""Value types and maths shared by every engine, rig, exporter and the preview.

No I/O, no pxr / viser / click / trimesh imports here.
"""

from animstudio.core.channels import GaitChannels
from animstudio.core.clip import Clip, ClipEvent, ClipSegment
from animstudio.core.mesh import SkinnedMesh
from animstudio.core.skeleton import Skeleton

__all__ = ["Clip", "ClipEvent", "ClipSegment", "GaitChannels", "Skeleton", "SkinnedMesh"]
