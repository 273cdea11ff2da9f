"""Pick Up Water's untrained drop branch under the release's waiting planes: how often it would be open.

    python benchmarks/aws_waiting_pickers.py [--levels 1 5 10] [--episodes 40] [--worlds 32] [--task pick_up_water]

The release's mask (HivexAgent.WriteDiscreteActionMask) opens the drop wherever a plane holds water over terrain
at least 0.02 m high, frozen or not, and a Pick Up Water plane freezes holding its water where it picked it up,
just past the island's 600 m, until the slowest plane of its world has too (finished_planes wait). This prints,
per terrain level: the share of random planes' decisions spent waiting after their pick-up (the release's plane
rules, test seeds), the share of the water ring's inner edge (602 m) over terrain at least 0.02 m high (this
toolkit's terrain generator, the release's), and the entropy an untrained policy would then show (ML-Agents'
Gaussian 1.419 plus ln 2 times the open share), against the original's first training point (the reward table's
note "Pick Up Water's untrained entropy"). It also plays the same random flights under params.drop_mask 'release',
which models that mask (waiting planes, the terrain under the water ring), and prints the share of decisions its
action mask left open and the entropy that gives; --task main does that for the main task.
"""

from __future__ import annotations

import argparse
import math

import numpy as np

import hivex_dsl
from hivex_dsl.envs.aerial_wildfire_suppression.simulator import MASK_TERRAIN_M
from hivex_dsl.evaluation.original import compare
from hivex_dsl.sim.procgen.terrain import generate_terrain, terrain_spec_for_level

RELEASE_RULES = {"plane_speed_m": 5.0, "turn_rule": "full", "finished_planes": "wait", "spawn_rule": "release"}
GAUSSIAN_ENTROPY = 0.5 * math.log(2 * math.pi * math.e)  # ML-Agents' untrained log-std 0: 1.419
RING_EDGE_M = 602.0
TASKS = {"main": 0, "pick_up_water": 5}


def waiting_share(level: int, episodes: int) -> tuple[float, float]:
    """(the mean share of plane-decisions spent after the plane's pick-up, the mean world length in decisions)."""
    compiled = hivex_dsl.compile({"hivex": 1, "environment": "aerial_wildfire_suppression", "task": "pick_up_water",
                                  "terrain_level": level, "params": RELEASE_RULES})
    env = hivex_dsl.parallel_env(compiled, split="test")
    shares, lengths = [], []
    for episode in range(episodes):
        env.reset(seed=compiled.seeds.test + episode)
        env.action_space(env.agents[0]).seed(episode)
        picked: dict[str, int | None] = {agent: None for agent in env.agents}
        steps = 0
        while env.agents:
            _, rewards, _, _, _ = env.step({agent: env.action_space(agent).sample() for agent in env.agents})
            steps += 1
            for agent, reward in rewards.items():
                if picked[agent] is None and reward > 50:  # the pick-up's +100
                    picked[agent] = steps
        ends = [steps if at is None else at for at in picked.values()]
        shares.append(sum(steps - at for at in ends) / (len(ends) * steps))
        lengths.append(steps)
    return float(np.mean(shares)), float(np.mean(lengths))


def open_share(level: int, episodes: int, task: str = "pick_up_water", drop_mask: str = "release") -> float:
    """The share of random planes' decisions (the release's plane rules, test seeds) at which the environment's
    action mask leaves the drop open, under params.drop_mask ``drop_mask``."""
    compiled = hivex_dsl.compile({"hivex": 1, "environment": "aerial_wildfire_suppression", "task": task,
                                  "terrain_level": level, "params": {**RELEASE_RULES, "drop_mask": drop_mask}})
    env = hivex_dsl.parallel_env(compiled, split="test")
    opened = decisions = 0
    for episode in range(episodes):
        _, infos = env.reset(seed=compiled.seeds.test + episode)
        env.action_space(env.agents[0]).seed(episode)
        while env.agents:
            opened += sum(int(infos[agent]["action_mask"]["discrete"][0][1]) for agent in env.agents)
            decisions += len(env.agents)
            _, _, _, _, infos = env.step({agent: env.action_space(agent).sample() for agent in env.agents})
    return opened / decisions


def ring_edge_over_terrain(level: int, worlds: int) -> float:
    """The mean share of the square ring's inner edge (at RING_EDGE_M) where the terrain stands MASK_TERRAIN_M high."""
    side = np.linspace(-RING_EDGE_M, RING_EDGE_M, 400)
    edge = np.concatenate([np.stack([side, np.full_like(side, sign * RING_EDGE_M)], -1) for sign in (-1, 1)]
                          + [np.stack([np.full_like(side, sign * RING_EDGE_M), side], -1) for sign in (-1, 1)])
    shares = [(generate_terrain(np.random.default_rng(1000 + world), terrain_spec_for_level(level)).height_at(edge)
               >= MASK_TERRAIN_M).mean() for world in range(worlds)]
    return float(np.mean(shares))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--levels", type=int, nargs="+", default=[1, 5, 10])
    parser.add_argument("--episodes", type=int, default=40)
    parser.add_argument("--worlds", type=int, default=32)
    parser.add_argument("--task", default="pick_up_water", help="the task of the measured mask (default pick_up_water)")
    args = parser.parse_args()
    for level in args.levels:
        share = open_share(level, args.episodes, args.task)
        original = compare.original_cell("aerial_wildfire_suppression", TASKS[args.task], level)
        print(f"level {level:2d}: {args.task}, drop_mask release: the drop open at {share:.3f} of decisions, entropy "
              f"{GAUSSIAN_ENTROPY + math.log(2) * share:.3f} (the original's first point "
              f"{original.panels['Entropy'].training.mean[0]:.3f})")
        if args.task != "pick_up_water":
            continue
        waiting, length = waiting_share(level, args.episodes)
        edge = ring_edge_over_terrain(level, args.worlds)
        entropy = GAUSSIAN_ENTROPY + math.log(2) * waiting * edge
        original = compare.original_cell("aerial_wildfire_suppression", 5, level).panels["Entropy"].training.mean[0]
        print(f"level {level:2d}: world {length:5.1f} decisions, waiting {waiting:.3f}, ring edge over terrain "
              f"{edge:.3f}, entropy {entropy:.3f} (the original's first point {original:.3f})")


if __name__ == "__main__":
    main()
