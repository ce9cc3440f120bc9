"""SOM training with the thesis's settings: animstudio vs MiniSom configured the same.

Both train a 40 x 40 map with 2-D inputs on the shipped training patterns (training_data/),
20,000 single-sample presentations in random order, learning rate 0.4 and neighbourhood 20
decreasing linearly, rectangular topology with a square "bubble" neighbourhood:

* animstudio: ``animstudio.som.training.train`` (numba, updates only the neighbourhood window);
  also its plain numpy statement ``train_reference`` for scale. The numba compile happens in a
  warm-up run that is not timed (it is cached on disk after the first run anyway).
* MiniSom 2.3: ``MiniSom(40, 40, 2, sigma=20, learning_rate=0.4, neighborhood_function="bubble",
  topology="rectangular", decay_function="linear_decay_to_zero",
  sigma_decay_function="linear_decay_to_one")`` and ``train(data, 20000, random_order=True)``.

Run: ``PYTHONPATH=. python benchmarks/bench_som_training.py [--repeats N]``. Prints the median
of N runs of each (same process, same machine) and the speed ratio; the target is >= 10x.
"""

from __future__ import annotations

import argparse
import statistics
import time
from collections.abc import Callable
from pathlib import Path

from minisom import MiniSom

from animstudio.gaitdata import load_training_set
from animstudio.som.training import TrainingSettings, train, train_reference

TRAINING_DATA = Path(__file__).resolve().parents[1] / "training_data"


def _median_time(func: Callable[[], object], repeats: int) -> tuple[float, list[float]]:
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        func()
        times.append(time.perf_counter() - start)
    return statistics.median(times), times


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()
    data = load_training_set(TRAINING_DATA)
    settings = TrainingSettings()

    start = time.perf_counter()
    train(data, settings)  # JIT compile (or load from the numba cache)
    warmup = time.perf_counter() - start

    def ours() -> object:
        return train(data, settings)

    def minisom() -> object:
        som = MiniSom(
            40,
            40,
            2,
            sigma=20.0,
            learning_rate=0.4,
            neighborhood_function="bubble",
            topology="rectangular",
            decay_function="linear_decay_to_zero",
            sigma_decay_function="linear_decay_to_one",
            random_seed=0,
        )
        som.train(data.inputs, settings.presentations, random_order=True)
        return som

    def reference() -> object:
        return train_reference(data, settings)

    t_ours, all_ours = _median_time(ours, args.repeats)
    t_mini, all_mini = _median_time(minisom, args.repeats)
    t_ref, _ = _median_time(reference, max(1, args.repeats // 2))
    print(
        f"SOM training: 40x40 map, 2-D input, {settings.presentations} presentations, "
        f"{data.num_patterns} patterns; median of {args.repeats} runs"
    )
    print(f"{'implementation':<34}{'median s':>10}{'min s':>10}{'max s':>10}")
    print(
        f"{'animstudio train (numba window)':<34}{t_ours:>10.4f}{min(all_ours):>10.4f}{max(all_ours):>10.4f}"
    )
    print(
        f"{'MiniSom 2.3 (bubble, linear)':<34}{t_mini:>10.4f}{min(all_mini):>10.4f}{max(all_mini):>10.4f}"
    )
    print(f"{'animstudio train_reference (numpy)':<34}{t_ref:>10.4f}")
    print(f"first call incl. numba compile/cache load: {warmup:.3f} s")
    print(f"speed-up vs MiniSom: {t_mini / t_ours:.1f}x (target >= 10x)")


if __name__ == "__main__":
    main()
