"""``OUT_DIR/manifest.json``: what each input rendered to, and whether a re-run may skip it.

The manifest is rewritten atomically after every finished job, so a killed batch loses at most
its in-flight work. Layout (``manifest_version`` 1)::

    {"manifest_version": 1, "generator": "animstudio batch",
     "entries": {"shots/a.gait": {
        "input": "shots/a.gait", "input_sha256": "...", "animstudio_version": "0.1.0",
        "settings": {"formats": ["usdc", "bvh"], "fps": 24, "weights_sha256": null},
        "status": "ok", "error": null, "engine": "som",
        "frames": 240, "duration_s": 10.0, "fps": 24.0, "source_fps": 30.0,
        "outputs": {"usdc": {"path": "shots/a.usdc", "bytes": 81234, "sha256": "..."}},
        "render_s": 0.41, "worker_peak_rss_mb": 151.3, "worker": "host:4242", "notes": []}}}

``settings.fps`` is the requested rate (``null``: each script's own); ``fps`` the rate written.
Output paths are relative to ``OUT_DIR``. ``worker`` is ``hostname:pid`` of the process that
rendered the entry, ``worker_peak_rss_mb`` that process's peak resident memory when it finished.
"""

from __future__ import annotations

import hashlib
import json
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any, Literal

from animstudio.errors import DataError
from animstudio.export import atomic

MANIFEST_NAME = "manifest.json"
MANIFEST_VERSION = 1

Status = Literal["ok", "failed"]


@dataclass(frozen=True)
class BatchSettings:
    """Everything besides the script and the version that changes what a job writes."""

    formats: tuple[str, ...]
    fps: int | None = None
    weights_sha256: str | None = None


@dataclass(frozen=True)
class OutputRecord:
    """One written file: ``path`` relative to OUT_DIR, its size and SHA-256."""

    path: str
    bytes: int
    sha256: str


@dataclass(frozen=True)
class Entry:
    """The manifest record of one input script (see the module docstring for the JSON)."""

    input: str
    input_sha256: str
    animstudio_version: str
    settings: BatchSettings
    status: Status
    error: str | None = None
    engine: str | None = None
    frames: int | None = None
    duration_s: float | None = None
    fps: float | None = None
    source_fps: float | None = None
    outputs: dict[str, OutputRecord] = field(default_factory=dict)
    render_s: float = 0.0
    worker_peak_rss_mb: float | None = None
    worker: str | None = None
    notes: tuple[str, ...] = ()

    def to_json(self) -> dict[str, Any]:
        data = asdict(self)
        data["settings"]["formats"] = list(self.settings.formats)
        data["notes"] = list(self.notes)
        return data

    @staticmethod
    def from_json(data: dict[str, Any]) -> Entry:
        s = data["settings"]
        settings = BatchSettings(tuple(s["formats"]), s["fps"], s["weights_sha256"])
        outputs = {fmt: OutputRecord(**rec) for fmt, rec in data["outputs"].items()}
        fields = {k: v for k, v in data.items() if k not in ("settings", "outputs", "notes")}
        if fields.get("status") not in ("ok", "failed"):
            raise ValueError(f"bad status {fields.get('status')!r}")
        return Entry(**fields, settings=settings, outputs=outputs, notes=tuple(data["notes"]))


def sha256_bytes(data: bytes) -> str:
    return hashlib.sha256(data).hexdigest()


def sha256_file(path: Path) -> str:
    """Hex SHA-256 of a file's contents, read in 1 MiB blocks."""
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        for block in iter(lambda: fh.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def load_manifest(out_dir: Path) -> dict[str, Entry]:
    """The entries of ``out_dir/manifest.json`` by input path (empty if there is none).

    Raises:
        DataError: the file exists but is not a batch manifest of this version.
    """
    path = out_dir / MANIFEST_NAME
    if not path.exists():
        return {}
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
        if data.get("manifest_version") != MANIFEST_VERSION:
            raise ValueError(f"manifest_version {data.get('manifest_version')!r}")
        return {rel: Entry.from_json(raw) for rel, raw in data["entries"].items()}
    except (OSError, ValueError, KeyError, TypeError, AttributeError) as exc:
        raise DataError(
            f"{path}: not an animstudio batch manifest ({exc}); "
            "delete it or re-run with --force to render everything again"
        ) from exc


class ManifestWriter:
    """Keeps ``OUT_DIR/manifest.json`` current as entries arrive, in time linear in the batch.

    Each entry is serialised once, when it is put (one JSON line per entry); a save joins the
    cached lines. Re-encoding every entry on every save made a 200-script batch spend most of
    its time in ``json`` (quadratic).
    """

    def __init__(self, out_dir: Path) -> None:
        self.out_dir = out_dir
        self._lines: dict[str, str] = {}

    def put(self, entry: Entry) -> None:
        self._lines[entry.input] = json.dumps(entry.to_json(), separators=(", ", ": "))

    def save(self) -> None:
        """Atomically write the manifest with every entry put so far (sorted by input path)."""
        body = ",\n".join(f"  {json.dumps(rel)}: {self._lines[rel]}" for rel in sorted(self._lines))
        text = (
            f'{{"manifest_version": {MANIFEST_VERSION}, "generator": "animstudio batch",\n'
            f' "entries": {{\n{body}\n }}}}\n'
        )
        atomic.write_text(self.out_dir / MANIFEST_NAME, text)


def save_manifest(out_dir: Path, entries: dict[str, Entry]) -> None:
    """Atomically write ``out_dir/manifest.json`` with ``entries`` (sorted by input path)."""
    writer = ManifestWriter(out_dir)
    for entry in entries.values():
        writer.put(entry)
    writer.save()


def is_up_to_date(
    entry: Entry | None, *, input_sha256: str, settings: BatchSettings, version: str, out_dir: Path
) -> bool:
    """Whether a re-run may skip this input: it rendered fine with the same script, settings and
    version, and every recorded output is still on disk with its recorded size and SHA-256."""
    if entry is None or entry.status != "ok":
        return False
    if (entry.input_sha256, entry.settings, entry.animstudio_version) != (
        input_sha256,
        settings,
        version,
    ):
        return False
    if set(entry.outputs) != set(settings.formats):
        return False
    for rec in entry.outputs.values():
        path = out_dir / rec.path
        try:
            if path.stat().st_size != rec.bytes:
                return False
        except OSError:
            return False
        if sha256_file(path) != rec.sha256:
            return False
    return True
