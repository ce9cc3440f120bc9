"""What every sub-command shares: error reporting and progress display."""

from __future__ import annotations

import functools
import sys
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import ParamSpec, TypeVar

import click

from animstudio.errors import AnimstudioError, ScriptError, ScriptErrors

P = ParamSpec("P")
R = TypeVar("R")


def reports_errors(func: Callable[P, R]) -> Callable[P, R]:
    """Turn project errors into ``message`` on stderr + exit 1, and Ctrl-C into exit 130."""

    @functools.wraps(func)
    def wrapper(*args: P.args, **kwargs: P.kwargs) -> R:
        try:
            return func(*args, **kwargs)
        except (ScriptError, ScriptErrors) as exc:
            click.echo(str(exc), err=True)  # already "file:line:col: message", one per line
            sys.exit(1)
        except AnimstudioError as exc:
            click.echo(f"error: {exc}", err=True)
            sys.exit(1)
        except KeyboardInterrupt:
            click.echo("interrupted", err=True)
            sys.exit(130)

    return wrapper


weights_option = click.option(
    "--weights",
    type=click.Path(dir_okay=False, path_type=Path),
    default=None,
    help="Kohonen weights file from 'animstudio train' (default: the shipped weights).",
)
"""The ``--weights`` option of every command that runs the Kohonen engine."""


def warn(message: str) -> None:
    """A warning the user must see (a fall, a dubious setting), on stderr."""
    click.secho(f"warning: {message}", err=True, fg="yellow")


def is_terminal() -> bool:
    return sys.stderr.isatty()


@contextmanager
def stages(names: list[str]) -> Iterator[Callable[[], None]]:
    """A progress bar over named stages on a terminal; silent when stderr is piped.

    Yields ``advance()``, to be called once as each stage completes.
    """
    from tqdm import tqdm

    with tqdm(total=len(names), disable=not is_terminal(), leave=False, unit="stage") as bar:
        bar.set_description(names[0])

        def advance() -> None:
            bar.update(1)
            if bar.n < len(names):
                bar.set_description(names[bar.n])

        yield advance
