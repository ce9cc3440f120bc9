"""``animstudio preview``: watch a script (or an exported USD file) in the browser."""

from __future__ import annotations

import ipaddress
import signal
import socket
import threading
from pathlib import Path
from types import FrameType

import click

from animstudio.cli import main
from animstudio.cli.common import reports_errors, warn, weights_option
from animstudio.engines import EngineOptions


def is_loopback(host: str) -> bool:
    """True when ``host`` only accepts connections from this machine (``localhost``, 127.x, ::1)."""
    if host == "localhost":
        return True
    try:
        return ipaddress.ip_address(host).is_loopback
    except ValueError:
        try:
            return all(
                ipaddress.ip_address(info[4][0]).is_loopback
                for info in socket.getaddrinfo(host, None)
            )
        except (OSError, ValueError):
            return False


@main.command("preview")
@click.argument("source", type=click.Path(dir_okay=False, path_type=Path))
@click.option("--host", default="127.0.0.1", show_default=True, help="Interface to listen on.")
@click.option("--port", default=8080, show_default=True, type=click.IntRange(1, 65535))
@weights_option
@reports_errors
def preview_command(source: Path, host: str, port: int, weights: Path | None) -> None:
    """Preview SOURCE (a .gait script, or an exported .usda/.usdc/.usd) in the browser.

    The script is re-rendered whenever it is saved; the page updates without reloading and
    keeps the current frame. A script error is shown in the page and the last good clip stays.
    Stop with Ctrl-C.

    \b
    Examples:
      animstudio preview scripts_gait/demo.gait            # then open http://127.0.0.1:8080
      animstudio preview exports/demo.usdc --port 8090
    """
    from animstudio.preview import PreviewApp
    from animstudio.preview.source import check_source

    check_source(source)
    if not is_loopback(host):
        warn(
            f"listening on {host}: anyone who can reach this machine on port {port} can view "
            "the preview and its file path (use the default 127.0.0.1 to keep it private)"
        )
    stop = threading.Event()

    def _on_signal(signum: int, frame: FrameType | None) -> None:
        stop.set()

    previous = {s: signal.signal(s, _on_signal) for s in (signal.SIGINT, signal.SIGTERM)}
    app = None
    try:
        app = PreviewApp(source, host=host, port=port, options=EngineOptions(weights=weights))
        if app.server.get_port() != port:
            warn(f"port {port} is taken; using {app.server.get_port()}")
        if app.error is not None:
            warn(f"the script does not render yet; fix it and save:\n{app.error}")
        click.echo(f"previewing {source} at {app.url}  (Ctrl-C to stop)")
        while not stop.wait(0.5):
            pass
    finally:
        if app is not None:
            app.stop()
        for s, handler in previous.items():
            signal.signal(s, handler)
    click.echo("preview stopped")
