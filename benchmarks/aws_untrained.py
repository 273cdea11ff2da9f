"""Untrained Aerial Wildfire Suppression planes beside the original's: each task's Episode Length and return a
plane-episode under random play, against the first training point of the original's page for the same cell.

    python benchmarks/aws_untrained.py [--tasks main pick_up_water ...] [--levels 1 3 6 10] [--episodes 40]
                                       [--set key=value ...]

The original's first summary point (9,000 agent-steps) averages the episodes its untrained policy ended there;
random play here (uniform steering and drops, `hivex_dsl.evaluation.rollout`'s 'random') plays ``--episodes`` test
episodes of each task at each level, three planes a world. ``--set`` overrides a param (``--set
finished_planes=wait --set plane_speed_m=5``): the reward table's note 'Three seeds of the release's episode
structure' records what it printed (issue 52).
"""

from __future__ import annotations

import argparse
import sys

import hivex_dsl
from hivex_dsl.base.errors import HivexError
from hivex_dsl.cli.argtypes import positive
from hivex_dsl.evaluation.original.curves import original_curves
from hivex_dsl.evaluation.rollout import rollout
from hivex_dsl.train.config import parse_assignments

ENVIRONMENT = "aerial_wildfire_suppression"
TASKS = ("main", "pick_up_water", "drop_water", "find_fire", "find_village")


def untrained(task: str, level: int, params: dict, episodes: int) -> tuple[float, float, float, float]:
    """(Episode Length, return) a plane-episode of random play in ``task`` at ``level`` under ``params``, then the
    same at the first training point of the original's page for that cell."""
    compiled = hivex_dsl.compile({"hivex": 1, "environment": ENVIRONMENT, "task": task, "terrain_level": level,
                                  "agents": 3, "episode_length": 3000, "params": params})
    done = rollout(compiled, "random", episodes, split="test")
    cell = original_curves(ENVIRONMENT, compiled.task_index, level)
    return (float(done.lengths.mean()), float(done.returns.mean()),
            float(cell.panel("Episode Length").training.mean[0]), float(cell.panel("Cumulative Reward").training.mean[0]))


def report(tasks: list[str], levels: list[int], params: dict, episodes: int) -> list[str]:
    """The printed lines: a header, then one line a task with each level's ours/original pairs."""
    lines = [f"random play, {episodes} test episodes a cell, params {params or 'the defaults'}: "
             "Episode Length / return a plane-episode, ours against the original's first training point"]
    for task in tasks:
        cells = []
        for level in levels:
            length, ret, o_length, o_ret = untrained(task, level, params, episodes)
            cells.append(f"L{level} {length:.0f}/{ret:.0f} ({o_length:.0f}/{o_ret:.0f})")
        lines.append(f"  {task}: " + ", ".join(cells))
    return lines


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--tasks", nargs="+", choices=TASKS, default=list(TASKS))
    parser.add_argument("--levels", nargs="+", type=int, choices=range(1, 11), default=[1, 3, 6, 10], metavar="LEVEL")
    parser.add_argument("--episodes", type=positive, default=40)
    parser.add_argument("--set", dest="assignments", action="append", default=[], metavar="KEY=VALUE")
    args = parser.parse_args(argv)
    try:
        params = dict(parse_assignments(args.assignments).values)  # each value a YAML scalar, as `hivex train --set`
        lines = report(args.tasks, args.levels, params, args.episodes)
    except HivexError as error:
        print(f"aws_untrained: {error}", file=sys.stderr)
        return 2
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    sys.exit(main())
