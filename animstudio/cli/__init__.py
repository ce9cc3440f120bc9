"""The ``animstudio`` command line: a thin shell over the library.

Each sub-command lives in its own module here; this is the only layer that prints, maps
:class:`~animstudio.errors.AnimstudioError` to exit status 1 with the message on stderr, and
never shows a traceback for a user mistake.
"""

from __future__ import annotations

import click

from animstudio import __version__


@click.group(context_settings={"help_option_names": ["-h", "--help"], "max_content_width": 100})
@click.version_option(__version__, prog_name="animstudio")
def main() -> None:
    """Turn gait scripts into 30 fps joint curves and USD skeletal animation.

    \b
    A script is a list of gaits and durations, e.g.  walk 60 / run 2s / climb 45
    (frames at the script's fps, or seconds with an 's').  Start with:
      animstudio render scripts_gait/demo.gait -o exports/demo.usda
    See docs/script-language.md for the language.
    """


def _register() -> None:
    # Sub-commands register themselves on import; one module per command keeps each small.
    from animstudio.cli import check, render, train  # noqa: F401

    for optional in ("plot", "batch", "preview"):
        try:
            __import__(f"animstudio.cli.{optional}")
        except ModuleNotFoundError as exc:
            if exc.name != f"animstudio.cli.{optional}":
                raise


_register()
