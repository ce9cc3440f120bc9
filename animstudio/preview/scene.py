"""The 3D scene of the preview: the skinned character, the ground grid and climb stairs.

The character is the Clip's own :class:`~animstudio.core.mesh.SkinnedMesh` on its skeleton (the
same rig and skin the USD export writes). A clip without a mesh (a bare skeleton read from USD)
is drawn as bone lines instead.
"""

from __future__ import annotations

import numpy as np
import viser

from animstudio.preview.pose import PosedClip
from animstudio.preview.stairs import StairFlight, stairs_for_clip

CHARACTER_COLOR = (90, 150, 220)
BONE_COLOR = (30, 60, 160)
STAIR_COLOR = (190, 170, 140)
GRID_MARGIN_M = 6.0


def _same_skin(a: PosedClip, b: PosedClip) -> bool:
    # A re-render of an edited script nearly always keeps the rig: then only the poses change and
    # the mesh is not re-sent (faster, and no flicker in the browser).
    ma, mb = a.clip.mesh, b.clip.mesh
    if ma is None or mb is None:
        return False
    return (
        a.clip.skeleton == b.clip.skeleton
        and np.array_equal(ma.vertices, mb.vertices)
        and np.array_equal(ma.faces, mb.faces)
        and np.array_equal(ma.joint_indices, mb.joint_indices)
        and np.array_equal(ma.joint_weights, mb.joint_weights)
    )


class CharacterView:
    """Scene nodes of one preview; all methods expect the caller to batch in ``server.atomic()``."""

    def __init__(self, server: viser.ViserServer) -> None:
        self._server = server
        self._mesh: viser.MeshSkinnedHandle | None = None
        self._bones: viser.LineSegmentsHandle | None = None
        self._posed: PosedClip | None = None
        self._stairs: list[viser.BoxHandle] = []
        self._flights: tuple[StairFlight, ...] | None = None
        self._grid: viser.GridHandle | None = None
        self._grid_extent: tuple[float, float, float, float] | None = None
        self.num_stair_boxes = 0

    @property
    def has_mesh(self) -> bool:
        return self._mesh is not None

    @property
    def character(self) -> viser.SceneNodeHandle | None:
        """The character's scene node (skinned mesh, or bone lines for a bare skeleton)."""
        return self._mesh if self._mesh is not None else self._bones

    def set_clip(self, posed: PosedClip) -> None:
        """Show ``posed`` (keeping the mesh node if the rig and skin are unchanged)."""
        scene = self._server.scene
        clip = posed.clip
        if self._posed is None or not _same_skin(self._posed, posed):
            if self._mesh is not None:
                self._mesh.remove()
                self._mesh = None
            if self._bones is not None:
                self._bones.remove()
                self._bones = None
            if clip.mesh is not None and posed.skin_weights is not None:
                self._mesh = scene.add_mesh_skinned(
                    "/character",
                    vertices=clip.mesh.vertices.astype(np.float32),
                    faces=clip.mesh.faces,
                    bone_wxyzs=posed.bind_wxyz,
                    bone_positions=posed.bind_positions,
                    skin_weights=posed.skin_weights,
                    color=CHARACTER_COLOR,
                )
            else:
                self._bones = scene.add_line_segments(
                    "/skeleton",
                    points=posed.segments_world(0),
                    colors=BONE_COLOR,
                    thickness=4.0,
                    thickness_units="screen",
                )
        self._posed = posed
        self._set_grid(posed)
        self._set_stairs(posed)

    def show_frame(self, posed: PosedClip, frame: int) -> None:
        """Pose the character at ``frame``."""
        if self._mesh is not None:
            wxyz, pos = posed.frame_pose(frame)
            for j, bone in enumerate(self._mesh.bones):
                bone.wxyz = wxyz[j]
                bone.position = pos[j]
        elif self._bones is not None:
            self._bones.points = posed.segments_world(frame)

    def _set_grid(self, posed: PosedClip) -> None:
        root = posed.clip.root_translations
        lo = np.floor(root[:, [0, 2]].min(axis=0) - GRID_MARGIN_M)
        hi = np.ceil(root[:, [0, 2]].max(axis=0) + GRID_MARGIN_M)
        extent = (float(lo[0]), float(hi[0]), float(lo[1]), float(hi[1]))
        if extent == self._grid_extent:
            return
        if self._grid is not None:
            self._grid.remove()
        self._grid = self._server.scene.add_grid(
            "/ground",
            width=extent[1] - extent[0],
            height=extent[3] - extent[2],
            plane="xz",
            cell_size=0.5,
            section_size=2.0,
            position=(0.5 * (extent[0] + extent[1]), 0.0, 0.5 * (extent[2] + extent[3])),
        )
        self._grid_extent = extent

    def _set_stairs(self, posed: PosedClip) -> None:
        flights = stairs_for_clip(posed.clip)
        if flights == self._flights:
            return  # an edit elsewhere in the script: the same stairs stay
        self._flights = flights
        steps = [step for flight in flights for step in flight.boxes]
        # Move the boxes there are (a re-timed script shifts its stairs) rather than re-create
        # them: creating a scene node costs ~1 ms of viser bookkeeping, on the reload path.
        for handle, step in zip(self._stairs, steps, strict=False):
            handle.dimensions = step.size
            handle.position = step.center
        for handle in self._stairs[len(steps) :]:
            handle.remove()
        for b in range(len(self._stairs), len(steps)):
            self._stairs.append(
                self._server.scene.add_box(
                    f"/stairs/box{b}",
                    dimensions=steps[b].size,
                    position=steps[b].center,
                    color=STAIR_COLOR,
                )
            )
        del self._stairs[len(steps) :]
        self.num_stair_boxes = len(self._stairs)
