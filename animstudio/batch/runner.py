"""Run a batch: skip what is up to date, render the rest in parallel, keep the manifest current.

Two executors run the same :func:`animstudio.batch.worker.render_job`:

- local: ``concurrent.futures.ProcessPoolExecutor`` with the ``spawn`` start method (no state
  forked from the caller, same behaviour on every platform), ``jobs`` worker processes;
- Dask: ``distributed.Client(scheduler)`` and one ``client.submit`` per script. The workers must
  see INPUT_DIR and OUT_DIR at the same absolute paths (a shared file system).

The library never prints: progress goes to the ``on_entry`` callback.
"""

from __future__ import annotations

import fcntl
import multiprocessing
import os
import secrets
import time
from collections.abc import Callable, Iterator
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait
from concurrent.futures.process import BrokenProcessPool
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Literal

from animstudio import __version__
from animstudio.batch.discovery import find_scripts, remove_temporaries
from animstudio.batch.manifest import (
    BatchSettings,
    Entry,
    ManifestWriter,
    is_up_to_date,
    load_manifest,
    sha256_bytes,
    sha256_file,
)
from animstudio.batch.worker import Job, render_job
from animstudio.errors import DataError, ExportError, lookup
from animstudio.export.formats import FORMATS

Outcome = Literal["rendered", "failed", "skipped"]
LOCK_NAME = ".animstudio-batch.lock"


@dataclass(frozen=True)
class BatchReport:
    """What a batch did.

    Attributes:
        entries: the manifest entry of every input, in input order.
        outcomes: per input, ``rendered``, ``failed`` or ``skipped`` (up to date).
        removed_temporaries: leftovers of a killed run deleted at the start.
        wall_s: wall-clock time of the whole run.
    """

    entries: tuple[Entry, ...]
    outcomes: tuple[Outcome, ...]
    removed_temporaries: int
    wall_s: float

    @property
    def failed(self) -> tuple[Entry, ...]:
        return tuple(e for e in self.entries if e.status == "failed")

    def count(self, outcome: Outcome) -> int:
        return sum(1 for o in self.outcomes if o == outcome)


def run_batch(
    input_dir: Path,
    out_dir: Path,
    *,
    formats: tuple[str, ...] = ("usdc",),
    fps: int | None = None,
    jobs: int | None = None,
    force: bool = False,
    scheduler: str | None = None,
    weights: Path | None = None,
    on_start: Callable[[int], None] | None = None,
    on_entry: Callable[[Entry, Outcome], None] | None = None,
) -> BatchReport:
    """Render every ``*.gait`` under ``input_dir`` into ``out_dir`` (see docs/batch.md).

    Args:
        input_dir: searched recursively; relative paths are kept under ``out_dir``.
        out_dir: created if missing; holds the outputs and ``manifest.json``.
        formats: output formats by extension (``usdc``, ``usda``, ``bvh``, ``csv``).
        fps: resample every clip to this rate; ``None`` keeps each script's own.
        jobs: local worker processes (default: the CPU count); ignored with ``scheduler``.
        force: render everything even if the manifest says it is up to date.
        scheduler: a Dask scheduler address (``tcp://host:port``) to run the jobs on instead.
        weights: Kohonen weights file for every script (``None``: the shipped weights).
        on_start: called once with the number of inputs.
        on_entry: called as each input is settled (skipped at once, others as they finish).

    Raises:
        UnknownName: a format that is not one of :data:`animstudio.export.formats.FORMATS`.
        DataError: no input directory / scripts, a missing weights file, a corrupt manifest.
        ExportError: OUT_DIR cannot be created or another batch is writing to it; the Dask
            scheduler cannot be reached.
    """
    started = time.perf_counter()
    input_dir = Path(input_dir)
    out_abs = Path(out_dir).resolve()
    scripts = find_scripts(input_dir)
    weights_abs: str | None = None
    weights_sha: str | None = None
    if weights is not None:
        if not Path(weights).is_file():
            raise DataError(f"{weights}: weights file not found")
        weights_abs = str(Path(weights).resolve())
        weights_sha = sha256_file(Path(weights))
    if not formats:
        raise ValueError("formats must name at least one output format")
    known = tuple(dict.fromkeys(lookup("format", f, FORMATS) for f in formats))
    settings = BatchSettings(known, fps, weights_sha)
    if jobs is not None and jobs < 1:
        raise ValueError(f"jobs must be >= 1, got {jobs}")
    if fps is not None and fps <= 0:
        raise ValueError(f"fps must be positive, got {fps}")

    with _exclusive(out_abs):
        removed = remove_temporaries(out_abs)
        old = {} if force else load_manifest(out_abs)
        entries: dict[str, Entry] = {}
        outcomes: dict[str, Outcome] = {}
        todo: list[Job] = []
        if on_start:
            on_start(len(scripts))
        for rel in scripts:
            src = input_dir / rel
            try:
                sha = sha256_bytes(src.read_bytes())
            except OSError:
                sha = ""  # the worker reports the located read error
            prev = old.get(rel)
            if not force and is_up_to_date(
                prev, input_sha256=sha, settings=settings, version=__version__, out_dir=out_abs
            ):
                assert prev is not None
                entries[rel] = prev
                outcomes[rel] = "skipped"
                if on_entry:
                    on_entry(prev, "skipped")
            else:
                todo.append(
                    Job(rel, str(src.resolve()), str(src), str(out_abs), settings, weights_abs)
                )
        # Entries of scripts no longer in INPUT_DIR are dropped; entries being re-rendered keep
        # their old record until the new one arrives (their outputs are still valid or absent).
        for job in todo:
            if job.rel in old:
                entries[job.rel] = old[job.rel]
        manifest = ManifestWriter(out_abs)
        for entry in entries.values():
            manifest.put(entry)
        manifest.save()

        def settle(entry: Entry) -> None:
            entries[entry.input] = entry
            outcomes[entry.input] = "rendered" if entry.status == "ok" else "failed"
            manifest.put(entry)
            manifest.save()  # after every job: a kill loses only in-flight work
            if on_entry:
                on_entry(entry, outcomes[entry.input])

        if todo:
            if scheduler is not None:
                _run_dask(todo, scheduler, settle)
            else:
                _run_local(todo, jobs or os.cpu_count() or 1, settle)

    return BatchReport(
        entries=tuple(entries[rel] for rel in scripts),
        outcomes=tuple(outcomes[rel] for rel in scripts),
        removed_temporaries=len(removed),
        wall_s=time.perf_counter() - started,
    )


def _run_local(todo: list[Job], workers: int, settle: Callable[[Entry], None]) -> None:
    # A bounded window of submitted jobs: a crashed worker (segfault, OOM kill) breaks the pool;
    # only the jobs in flight are then reported failed and a fresh pool takes the rest.
    pending = list(reversed(todo))
    context = multiprocessing.get_context("spawn")
    with _worker_threads(max(1, (os.cpu_count() or 1) // workers)):
        _pool_loop(pending, workers, context, settle)


def _pool_loop(
    pending: list[Job],
    workers: int,
    context: multiprocessing.context.BaseContext,
    settle: Callable[[Entry], None],
) -> None:
    while pending:
        with ProcessPoolExecutor(
            max_workers=min(workers, len(pending)), mp_context=context
        ) as pool:
            in_flight: dict[Future[Entry], Job] = {}
            broken = False
            while (pending or in_flight) and not broken:
                while pending and len(in_flight) < 2 * workers:
                    job = pending.pop()
                    in_flight[pool.submit(render_job, job)] = job
                done, _ = wait(in_flight, return_when=FIRST_COMPLETED)
                for fut in done:
                    job = in_flight.pop(fut)
                    try:
                        settle(fut.result())
                    except BrokenProcessPool:
                        broken = True
                        settle(_crashed(job, "its worker process died (crash or out of memory)"))
            if broken:
                for job in in_flight.values():
                    settle(_crashed(job, "its worker process died while another job crashed"))


def _run_dask(todo: list[Job], scheduler: str, settle: Callable[[Entry], None]) -> None:
    try:
        from distributed import Client, as_completed
    except ImportError as exc:
        raise ExportError(
            "--scheduler needs dask.distributed: pip install 'dask[distributed]'"
        ) from exc
    try:
        client = Client(scheduler, timeout="10s")
    except (OSError, TimeoutError, ValueError) as exc:
        raise ExportError(f"cannot connect to the Dask scheduler at {scheduler}: {exc}") from exc
    try:
        # Keys unique per run: a later batch from this process must run again, not reuse results.
        run = secrets.token_hex(4)
        futures = {
            client.submit(render_job, job, pure=False, key=f"animstudio-batch-{run}-{job.rel}"): job
            for job in todo
        }
        for fut in as_completed(futures):
            job = futures[fut]
            try:
                settle(fut.result())
            except (
                Exception
            ) as exc:  # KilledWorker, lost connection: this job failed, not the batch
                settle(_crashed(job, f"the Dask worker failed: {type(exc).__name__}: {exc}"))
    finally:
        client.close()


def _crashed(job: Job, why: str) -> Entry:
    return Entry(
        input=job.rel,
        input_sha256="",
        animstudio_version=__version__,
        settings=job.settings,
        status="failed",
        error=f"{job.display_path}: not rendered: {why}",
    )


_THREAD_VARIABLES = (
    "OMP_NUM_THREADS",
    "OPENBLAS_NUM_THREADS",
    "MKL_NUM_THREADS",
    "NUMBA_NUM_THREADS",
)


@contextmanager
def _worker_threads(threads: int) -> Iterator[None]:
    # Parallelism comes from the processes: N workers each running BLAS / numba thread pools
    # sized to every core oversubscribe the machine (measured: 2 workers on 2 cores ran at 0.4x
    # one worker's throughput). Spawned workers read these variables when numpy and numba
    # load, so they are set for the pool's lifetime; values the user set are kept.
    saved = {name: os.environ.get(name) for name in _THREAD_VARIABLES}
    for name, value in saved.items():
        if value is None:
            os.environ[name] = str(threads)
    try:
        yield
    finally:
        for name, value in saved.items():
            if value is None:
                os.environ.pop(name, None)


@contextmanager
def _exclusive(out_dir: Path) -> Iterator[None]:
    # Two batches writing one OUT_DIR would race on the manifest and delete each other's
    # temporaries. flock is released by the kernel when the holder dies, even by SIGKILL.
    try:
        out_dir.mkdir(parents=True, exist_ok=True)
        fd = os.open(out_dir / LOCK_NAME, os.O_RDWR | os.O_CREAT, 0o644)
    except OSError as exc:
        raise ExportError(
            f"{out_dir}: cannot create output directory: {exc.strerror or exc}"
        ) from exc
    try:
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            raise ExportError(
                f"{out_dir}: another animstudio batch is writing to this directory"
            ) from None
        yield
    finally:
        os.close(fd)
