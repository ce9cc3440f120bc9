"""Figures of the engines' internals: ``plot(script, kind, out_path, options=...)``.

Each engine ``<name>`` that has figures provides ``animstudio.plots.<name>`` with ``KINDS`` (the
figure names) and ``plot(script, kind, out_path, *, options)``. Modules are imported lazily:
plotting a Kohonen script never compiles the biped. Figures use matplotlib's Agg canvas (no
display needed) and are written atomically (``animstudio.export.atomic.write_with``).
"""

from __future__ import annotations

import difflib
import importlib
from collections.abc import Iterator, Mapping
from pathlib import Path
from types import ModuleType

from animstudio.engines import EngineOptions
from animstudio.errors import UnknownName
from animstudio.script.model import ENGINES, Script

_MODULES: dict[str, str] = {"cpg": "animstudio.plots.cpg", "obb": "animstudio.plots.obb"}


def _module(engine: str) -> ModuleType | None:
    name = _MODULES.get(engine)
    return importlib.import_module(name) if name is not None else None


def kinds(engine: str) -> tuple[str, ...]:
    """The figure kinds of ``engine`` (empty for an engine without figures)."""
    module = _module(engine)
    return tuple(module.KINDS) if module is not None else ()


class _KindsByEngine(Mapping[str, tuple[str, ...]]):
    """``engine -> kinds`` over every engine; each plot module is imported on first access."""

    def __init__(self) -> None:
        self._cache: dict[str, tuple[str, ...]] = {}

    def __getitem__(self, engine: str) -> tuple[str, ...]:
        if engine not in ENGINES:
            raise KeyError(engine)
        if engine not in self._cache:
            self._cache[engine] = kinds(engine)
        return self._cache[engine]

    def __iter__(self) -> Iterator[str]:
        return iter(ENGINES)

    def __len__(self) -> int:
        return len(ENGINES)


KINDS_BY_ENGINE: Mapping[str, tuple[str, ...]] = _KindsByEngine()
"""``engine -> figure kinds``, filled lazily from ``animstudio.plots.<engine>.KINDS``."""


def plot(
    script: Script, kind: str, out_path: Path, *, options: EngineOptions | None = None
) -> None:
    """Render figure ``kind`` of ``script`` into the PNG ``out_path`` (written atomically).

    Raises:
        UnknownName: ``kind`` is not a figure of the script's engine (lists the valid ones).
    """
    valid = KINDS_BY_ENGINE[script.engine]
    if kind not in valid:
        listing = ", ".join(f"'{k}'" for k in valid) if valid else "none"
        close = difflib.get_close_matches(kind, valid, n=1, cutoff=0.6)
        hint = f"did you mean '{close[0]}'? " if close else ""
        raise UnknownName(
            f"unknown plot kind '{kind}' for engine {script.engine} ({hint}valid kinds: {listing})"
        )
    module = _module(script.engine)
    assert module is not None  # valid is non-empty only for engines with a module
    module.plot(script, kind, Path(out_path), options=options or EngineOptions())
