"""What every sub-command shares: error reporting and progress display."""

from __future__ import annotations

import functools
import logging
import sys
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import ParamSpec, TypeVar

import click

from animstudio.errors import AnimstudioError

P = ParamSpec("P")
R = TypeVar("R")


def reports_errors(func: Callable[P, R]) -> Callable[P, R]:
    """Turn project errors into ``message`` on stderr + exit 1, and Ctrl-C into exit 130."""

    @functools.wraps(func)
    def wrapper(*args: P.args, **kwargs: P.kwargs) -> R:
        try:
            return func(*args, **kwargs)
        except AnimstudioError as exc:
            click.echo(f"error: {exc}" if "\n" not in str(exc) else str(exc), err=True)
            sys.exit(1)
        except KeyboardInterrupt:
            click.echo("interrupted", err=True)
            sys.exit(130)

    return wrapper


def warn(message: str) -> None:
    """A warning the user must see (a fall, a dubious setting), on stderr."""
    click.secho(f"warning: {message}", err=True, fg="yellow")


def is_terminal() -> bool:
    return sys.stderr.isatty()


@contextmanager
def captured_warnings() -> Iterator[None]:
    """Show library ``warnings.warn`` and ``logging`` warnings as one-line messages, not tracebacks."""
    import warnings

    logging.basicConfig(level=logging.WARNING, format="%(levelname)s: %(message)s")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        yield
    for w in caught:
        warn(str(w.message))
