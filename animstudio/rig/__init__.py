"""Characters: skeletons, skinned meshes, and the mapping from GaitChannels to a Clip."""

from __future__ import annotations

import importlib

from animstudio.core.channels import GaitChannels
from animstudio.core.clip import Clip

_RIGS = {"humanoid": "animstudio.rig.humanoid", "hexapod": "animstudio.rig.hexapod"}


def clip_from_channels(channels: GaitChannels) -> Clip:
    """Pose the character named by ``channels.character`` with the channels (module ``rig.<character>``)."""
    module = importlib.import_module(_RIGS[channels.character])
    return module.clip_from_channels(channels)  # type: ignore[no-any-return, unused-ignore]
