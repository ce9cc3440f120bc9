"""``animstudio check``: validate scripts without rendering them."""

from __future__ import annotations

import sys
from pathlib import Path

import click

from animstudio.cli import main
from animstudio.cli.common import warn, weights_option
from animstudio.engines import EngineOptions
from animstudio.errors import AnimstudioError, ScriptError, ScriptErrors


@main.command("check")
@click.argument("scripts", nargs=-1, required=True, type=click.Path(dir_okay=False, path_type=Path))
@click.option(
    "--simulate",
    is_flag=True,
    help="Also run the engine (without exporting) and report what happens, "
    "e.g. a walker that falls.",
)
@weights_option
def check_command(scripts: tuple[Path, ...], simulate: bool, weights: Path | None) -> None:
    """Validate scripts without rendering them.

    Prints each problem as file:line:col: message.

    Exits 0 when every script is valid (and, with --simulate, nobody falls), 1 otherwise.
    """
    from animstudio import pipeline

    options = EngineOptions(weights=weights)
    failed = False
    for path in scripts:
        try:
            script = pipeline.load_script(path, options=options)
        except ScriptErrors as exc:
            for err in exc.errors:
                click.echo(str(err), err=True)
            failed = True
            continue
        except ScriptError as exc:  # a syntax error stops parsing at the first problem
            click.echo(str(exc), err=True)
            failed = True
            continue
        except AnimstudioError as exc:
            click.echo(f"error: {exc}", err=True)
            failed = True
            continue
        summary = (
            f"{path}: ok ({len(script.segments)} segments, {script.total_frames} frames = "
            f"{script.duration_s:.2f} s at {script.fps} fps, engine {script.engine}, "
            f"{len(script.events)} event{'s' if len(script.events) != 1 else ''})"
        )
        if simulate:
            try:
                channels = pipeline.generate(script, options=options)
            except AnimstudioError as exc:
                click.echo(f"{path}: error: {exc}", err=True)
                failed = True
                continue
            for note in channels.notes:
                warn(f"{path}: {note}")
            if any(ev.kind == "fall" for ev in channels.events):
                failed = True
                continue
        click.echo(summary)
    sys.exit(1 if failed else 0)
