"""Time the fire engine: ``python benchmarks/bench_fire.py`` (about a minute).

Plain script, not collected by pytest. Prints the median wall time of each case in milliseconds.
The engine writes the tree grid in place, so every timed call starts from a fresh copy of a
prepared state (the copy is not timed).

A "steady" case times the step after one untimed step, when the engine knows which burning trees
have nothing left to ignite (``FireState.spent``), as in a running simulation; "grid" passes the
weather as a ``FactorGrid``, as Wildfire Resource Management does.

Fronts are built, not grown, on a 400 x 400 forest of about 60 % density: a ring front burns the
trees of a band around a world's fire centre (random ages), with burnt trees inside and existing
ones outside, the shape of a fire that spread outwards; a scattered front burns random trees
amid existing ones, the most pairs to try for its size. The weather is the nearest cell of a
coarse per-world grid (as a simulator would sample it), the heights a tilted plane plus bumps.
"""

from __future__ import annotations

import time
from typing import Callable

import numpy as np

from hivex_dsl.sim.fire import (
    FactorGrid, FireSpec, FireState, TreeState, burning_count, closest_burning, count_factors, douse, fire_copy,
    fire_step, grid_cell_table,
)

CELLS = 400
DENSITY = 0.6


def median_ms(prepare: Callable[[], object], call: Callable[[object], object], runs: int) -> float:
    """Median wall time of ``call(prepare())`` over ``runs`` runs (after one warm-up), preparing untimed."""
    call(prepare())
    times = []
    for _ in range(runs):
        argument = prepare()
        start = time.perf_counter()
        call(argument)
        times.append(time.perf_counter() - start)
    return 1e3 * float(np.median(times))


def forest(rng: np.random.Generator, batch: int) -> np.ndarray:
    """(B, C, C) uint8 trees: EXISTING in about DENSITY of the cells."""
    return np.where(rng.random((batch, CELLS, CELLS)) < DENSITY, TreeState.EXISTING, TreeState.NONE).astype(np.uint8)


def as_state(rng: np.random.Generator, trees: np.ndarray, burn_steps: int) -> FireState:
    """A fire state over ``trees`` (B, C, C) with random ages."""
    batch = trees.shape[0]
    burning = np.flatnonzero(trees == TreeState.BURNING).astype(np.int64)
    zeros = np.zeros(batch, np.int64)
    return FireState(trees=trees, burning=burning, age=rng.integers(0, burn_steps, len(burning)).astype(np.int32),
                     quiet=np.zeros(batch, np.int32), out=np.zeros(batch, bool), ignited=zeros, burnt_out=zeros)


def ring_fire(rng: np.random.Generator, batch: int, radius: float | np.ndarray, width: float | np.ndarray,
              burn_steps: int) -> FireState:
    """``batch`` worlds whose trees burn in a ring band [radius - width, radius) around a random centre.

    radius and width are one number or one per world (B,).
    """
    trees = forest(rng, batch)
    radius = np.broadcast_to(np.asarray(radius, dtype=np.float64), (batch,))[:, None, None]
    width = np.broadcast_to(np.asarray(width, dtype=np.float64), (batch,))[:, None, None]
    centre = rng.uniform(radius[..., None] + 10, CELLS - radius[..., None] - 10, (batch, 1, 1, 2))
    grid = np.stack(np.meshgrid(np.arange(CELLS), np.arange(CELLS), indexing="ij"), axis=-1)
    distance = np.sqrt(((grid[None] - centre) ** 2).sum(axis=-1))
    has_tree = trees == TreeState.EXISTING
    trees[has_tree & (distance < radius - width)] = TreeState.BURNT
    trees[has_tree & (distance >= radius - width) & (distance < radius)] = TreeState.BURNING
    return as_state(rng, trees, burn_steps)


def scattered_fire(rng: np.random.Generator, batch: int, count: int, burn_steps: int) -> FireState:
    """The worst front for its size: ``count`` trees per world burn at random places, amid existing trees."""
    trees = forest(rng, batch)
    for world in trees:
        flat = world.reshape(-1)
        flat[rng.choice(np.flatnonzero(flat == TreeState.EXISTING), count, replace=False)] = TreeState.BURNING
    return as_state(rng, trees, burn_steps)


def weather_lookup(rng: np.random.Generator, batch: int, grid: int = 16):
    """A ``conditions`` callable reading the nearest cell of a coarse (B, G, G) weather grid per field.

    Like a simulator that samples its smooth weather fields on a few cells per side of the island.
    """
    fields = rng.random((3, batch, grid, grid)).astype(np.float32)
    lookup = (np.arange(CELLS) * grid) // CELLS
    return lambda world, row, col: tuple(f[world, lookup[row], lookup[col]] for f in fields)


def heights(rng: np.random.Generator, batch: int) -> np.ndarray:
    """(B, C, C) float32: a random tilted plane plus small bumps per world."""
    tilt = rng.normal(0.0, 0.2, (batch, 2, 1, 1))
    grid = np.arange(CELLS, dtype=np.float32)
    plane = tilt[:, 0] * grid[:, None] + tilt[:, 1] * grid[None, :]
    return (plane + rng.random((batch, CELLS, CELLS))).astype(np.float32)


def step_case(rng: np.random.Generator, name: str, base: FireState, runs: int, steady: bool = False,
              grid: bool = False) -> tuple[str, str, int, float]:
    """fire_step on copies of ``base``; ``steady``: after one untimed step, so the spent trees are known
    (as in a running simulation); ``grid``: the weather as a FactorGrid (as WRM passes it) instead of a callable."""
    spec, batch = FireSpec(), base.batch
    wind = rng.uniform(-np.pi, np.pi, batch)
    conditions, height = weather_lookup(rng, batch), heights(rng, batch)
    if grid:
        conditions = factor_grid(rng, batch, spec)
    if steady:
        base = fire_step(fire_copy(base), rng, spec, wind, height, conditions)
    size = f"B={batch}, ~{int(burning_count(base).mean())} burning/world"
    ms = median_ms(lambda: fire_copy(base), lambda s: fire_step(s, rng, spec, wind, height, conditions), runs)
    return name, size, runs, ms


def factor_grid(rng: np.random.Generator, batch: int, spec: FireSpec, grid: int = 16) -> FactorGrid:
    """The weather of :func:`weather_lookup` as a FactorGrid: factors counted once per grid cell."""
    values = rng.random((batch, grid, grid, 3)).astype(np.float32)
    return FactorGrid(count_factors(values, spec), grid_cell_table((np.arange(CELLS) * grid) // CELLS, grid))


def water_cases(rng: np.random.Generator, batch: int, agents: int, runs: int) -> list[tuple[str, str, int, float]]:
    """douse with every plane (or 1 % of them) dropping a 4-point swath of radius 10 cells, and closest_burning."""
    base = ring_fire(rng, batch, 19.0, 3.0, 10)
    owners = batch * agents
    plane = rng.uniform(0, CELLS, (owners, 2))
    heading = rng.uniform(-np.pi, np.pi, owners)
    ahead = np.arange(4) * (20.0 / 3.0)  # swath points 0, 20, 40, 60 m ahead on a 3 m grid
    rows = (plane[:, 0:1] + ahead * np.sin(heading)[:, None]).ravel()
    cols = (plane[:, 1:2] + ahead * np.cos(heading)[:, None]).ravel()
    owner = np.repeat(np.arange(owners), 4)
    few = owner < max(1, owners // 100)  # planes 0..7 only (planes must fetch water between drops)
    size = f"B={batch} x {agents} planes"
    cases = []
    for label, pick in (("douse (every plane drops)", slice(None)), ("douse (1 % of planes drop)", few)):
        args = (owner[pick] // agents, rows[pick], cols[pick], 10.0, owner[pick], owners)
        cases.append((label, size, runs, median_ms(lambda: fire_copy(base), lambda s: douse(s, *args), runs)))
    one = np.arange(owners) // agents
    near_ms = median_ms(lambda: base, lambda s: closest_burning(s, one, plane[:, 0], plane[:, 1], 50.0), runs)
    return cases + [("closest_burning (50 cells)", f"{size}, ~{int(burning_count(base).mean())} burning/world", runs,
                     near_ms)]


def search_cases(rng: np.random.Generator, runs: int) -> list[tuple[str, str, int, float]]:
    """closest_burning with 50-cell half boxes on large fronts, as Aerial Wildfire Suppression asks it each step.

    256 worlds whose rings of radius 100-140 cells and width 6-10 cells (2,000 to 5,000 burning trees)
    span most of the island, queried by 3 planes and the village of each world; and one world with 5,000
    scattered burning trees and 4 queries.
    """
    batch = 256
    base = ring_fire(rng, batch, rng.uniform(100.0, 140.0, batch), rng.uniform(6.0, 10.0, batch), 10)
    world = np.concatenate([np.repeat(np.arange(batch), 3), np.arange(batch)])
    point = rng.uniform(0, CELLS, (len(world), 2))
    counts = burning_count(base)
    ring_ms = median_ms(lambda: base, lambda s: closest_burning(s, world, point[:, 0], point[:, 1], 50.0), runs)
    one = scattered_fire(rng, 1, 5000, 10)
    few = rng.uniform(0, CELLS, (4, 2))
    one_ms = median_ms(lambda: one, lambda s: closest_burning(s, np.zeros(4, np.int64), few[:, 0], few[:, 1], 50.0),
                       10 * runs)
    return [("closest_burning (50 cells)", f"B={batch} x (3 planes + village), {counts.min()}-{counts.max()} "
             "burning/world", runs, ring_ms),
            ("closest_burning (50 cells)", "B=1 x 4 queries, 5000 burning", 10 * runs, one_ms)]


def main() -> None:
    rng = np.random.default_rng(0)
    burn = FireSpec().burn_steps
    rows = [
        step_case(rng, "fire_step (ring front)", ring_fire(rng, 1, 138.0, 10.0, burn), 30),
        step_case(rng, "fire_step (scattered)", scattered_fire(rng, 1, 5000, burn), 30),
        step_case(rng, "fire_step (ring front)", ring_fire(rng, 256, 19.0, 3.0, burn), 15),
        step_case(rng, "fire_step (ring, steady)", ring_fire(rng, 1, 138.0, 10.0, burn), 30, steady=True),
        step_case(rng, "fire_step (ring, steady)", ring_fire(rng, 256, 19.0, 3.0, burn), 15, steady=True),
        step_case(rng, "fire_step (steady, grid)", ring_fire(rng, 256, 19.0, 3.0, burn), 15, steady=True, grid=True),
        *water_cases(rng, 256, 3, 15),
        *search_cases(rng, 15),
    ]
    print(f"{'case':<28} {'size':<52} {'runs':>4} {'median ms':>10}")
    for name, size, runs, ms in rows:
        print(f"{name:<28} {size:<52} {runs:>4} {ms:>10.3f}")


if __name__ == "__main__":
    main()
