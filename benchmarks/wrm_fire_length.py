"""Wildfire Resource Management's fire length per terrain level, as the original's Episode Length curves log it.

    python benchmarks/wrm_fire_length.py [--worlds 12] [--steps 2000] [--levels 1,2,...] [--param NAME=VALUE ...]
                                         [--generators '{"weather": {"noise_scale_m": 6000}}']

ML-Agents logs Episode Length at every summary point (4,500 agent-steps: 500 steps of the nine towers) as the mean
of the episodes that ended since the last point, and the original's curve is the mean over its three runs. So each
world here plays a continuous stream of all-zeros episodes on the training seed stream (no action changes the fire),
its steps are cut in 500-step windows, each window's ended episodes averaged, and the windows averaged; beside it the
plain mean over episodes, the Collective Performance per step and the original's training average
(hivex_dsl.evaluation.original.evidence.training_average). How far the windows scatter is read like with like: each
world is one stream, as each level of the original is (its three runs and three tasks log one Episode Length curve),
so the spread is the standard deviation of a world's windows, pooled over the worlds (the root of their mean
variance), beside the original's points' (evidence.training_spread); it needs long streams (--steps 20000 gives 40
windows a world). The reward table's notes record what it printed for the fitted spread chance and for the spread
(issue 52).
"""

from __future__ import annotations

import argparse
import json
import sys

import numpy as np

import hivex_dsl
from hivex_dsl.base.errors import HivexError
from hivex_dsl.cli import argtypes
from hivex_dsl.evaluation.original.evidence import EPISODE_LENGTH, training_average, training_spread
from hivex_dsl.runtime.batched import BatchedEnv

ENVIRONMENT = "wildfire_resource_management"
WINDOW = 500  # steps of one summary point: summary_freq 4,500 agent-steps over 9 towers
COLLECTIVE = "Collective Performance"


def window_means(worlds: np.ndarray, ends: np.ndarray, values: np.ndarray, window: int = WINDOW) -> np.ndarray:
    """(W,) the mean of ``values`` over the episodes that ended in each window holding any: ``worlds``, ``ends``
    (the step an episode ended on, from 1) and ``values`` (N,) per episode, windows [k * window + 1, (k + 1) * window]."""
    keys = worlds.astype(np.int64) * (ends.max() // window + 1) + (ends - 1) // window
    _, which = np.unique(keys, return_inverse=True)
    return np.bincount(which, values) / np.bincount(which)


def stream_spread(worlds: np.ndarray, ends: np.ndarray, values: np.ndarray, window: int = WINDOW) -> float:
    """How far each world's windows scatter (:func:`window_means` of that world alone: one stream, as one level of
    the original), pooled over the worlds: the root of their mean sample variance."""
    variances = [window_means(worlds[here], ends[here], values[here], window).var(ddof=1)
                 for here in (worlds == world for world in np.unique(worlds))]
    return float(np.sqrt(np.mean(variances)))


def streams(level: int, worlds: int, steps: int, params: dict,
            generators: dict | None = None) -> tuple[np.ndarray, ...]:
    """(world, end step, length, Collective Performance) (N,) of every episode ended within ``steps`` steps of
    ``worlds`` continuous all-zeros streams at ``level``, under the scenario's ``params`` and ``generators``. A
    tower's performance is its P alone unless ``params`` say otherwise (performance_weight 'none': all-zeros towers
    hold no share, so the default reading would log no Collective Performance), the fire's own yield."""
    scenario = {"hivex": 1, "environment": ENVIRONMENT, "terrain_level": level, "agents": 9, "episode_length": 500,
                "seeds": {"train": 5000, "test": 6000}, "params": {"performance_weight": "none", **params}}
    compiled = hivex_dsl.compile({**scenario, "generators": generators} if generators else scenario)
    env = BatchedEnv(compiled, batch=worlds, split="train")
    env.reset()
    actions = np.zeros((worlds, compiled.agents, 4), np.int64)
    found: list[tuple[np.ndarray, ...]] = []
    for step in range(1, steps + 1):
        env.step(actions)
        ended = ~env.alive.any(axis=1)
        if ended.any():
            index = np.flatnonzero(ended)
            found.append((index, np.full(len(index), step), env.lengths[index, 0].copy(),
                          env.statistic_sums()[COLLECTIVE][index, 0].copy()))
            env.reset_worlds(ended)
    return tuple(np.concatenate(column) for column in zip(*found))


def parse_params(assignments: list[str]) -> dict:
    """``["spread_chance_per_factor=0.5"]`` -> ``{"spread_chance_per_factor": 0.5}`` (values read as JSON)."""
    params = {}
    for text in assignments:
        name, sep, value = text.partition("=")
        if not sep or not name.strip():
            raise HivexError(f"--param {text}: expected NAME=VALUE")
        try:
            params[name.strip()] = json.loads(value)
        except json.JSONDecodeError:
            raise HivexError(f"--param {text}: the value must be a number, true/false or a quoted string") from None
    return params


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--worlds", type=int, default=12, help="continuous streams a level (default 12)")
    parser.add_argument("--steps", type=int, default=2000, help="steps of each stream (default 2000: 4 windows)")
    parser.add_argument("--levels", default="1,2,3,4,5,6,7,8,9,10", help="terrain levels, comma-separated")
    parser.add_argument("--param", action="append", default=[], help="NAME=VALUE of the scenario's params")
    parser.add_argument("--generators", type=argtypes.generators, default=None,
                        help="the scenario's generators mapping, as JSON (the language's generators section)")
    args = parser.parse_args(argv)
    try:
        if args.worlds < 1 or args.steps < WINDOW:
            raise HivexError(f"--worlds must be >= 1 and --steps >= {WINDOW} (one window)")
        levels = [int(level) for level in args.levels.split(",")]
        params = parse_params(args.param)
        print("level  windows  logged length  original  ratio  episode mean  Collective/step  original"
              "  spread  original")
        for level in levels:
            world, end, length, collective = streams(level, args.worlds, args.steps, params, args.generators)
            logged, per_step = window_means(world, end, length), window_means(world, end, collective)
            original = training_average(ENVIRONMENT, 0, level)
            original_yield = training_average(ENVIRONMENT, 0, level, COLLECTIVE) / original
            spread = stream_spread(world, end, length) if len(logged) > args.worlds else float("nan")
            print(f"{level:5d}  {len(logged):7d}  {logged.mean():13.1f}  {original:8.1f}  {logged.mean() / original:5.2f}"
                  f"  {length.mean():12.1f}  {per_step.sum() / logged.sum():15.3f}  {original_yield:8.3f}"
                  f"  {spread:6.1f}  {training_spread(ENVIRONMENT, 0, level):8.1f}", flush=True)
    except (HivexError, ValueError) as error:
        print(f"error: {error}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
