"""How often trivial planes find the village in Aerial Wildfire Suppression's Find Village task, under any params.

    python benchmarks/aws_find_village.py [--worlds 64] [--level 1] [--set key=value ...]

Plays the first episode of ``--worlds`` test-seed worlds twice, with the audit's all-zeros policy (straight flights)
and its random policy (hivex_dsl.evaluation.policies), and prints for each the mean return a plane-episode, the share
of planes that found the village and the mean length of a world's episode. The worlds are the same under any
``--set``, so two rules compare on matched flights: a batch of worlds, where `hivex audit` plays its episodes one after
another in one world, so that a rule that ends one episode sooner draws the next ones afresh (``--set
village_distance=release``: the release's 3-D distance; the reward table's note 'The village's zone, its distance and
the water that does not stop the fire', issue 52).
"""

from __future__ import annotations

import argparse
import sys

import numpy as np

import hivex_dsl
from hivex_dsl.base.errors import HivexError
from hivex_dsl.evaluation.policies import make_policy
from hivex_dsl.runtime import BatchedEnv
from hivex_dsl.train.config import parse_assignments

AGENTS = 3


def first_episodes(params: dict, worlds: int, level: int, policy: str, seed: int = 1) -> tuple[float, float, float]:
    """(mean return a plane-episode, share of planes that found the village, mean world-episode length) of the
    first episode of ``worlds`` test-seed worlds under the audit's 'zeros' or 'random' policy."""
    compiled = hivex_dsl.compile({"hivex": 1, "environment": "aerial_wildfire_suppression", "task": "find_village",
                                  "terrain_level": level, "agents": AGENTS, "episode_length": 3000, "params": params})
    env = BatchedEnv(compiled, batch=worlds)
    observations = env.reset(seed=compiled.seeds.test)
    act = make_policy(policy, compiled, env.sim.action_space, env.shape, seed=seed)
    total, found = np.zeros((worlds, AGENTS)), np.zeros((worlds, AGENTS))
    ended, length = np.zeros(worlds, bool), np.zeros(worlds)
    for _ in range(compiled.episode_length):
        step = env.step(act(observations))
        observations = step.observations
        going = ~ended[:, None]
        total += np.where(going, step.rewards, 0.0)
        found += going & env.state.found_village
        length += ~ended
        ended |= (step.terminated | step.truncated).all(1)
        if ended.all():
            break
    return float(total.mean()), float(found.mean()), float(length.mean())


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--worlds", type=int, default=64)
    parser.add_argument("--level", type=int, default=1)
    parser.add_argument("--set", action="append", default=[], metavar="KEY=VALUE")
    args = parser.parse_args(argv)
    try:
        params = dict(parse_assignments(args.set).values)
        for policy in ("zeros", "random"):
            ret, share, length = first_episodes(params, args.worlds, args.level, policy)
            print(f"{params or 'defaults'} {policy}: return {ret:.1f} a plane-episode, village found by {share:.1%} "
                  f"of planes, world-episodes of {length:.0f} steps")
    except HivexError as exc:
        print(f"aws_find_village: {exc}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
