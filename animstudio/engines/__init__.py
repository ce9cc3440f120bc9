"""Motion engines: a Script in, GaitChannels out.

Each engine module provides an object satisfying :class:`Engine`; :func:`get_engine` is the
one lookup by name. Engines are imported lazily so that, e.g., rendering a Kohonen script never
pays for compiling the biped simulator.
"""

from __future__ import annotations

import importlib
from dataclasses import dataclass
from pathlib import Path
from typing import Protocol

from animstudio.core.channels import GaitChannels
from animstudio.errors import ScriptError
from animstudio.script.model import ENGINES, Script


@dataclass(frozen=True)
class EngineOptions:
    """Settings that come from the command line rather than the script.

    Attributes:
        weights: Kohonen weights file (``None``: the shipped default weights).
    """

    weights: Path | None = None


class Engine(Protocol):
    name: str
    characters: tuple[str, ...]

    def gaits(self, options: EngineOptions) -> tuple[str, ...]:
        """The gait names a script may use with this engine."""
        ...

    def validate(self, script: Script, options: EngineOptions) -> list[ScriptError]:
        """Every located problem of ``script`` for this engine (unknown gaits, bad params, events)."""
        ...

    def generate(self, script: Script, options: EngineOptions) -> GaitChannels:
        """Run the engine over the whole script. ``script`` has passed :meth:`validate`."""
        ...


_MODULES = {
    "som": "animstudio.engines.som",
    "cpg": "animstudio.engines.cpg",
    "obb": "animstudio.engines.obb",
}


def get_engine(name: str) -> Engine:
    """The engine called ``name`` (one of :data:`animstudio.script.model.ENGINES`)."""
    assert name in ENGINES, name  # the parser only produces valid engine names
    module = importlib.import_module(_MODULES[name])
    return module.ENGINE  # type: ignore[no-any-return, unused-ignore]
