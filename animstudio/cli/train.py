"""``animstudio train``: train a Kohonen map from a training-data directory."""

from __future__ import annotations

import re
from pathlib import Path

import click

from animstudio.cli import main
from animstudio.cli.common import is_terminal, reports_errors, warn
from animstudio.errors import DataError


def _map_size(value: str) -> tuple[int, int]:
    m = re.fullmatch(r"\s*(\d+)\s*[xX]\s*(\d+)\s*", value)
    if not m or int(m.group(1)) < 1 or int(m.group(2)) < 1:
        raise click.BadParameter(f"expected ROWSxCOLS such as 40x40, got {value!r}")
    return int(m.group(1)), int(m.group(2))


@main.command("train")
@click.argument("data_dir", type=click.Path(file_okay=False, path_type=Path))
@click.option(
    "-o",
    "--output",
    type=click.Path(dir_okay=False, path_type=Path),
    required=True,
    help="Weights file to write (.npz), e.g. W.npz.",
)
@click.option(
    "--seed",
    type=click.IntRange(min=0),
    default=None,
    help="Seed for the initial weights and presentation order (default: the shipped weights' seed).",
)
@click.option(
    "--presentations",
    type=click.IntRange(min=1),
    default=20_000,
    show_default=True,
    help="Pattern presentations (the thesis: 20,000).",
)
@click.option(
    "--map-size",
    default="40x40",
    show_default=True,
    help="Competitive layer ROWSxCOLS (the thesis: 40x40).",
)
@reports_errors
def train_command(
    data_dir: Path, output: Path, seed: int | None, presentations: int, map_size: str
) -> None:
    """Train a Kohonen map on the gait cycles in DATA_DIR and write its weights.

    Learning rate 0.4 and neighbourhood 20 decrease linearly over the presentations, as in the
    thesis. The same data and seed always give a byte-identical file.

    \b
    Example (reproduces the shipped weights):
      animstudio train training_data -o W.npz
    """
    from tqdm import tqdm

    from animstudio.gaitdata import load_training_set
    from animstudio.som.training import TrainingSettings, unreproduced_patterns
    from animstudio.som.weights import DEFAULT_SEED, save_weights, train_weights

    if output.suffix != ".npz":
        raise DataError(f"{output}: the weights file must end in .npz")
    try:
        shape = _map_size(map_size)
    except click.BadParameter as exc:
        raise click.UsageError(str(exc)) from None
    data = load_training_set(data_dir)
    settings = TrainingSettings(
        map_shape=shape,
        presentations=presentations,
        seed=DEFAULT_SEED if seed is None else seed,
    )
    with tqdm(total=presentations, disable=not is_terminal(), leave=False, unit="pattern") as bar:
        weights = train_weights(data, settings, progress=bar.update)
    save_weights(output, weights)
    bad = unreproduced_patterns(weights.trained, data)
    if bad.size:
        frames = ", ".join(
            f"{data.gait_names[data.gait_index[p]]} frame "
            f"{p - int(data.cycle_frames[: data.gait_index[p]].sum())}"
            for p in bad
        )
        warn(
            f"{bad.size} training pattern(s) share their winning unit with another and will not "
            f"replay exactly ({frames}); another --seed usually separates them"
        )
    won = int(weights.trained.won.sum())
    click.echo(
        f"wrote {output} ({shape[0]}x{shape[1]} map, {presentations} presentations, "
        f"seed {settings.seed}; {data.num_patterns} patterns of {', '.join(data.gait_names)}; "
        f"{won} units won)"
    )
