"""``animstudio render``: one script to one animation file."""

from __future__ import annotations

from pathlib import Path

import click

from animstudio.cli import main
from animstudio.cli.common import reports_errors, stages, warn, weights_option
from animstudio.engines import EngineOptions
from animstudio.export.formats import FORMATS, writer_for

DEFAULT_EXPORT_DIR = Path("exports")


@main.command("render")
@click.argument("script", type=click.Path(dir_okay=False, path_type=Path))
@click.option(
    "-o",
    "--output",
    type=click.Path(dir_okay=False, path_type=Path),
    default=None,
    help=f"Output file; its extension picks the format ({', '.join(FORMATS)}). "
    "Default: exports/<script name>.usda.",
)
@weights_option
@reports_errors
def render_command(script: Path, output: Path | None, weights: Path | None) -> None:
    """Render SCRIPT (a .gait file) to an animation file.

    \b
    Examples:
      animstudio render scripts_gait/demo.gait                 # -> exports/demo.usda
      animstudio render walk.gait -o shot010/walk.usdc
    """
    from animstudio import pipeline

    out = output if output is not None else DEFAULT_EXPORT_DIR / f"{script.stem}.usda"
    write = writer_for(out)  # an unknown extension fails before any work is done
    options = EngineOptions(weights=weights)
    with stages(["parse", "simulate", "pose", "export"]) as step:
        parsed = pipeline.load_script(script, options=options)
        step()
        channels = pipeline.generate(parsed, options=options)
        step()
        from animstudio.rig import clip_from_channels

        clip = clip_from_channels(channels)
        step()
        write(out, clip)
        step()
    for note in clip.notes:
        warn(note)
    click.echo(
        f"wrote {out} ({clip.num_frames} frames, {clip.duration_s:.2f} s at {clip.fps:g} fps, "
        f"{len(clip.segments)} segments, engine {parsed.engine})"
    )
