"""Where Aerial Wildfire Suppression's planes drop their water and how many trees a drop wets, per terrain level.

    python benchmarks/aws_drops.py [--task main] [--policy random|scripted|trained] [--levels 1,2,...]
                                   [--worlds 8] [--episodes 1] [--grid /work/runs/aws-grid] [--headlands]
                                   [--generators '{"terrain": {"sea_level_m": 7}}']
                                   [--params '{"drop_ground": "island"}']

Plays test-seed episodes and logs every drop: the trees it wetted, the ground height and the distance to the sea
under the plane, how many trees its swath held when the episode began (so the share it found still dry), and
whether the plane was over the water ring (past the island's square): a drop the last frame's terrain cast let
through there wets nothing (params.terrain_cast 'frame'), the loop the original's late records show (pick-ups
within one of the drops at a few trees a drop). Per plane it logs the decisions it played and whether it dropped
at all: in Drop Water (task drop_water) an episode ends on the first drop, so that is the untrained planes' time to
their first drop, the original's Episode Length at its first summary points. Beside each level it prints the
original's trees a drop, pooled over its first 90,000 agent-steps
(hivex_dsl.evaluation.original.evidence.pooled_ratio). ``--policy trained`` plays the checkpoint of ``--grid``'s
run of that level, one world at a time. ``--headlands`` prints instead, per level, how much terrain stands above
the sea between the island's square and the border, where under params.drop_ground 'terrain' (the default, the
release's DropWater) a plane refills and drops without crossing back. The reward table's notes record what it
printed (issue 52).
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np

import hivex_dsl
from hivex_dsl.base.errors import HivexError
from hivex_dsl.envs.island import SEA
from hivex_dsl.evaluation.original.evidence import EvidenceError, pooled_ratio
from hivex_dsl.evaluation.policies import make_policy
from hivex_dsl.runtime.batched import BatchedEnv
from hivex_dsl.sim.fire.water import covered_cells
from hivex_dsl.sim.grids import sample_bilinear

ENVIRONMENT = "aerial_wildfire_suppression"
TREES = ("Preparing Trees", "Extinguishing Trees")
UNTRAINED = 90_000  # agent-steps: the original's first ten summary points


def sea_distance_m(land: np.ndarray, cell_m: float, cap_cells: int = 120) -> np.ndarray:
    """(B, C, C) metres from each cell of ``land`` (B, C, C) bool to the nearest sea cell (off the grid is sea),
    by dilation alternating 4- and 8-neighbour steps (an octagon, within 8% of the Euclidean distance); cells
    further than ``cap_cells`` steps are inf."""
    near = ~land
    distance = np.where(near, 0.0, np.inf)
    for step in range(1, cap_cells + 1):
        p = np.pad(near, ((0, 0), (1, 1), (1, 1)), constant_values=True)
        grown = near | p[:, :-2, 1:-1] | p[:, 2:, 1:-1] | p[:, 1:-1, :-2] | p[:, 1:-1, 2:]
        if step % 2 == 0:
            grown = grown | p[:, :-2, :-2] | p[:, :-2, 2:] | p[:, 2:, :-2] | p[:, 2:, 2:]
        distance[grown & ~near] = step * cell_m * 0.94  # an octagon step averages 1.06 cells of Euclidean reach
        near = grown
    return distance


def swath_trees(sim, exists: np.ndarray, world: np.ndarray, position: np.ndarray, heading: np.ndarray) -> np.ndarray:
    """(D,) tree cells of ``exists`` (B, C, C) a swath covers: D drops by ``world`` (D,), plane ``position``
    (D, 2) metres and ``heading`` (D,) radians, on the simulator's own swath (its points ahead and cell coordinates)."""
    rows, cols = sim.swath_cells(position, np.stack([np.cos(heading), np.sin(heading)], axis=-1))
    batch, cells, per_drop = exists.shape[0], exists.shape[1], rows.shape[1]
    point, flat = covered_cells(np.repeat(world, per_drop), rows.ravel(), cols.ravel(),
                                sim.params.drop_radius_m / sim.cell_m, cells, batch)
    drop_cell = np.unique((point // per_drop).astype(np.int64) * exists.size + flat)  # each cell once a drop
    drop, cell = np.divmod(drop_cell, exists.size)
    return np.bincount(drop, weights=exists.reshape(-1)[cell], minlength=len(world))


def policy_of(name: str, compiled, core: BatchedEnv, level: int, grid: Path | None):
    if name != "trained":
        return make_policy(name, compiled, core.sim.action_space, core.shape, seed=level)
    from hivex_dsl.train.evaluate import checkpoint_policies, level_checkpoint

    if grid is None:
        raise HivexError("--policy trained plays the checkpoints of a `hivex train` level sweep: name it with --grid")
    return checkpoint_policies(level_checkpoint(grid, level))(compiled)


def play(level: int, task: str, policy: str, worlds: int, episodes: int, generators: dict, grid: Path | None,
         params: dict | None = None) -> tuple[dict[str, np.ndarray], dict[str, np.ndarray]]:
    """Per drop (wet, height, sea, swath, ring) and per plane (length, dropped) arrays over ``episodes`` of
    ``worlds``."""
    scenario = {"hivex": 1, "environment": ENVIRONMENT, "task": task, "terrain_level": level}
    if generators:
        scenario["generators"] = generators
    if params:
        scenario["params"] = params
    compiled = hivex_dsl.compile(scenario)
    core = BatchedEnv(compiled, batch=1 if policy == "trained" else worlds, split="test")
    act = policy_of(policy, compiled, core, level, grid)
    p, spec = compiled.params, compiled.generators["forest"]
    drops, planes = {k: [] for k in ("wet", "height", "sea", "swath", "ring")}, {"length": [], "dropped": []}
    for episode in range(episodes):
        observations = core.reset() if episode == 0 else core.reset_worlds(np.ones(core.batch, bool))
        start = core.state.maps
        sea = sea_distance_m(start.ground != SEA, spec.spacing_m)  # the simulator's sea (its sea level)
        length, dropped = np.zeros(core.shape, np.int64), np.zeros(core.shape, bool)
        while core.alive.any() and core.clock.max() < compiled.episode_length:
            length += core.alive
            observations = core.step(act(observations)).observations
            s = core.state
            world, plane = np.nonzero(s.dropped)
            dropped |= s.dropped
            if not len(world):
                continue
            cell = np.clip(((s.position[world, plane] + p.island_half_extent_m) // spec.spacing_m).astype(np.int64),
                           0, spec.cells - 1)
            drops["wet"].append(s.prepared[world, plane] + s.extinguished[world, plane])
            drops["ring"].append(np.abs(s.position[world, plane]).max(axis=-1) > p.island_half_extent_m)
            drops["height"].append(start.height[world, cell[:, 1], cell[:, 0]])
            drops["sea"].append(sea[world, cell[:, 1], cell[:, 0]])
            drops["swath"].append(swath_trees(core.sim, start.exists, world, s.position[world, plane],
                                              s.heading[world, plane]))
        planes["length"].append(length.ravel())
        planes["dropped"].append(dropped.ravel())
    join = lambda parts: np.concatenate(parts) if parts else np.zeros(0)  # noqa: E731
    return {k: join(v) for k, v in drops.items()}, {k: join(v) for k, v in planes.items()}


def headlands(level: int, worlds: int, lattice_m: float = 2.5) -> tuple[float, float]:
    """The share of ``worlds`` test-seed worlds whose terrain stands above the sea somewhere between the island's
    square and the border, and that land's mean area (m^2 a world), on a lattice of ``lattice_m``."""
    compiled = hivex_dsl.compile({"hivex": 1, "environment": ENVIRONMENT, "task": "main", "terrain_level": level})
    core = BatchedEnv(compiled, batch=worlds, split="test")
    core.reset()
    p, sim = compiled.params, core.sim
    axis = np.arange(-p.border_half_extent_m, p.border_half_extent_m + lattice_m / 2, lattice_m)
    x, y = np.meshgrid(axis, axis)
    ring = np.maximum(np.abs(x), np.abs(y)) > p.island_half_extent_m
    points = np.broadcast_to(np.stack([x[ring], y[ring]], axis=-1), (worlds, int(ring.sum()), 2))
    land = sample_bilinear(core.state.maps.terrain, sim.terrain_grid, np.ascontiguousarray(points)) > sim.sea_level_m
    return float(land.any(axis=1).mean()), float(land.sum(axis=1).mean() * lattice_m ** 2)


def original_trees_a_drop(task: str, level: int) -> str:
    compiled = hivex_dsl.compile({"hivex": 1, "environment": ENVIRONMENT, "task": task, "terrain_level": level})
    try:
        ratio, drops = pooled_ratio(ENVIRONMENT, compiled.task_index, level, TREES, "Water Drop", 0, UNTRAINED)
    except EvidenceError:
        return "original: -"
    return f"original first 90k: {ratio:6.1f} a drop, {drops:4.2f} drops"


def row(level: int, drops: dict[str, np.ndarray], planes: dict[str, np.ndarray]) -> str:
    if not len(drops["wet"]):
        return f"L{level:2d}: no drop; planes' mean length {planes['length'].mean():6.1f}"
    dry = drops["wet"].sum() / max(drops["swath"].sum(), 1)
    ring = drops["ring"].astype(bool)
    land = f"{drops['wet'][~ring].mean():6.1f}" if (~ring).any() else "     -"
    return (f"L{level:2d}: {len(drops['wet']):4d} drops, {drops['wet'].mean():6.1f} trees a drop ({ring.mean():4.2f} "
            f"of the drops over the ring; over land {land} a drop) (swath held "
            f"{drops['swath'].mean():6.1f} at the start, {dry:4.2f} of them still dry), ground median "
            f"{np.median(drops['height']):5.1f} m, sea median {np.median(drops['sea']):4.0f} m "
            f"({np.mean(drops['sea'] < 60):4.2f} within 60 m); planes: length {planes['length'].mean():6.1f}, "
            f"dropped {planes['dropped'].mean():4.2f}")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--task", default="main")
    parser.add_argument("--policy", choices=("random", "scripted", "zeros", "trained"), default="random")
    parser.add_argument("--levels", default="1,2,3,4,5,6,7,8,9,10")
    parser.add_argument("--worlds", type=int, default=8)
    parser.add_argument("--episodes", type=int, default=1)
    parser.add_argument("--grid", type=Path, default=None, help="a `hivex train` sweep folder (--policy trained)")
    parser.add_argument("--generators", default="{}", help="a scenario's generators: overrides, as JSON")
    parser.add_argument("--params", default="{}", help="a scenario's params: overrides, as JSON")
    parser.add_argument("--headlands", action="store_true", help="print the land past the island's square instead")
    args = parser.parse_args(argv)
    try:
        levels = [int(v) for v in args.levels.split(",")]
        generators, params = json.loads(args.generators), json.loads(args.params)
        for level in levels if args.headlands else ():
            share, area = headlands(level, args.worlds)
            print(f"L{level:2d}: {share:4.2f} of worlds hold land above the sea past the island, "
                  f"{area:6.0f} m^2 a world")
        for level in () if args.headlands else levels:
            drops, planes = play(level, args.task, args.policy, args.worlds, args.episodes, generators, args.grid,
                                 params)
            print(f"{row(level, drops, planes)}  | {original_trees_a_drop(args.task, level)}", flush=True)
    except (HivexError, ValueError) as error:
        print(f"aws_drops: {error}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
