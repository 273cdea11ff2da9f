"""The course of Aerial Wildfire Suppression's fire left alone, under any params: how often and when it reaches the
village, how often it goes out, how much it burns.

    python benchmarks/aws_fire_course.py [--worlds 64] [--level 1] [--steps 3000] [--set key=value ...]
                                         [--generators '{"weather": {"octaves": 1}}'] [--stream]

Plays ``--worlds`` test-seed worlds of the main task for ``--steps`` steps with every plane circling (steer 1, no
drop), so nothing fights the fire and no plane leaves, and prints the share of worlds whose fire came within the
village radius (and the median step it did), the share whose fire went out (and the median step it did), and the
median trees burnt and still burning at the end. ``--set`` overrides a param. Under the default cadence (fire_cadence frames, the release's) no
world is redrawn here, so the fire steps every two frames as in a stream's first world, 33.3 steps; ``--stream``
starts every world as a world of a stream after its first redraw, a BurnNext waiting, so the fire steps every frame
(16.7 steps), the release's pace for nearly all of a training or test run; ``--set fire_cadence=interval --set
fire_step_interval=17`` steps it every 17 (the reward table's notes record what it printed, issue 52).
``--generators`` the scenario's generators section, as JSON (the release's weather: the note 'The release's
weather').
"""

from __future__ import annotations

import argparse
import sys
from dataclasses import dataclass, replace

import numpy as np

import hivex_dsl
from hivex_dsl.base.errors import HivexError
from hivex_dsl.cli import argtypes
from hivex_dsl.sim.fire.engine import TreeState
from hivex_dsl.train.config import parse_assignments

ENVIRONMENT = "aerial_wildfire_suppression"


@dataclass(frozen=True)
class Course:
    reached_step: np.ndarray  # (B,) first step the fire came within the village radius, -1 if never
    out_step: np.ndarray  # (B,) first step the fire went out, -1 if never
    burnt: np.ndarray  # (B,) trees burnt at the end
    burning: np.ndarray  # (B,) trees burning at the end


def fire_course(params: dict, worlds: int, level: int = 1, steps: int = 3000, generators: dict | None = None,
                stream: bool = False) -> Course:
    """Run ``worlds`` test-seed worlds of the main task at ``level`` with ``params`` (and ``generators``, the
    scenario's section) for ``steps`` steps, every plane circling without a drop; ``stream``: each world as one
    drawn after its stream's first redraw, a BurnNext waiting (burn_clock.py), so 'frames' steps the fire every
    frame from the start."""
    scenario = {"hivex": 1, "environment": ENVIRONMENT, "task": "main", "terrain_level": level,
                "episode_length": steps, "params": params}
    compiled = hivex_dsl.compile({**scenario, "generators": generators} if generators else scenario)
    sim = compiled.entry.make_simulator(compiled)
    rng = np.random.default_rng(compiled.seeds.test)
    state = sim.reset(rng, worlds)
    if stream:
        state = replace(state, burn_waiting=np.ones(worlds, bool))
    shape = (worlds, compiled.agents, 1)
    circling = {"continuous": np.ones(shape, np.float32), "discrete": np.zeros(shape, np.int64)}
    reached, out = np.full(worlds, -1), np.full(worlds, -1)
    for step in range(steps):
        state, _ = sim.step(state, circling, rng)
        reached = np.where((reached < 0) & state.village_threatened, step, reached)
        out = np.where((out < 0) & state.fire_went_out, step, out)
    trees = state.fire.trees.reshape(worlds, -1)
    return Course(reached, out, (trees == TreeState.BURNT).sum(1), (trees == TreeState.BURNING).sum(1))


def describe(course: Course) -> str:
    reached, out = course.reached_step >= 0, course.out_step >= 0
    when = f"median step {np.median(course.reached_step[reached]):.0f}" if reached.any() else "never"
    ended = f" (median step {np.median(course.out_step[out]):.0f})" if out.any() else ""
    return (f"village reached in {reached.mean():.0%} of worlds ({when}), out in {out.mean():.0%}{ended}, "
            f"burnt trees median {np.median(course.burnt):.0f}, burning at the end median {np.median(course.burning):.0f}")


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--worlds", type=int, default=64)
    parser.add_argument("--level", type=int, default=1)
    parser.add_argument("--steps", type=int, default=3000)
    parser.add_argument("--set", action="append", default=[], metavar="KEY=VALUE")
    parser.add_argument("--generators", type=argtypes.generators, default=None, metavar="JSON",
                        help="the scenario's generators section, as JSON")
    parser.add_argument("--stream", action="store_true",
                        help="every world as one after its stream's first redraw: under fire_cadence frames the "
                             "fire steps every frame from the start")
    args = parser.parse_args(argv)
    try:
        params = dict(parse_assignments(args.set).values)  # each value a YAML scalar, as `hivex train --set`
        course = fire_course(params, args.worlds, args.level, args.steps, args.generators, args.stream)
    except HivexError as exc:
        print(f"aws_fire_course: {exc}", file=sys.stderr)
        return 2
    print(params or "defaults", *([args.generators] if args.generators else []), *(["stream"] if args.stream else []),
          describe(course))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
