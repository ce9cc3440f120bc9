"""One batch job, run in a worker process (local pool or Dask worker): script in, files out.

:func:`render_job` is a module-level function of plain, picklable values, so it runs the same
under ``ProcessPoolExecutor`` with the ``spawn`` start method and on a Dask worker. It never
raises for a bad script: every problem becomes a ``failed`` :class:`~animstudio.batch.manifest.Entry`
carrying the located message, so one bad script never stops a batch.
"""

from __future__ import annotations

import os
import resource
import socket
import sys
import time
import warnings
from dataclasses import dataclass, replace
from pathlib import Path

from animstudio import __version__
from animstudio.batch.discovery import output_relpath
from animstudio.batch.manifest import BatchSettings, Entry, OutputRecord, sha256_bytes, sha256_file
from animstudio.errors import AnimstudioError


@dataclass(frozen=True)
class Job:
    """What a worker needs to render one script.

    Attributes:
        rel: the script's path relative to INPUT_DIR (``shots/a.gait``), the manifest key.
        input_path: absolute path to read the script from (workers may run in another cwd).
        display_path: the path errors are located against (``INPUT_DIR/shots/a.gait`` as the
            user spelled INPUT_DIR).
        out_dir: absolute OUT_DIR.
        settings: formats, requested fps and the weights' hash.
        weights: absolute Kohonen weights path, ``None`` for the shipped weights.
    """

    rel: str
    input_path: str
    display_path: str
    out_dir: str
    settings: BatchSettings
    weights: str | None = None


def render_job(job: Job) -> Entry:
    """Render ``job``'s script to every requested format; a ``failed`` entry on any problem.

    Outputs are written atomically one by one. If any step fails, the outputs this job already
    wrote (and stale ones from an earlier run) are removed, so OUT_DIR only ever holds complete
    outputs of scripts whose manifest entry says ``ok``.
    """
    start = time.perf_counter()
    try:
        raw = Path(job.input_path).read_bytes()
    except OSError as exc:
        _remove_outputs(job)
        return _failed(
            job, "", f"{job.display_path}: cannot read script: {exc.strerror or exc}", start
        )
    input_sha = sha256_bytes(raw)
    notes: list[str] = []
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            entry = _render(job, raw, input_sha, start)
        notes = [str(w.message) for w in caught]
    except AnimstudioError as exc:
        _remove_outputs(job)
        return _failed(job, input_sha, _located(job, str(exc)), start)
    except Exception as exc:  # a bug must not stop the other 199 scripts; it is reported as one
        _remove_outputs(job)
        message = f"internal error: {type(exc).__name__}: {exc}"
        return _failed(job, input_sha, _located(job, message), start)
    if notes:
        entry = replace(entry, notes=entry.notes + tuple(notes))
    return entry


def _render(job: Job, raw: bytes, input_sha: str, start: float) -> Entry:
    from animstudio import pipeline
    from animstudio.core.resample import resample_clip
    from animstudio.engines import EngineOptions
    from animstudio.export.formats import write_clip
    from animstudio.script.parser import decode_utf8

    options = EngineOptions(weights=Path(job.weights) if job.weights else None)
    # The bytes already read and hashed are the ones parsed (a BOM dropped, bad UTF-8 located).
    text = decode_utf8(raw, path=job.display_path)
    script = pipeline.parse_script(text, path=job.display_path, options=options)
    clip = pipeline.render(script, options=options)
    source_fps = clip.fps
    if job.settings.fps is not None:
        clip = resample_clip(clip, float(job.settings.fps))
    out_dir = Path(job.out_dir)
    outputs: dict[str, OutputRecord] = {}
    for fmt in job.settings.formats:
        rel = output_relpath(job.rel, fmt)
        target = out_dir / rel
        write_clip(target, clip)
        outputs[fmt] = OutputRecord(rel, target.stat().st_size, sha256_file(target))
    return Entry(
        input=job.rel,
        input_sha256=input_sha,
        animstudio_version=__version__,
        settings=job.settings,
        status="ok",
        engine=script.engine,
        frames=clip.num_frames,
        duration_s=clip.duration_s,
        fps=clip.fps,
        source_fps=source_fps,
        outputs=outputs,
        render_s=time.perf_counter() - start,
        worker_peak_rss_mb=peak_rss_mb(),
        worker=worker_id(),
        notes=tuple(clip.notes),
    )


def peak_rss_mb() -> float:
    """Peak resident memory of this process so far, MiB (``ru_maxrss`` is KiB on Linux)."""
    rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    return rss / (1024.0 * 1024.0) if sys.platform == "darwin" else rss / 1024.0


def worker_id() -> str:
    """``hostname:pid`` of this process: which worker rendered an entry."""
    return f"{socket.gethostname()}:{os.getpid()}"


def _located(job: Job, message: str) -> str:
    # Script errors already start with "path:line:col"; engine and export errors that do not
    # name the script get its path, so every line of the summary says which script failed.
    return message if message.startswith(job.display_path) else f"{job.display_path}: {message}"


def _remove_outputs(job: Job) -> None:
    for fmt in job.settings.formats:
        (Path(job.out_dir) / output_relpath(job.rel, fmt)).unlink(missing_ok=True)


def _failed(job: Job, input_sha: str, error: str, start: float) -> Entry:
    return Entry(
        input=job.rel,
        input_sha256=input_sha,
        animstudio_version=__version__,
        settings=job.settings,
        status="failed",
        error=error,
        render_s=time.perf_counter() - start,
        worker_peak_rss_mb=peak_rss_mb(),
        worker=worker_id(),
    )
