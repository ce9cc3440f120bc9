"""``animstudio batch``: every script under a directory to USD/BVH/CSV, in parallel, resumable."""

from __future__ import annotations

import os
import sys
from pathlib import Path

import click

from animstudio.cli import main
from animstudio.cli.common import is_terminal, reports_errors, warn, weights_option
from animstudio.errors import lookup
from animstudio.export.formats import FORMATS

FPS_CHOICES = ("24", "25", "30", "60")


def _parse_formats(value: str) -> tuple[str, ...]:
    names = [v.strip().lower().lstrip(".") for v in value.split(",") if v.strip()]
    if not names:
        raise click.BadParameter("give at least one format, e.g. usdc,bvh")
    return tuple(dict.fromkeys(lookup("format", n, FORMATS) for n in names))


@main.command("batch")
@click.argument("input_dir", type=click.Path(file_okay=False, path_type=Path))
@click.option(
    "-o",
    "--output",
    "out_dir",
    required=True,
    type=click.Path(file_okay=False, path_type=Path),
    help="Output directory (created); relative script paths are kept below it.",
)
@click.option(
    "--format",
    "formats",
    default="usdc",
    show_default=True,
    help=f"Comma-separated output formats: {', '.join(FORMATS)}.",
)
@click.option(
    "--fps",
    type=click.Choice(FPS_CHOICES),
    default=None,
    help="Resample every clip to this frame rate (default: each script's own).",
)
@click.option(
    "-j",
    "--jobs",
    type=click.IntRange(min=1),
    default=None,
    help="Worker processes (default: the number of CPUs). Ignored with --scheduler.",
)
@click.option("--force", is_flag=True, help="Re-render everything, even what is up to date.")
@click.option(
    "--scheduler",
    default=None,
    metavar="tcp://HOST:PORT",
    help="Run the jobs on this Dask distributed scheduler (shared file system needed).",
)
@weights_option
@reports_errors
def batch_command(
    input_dir: Path,
    out_dir: Path,
    formats: str,
    fps: str | None,
    jobs: int | None,
    force: bool,
    scheduler: str | None,
    weights: Path | None,
) -> None:
    """Render every *.gait under INPUT_DIR (recursively) into OUT_DIR.

    \b
    OUT_DIR/manifest.json records each script's hash, settings and outputs; a re-run skips
    what is up to date and completes what is missing (also after a crash or kill).
    Exit status 1 if any script failed.
    \b
    Examples:
      animstudio batch shots/ -o renders/ --format usdc,bvh --fps 24 -j 2
      animstudio batch shots/ -o renders/ --scheduler tcp://10.0.0.5:8786
    """
    from tqdm import tqdm

    from animstudio.batch import Entry, run_batch

    format_list = _parse_formats(formats)
    bar: list[tqdm] = []

    def on_start(total: int) -> None:
        bar.append(
            tqdm(
                total=total, unit="script", file=sys.stderr, disable=not is_terminal(), leave=False
            )
        )

    def on_entry(entry: Entry, outcome: str) -> None:
        if bar:
            bar[0].update(1)
            if outcome == "failed":
                bar[0].set_postfix_str(f"{entry.input} failed", refresh=False)

    try:
        report = run_batch(
            input_dir,
            out_dir,
            formats=format_list,
            fps=int(fps) if fps else None,
            jobs=jobs,
            force=force,
            scheduler=scheduler,
            weights=weights,
            on_start=on_start,
            on_entry=on_entry,
        )
    finally:
        if bar:
            bar[0].close()

    _print_summary(report, out_dir)
    if report.failed:
        sys.exit(1)


def _print_summary(report: object, out_dir: Path) -> None:
    from animstudio.batch import BatchReport

    assert isinstance(report, BatchReport)
    rows = [("script", "status", "engine", "frames", "fps", "seconds", "outputs")]
    for entry, outcome in zip(report.entries, report.outcomes, strict=True):
        status = {"rendered": "ok", "skipped": "skipped", "failed": "FAILED"}[outcome]
        rows.append(
            (
                entry.input,
                status,
                entry.engine or "-",
                "-" if entry.frames is None else str(entry.frames),
                "-" if entry.fps is None else f"{entry.fps:g}",
                "-" if outcome == "skipped" else f"{entry.render_s:.2f}",
                ",".join(entry.outputs) or "-",
            )
        )
    widths = [max(len(r[i]) for r in rows) for i in range(len(rows[0]))]
    for k, row in enumerate(rows):
        line = "  ".join(cell.ljust(w) for cell, w in zip(row, widths, strict=True)).rstrip()
        if k == 0:
            click.secho(line, bold=True)
        elif row[1] == "FAILED":
            click.secho(line, fg="red")
        else:
            click.echo(line)
    click.echo(
        f"\n{len(report.entries)} scripts: {report.count('rendered')} rendered, "
        f"{report.count('skipped')} up to date, {report.count('failed')} failed "
        f"in {report.wall_s:.1f} s -> {out_dir}{os.sep}manifest.json"
    )
    if report.removed_temporaries:
        click.echo(
            f"removed {report.removed_temporaries} leftover temporary file(s) of an interrupted run"
        )
    for entry in report.entries:
        for note in entry.notes:
            warn(f"{entry.input}: {note}")
    if report.failed:
        click.echo("\nerrors:", err=True)
        for entry in report.failed:
            click.echo(entry.error or f"{entry.input}: failed", err=True)
