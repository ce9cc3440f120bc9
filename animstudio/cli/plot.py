"""``animstudio plot``: the papers' figures for a script."""

from __future__ import annotations

from pathlib import Path

import click

from animstudio.cli import main
from animstudio.cli.common import reports_errors
from animstudio.engines import EngineOptions


@main.command("plot")
@click.argument("script", type=click.Path(dir_okay=False, path_type=Path))
@click.option(
    "--kind",
    required=True,
    help="Figure to draw. cpg: stick, neurons, torque. obb: neurons, footfall.",
)
@click.option(
    "-o",
    "--output",
    required=True,
    type=click.Path(dir_okay=False, path_type=Path),
    help="PNG file to write.",
)
@reports_errors
def plot_command(script: Path, kind: str, output: Path) -> None:
    """Simulate SCRIPT and draw one of its engine's figures to a PNG."""
    from animstudio import pipeline, plots

    options = EngineOptions()
    parsed = pipeline.load_script(script, options=options)
    plots.plot(parsed, kind, output, options=options)
    click.echo(f"wrote {output}")
