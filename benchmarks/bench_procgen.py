"""Time the procedural generators: ``python benchmarks/bench_procgen.py`` (a few seconds).

Plain script, not collected by pytest (testpaths is tests/). Prints the median wall time of
each case; the first call of each case is a warm-up and is not counted.
"""

from __future__ import annotations

import time
from typing import Callable

import numpy as np

from hivex_dsl.sim.procgen.terrain import generate_terrain, terrain_spec_for_level
from hivex_dsl.sim.procgen.weather import WeatherSpec, weather_at, weather_reset, weather_step


def median_ms(call: Callable[[], object], runs: int) -> float:
    """Median wall time of ``runs`` calls in milliseconds, after one warm-up call."""
    call()
    times = []
    for _ in range(runs):
        start = time.perf_counter()
        call()
        times.append(time.perf_counter() - start)
    return 1e3 * float(np.median(times))


def cases() -> list[tuple[str, str, int, Callable[[], object]]]:
    """(name, size, runs, call) of every benchmark case."""
    rng = np.random.default_rng(0)
    terrain_spec = terrain_spec_for_level(5)
    weather_spec = WeatherSpec()
    worlds, points_per_world = 256, 9
    state = weather_reset(rng, worlds, weather_spec)
    points = rng.uniform(-750.0, 750.0, (worlds, points_per_world, 2))
    wind = rng.uniform(-np.pi, np.pi, worlds)
    return [
        ("generate_terrain (level 5)", f"{terrain_spec.size}x{terrain_spec.size}", 20,
         lambda: generate_terrain(rng, terrain_spec)),
        ("weather_at", f"B={worlds} x {points_per_world} pts", 50, lambda: weather_at(state, points, weather_spec)),
        ("weather_step", f"B={worlds}", 50, lambda: weather_step(state, wind, weather_spec)),
        ("weather_reset", f"B={worlds}", 20, lambda: weather_reset(rng, worlds, weather_spec)),
    ]


def main() -> None:
    rows = [(name, size, runs, median_ms(call, runs)) for name, size, runs, call in cases()]
    print(f"{'case':<28} {'size':<18} {'runs':>4} {'median ms':>10}")
    for name, size, runs, ms in rows:
        print(f"{name:<28} {size:<18} {runs:>4} {ms:>10.3f}")


if __name__ == "__main__":
    main()
