"""Ocean Plastic Collection: how long collectors live when they see their neighbours less (issue 52).

The original's trained worlds crash at a steady rate, about once every 160 decisions, with policies sharper than
ours (the reward table's ending note). A collector that cannot see the other vessels meets them by chance where the
plastic draws them all, which would crash its worlds at such a steady rate. This plays the scripted
skipper, which steers for dense water and turns away from a vessel it sees close ahead, on the main task's test
worlds at several of params.neighbour_sight_m (how far the vector observation sends the closest vessel; null: at any
distance, the default), and uniform random play beside it (which reads nothing, so any sight plays it alike):

    python benchmarks/opc_neighbour_sight.py [--worlds N] [--sights none,0,15,25,50,100]

Each row: decisions a vessel-episode (mean and median), the coefficient of variation of the world-episodes' lives
(1 for a steady rate of crashes, less where the time limit cuts long lives), Local (pebbles a vessel-episode), the
pace (pebbles a decision), the return, and the share of vessel-episodes paying a border crossing and a collision.
"""

from __future__ import annotations

import argparse

import numpy as np

import hivex_dsl
from hivex_dsl.evaluation.rollout import rollout

ENV = "ocean_plastic_collection"


def main_task(sight: float | None) -> hivex_dsl.CompiledScenario:
    spec = {"hivex": 1, "environment": ENV, "task": 0, "agents": 3, "episode_length": 5000,
            "seeds": {"train": 5000, "test": 6000}}
    return hivex_dsl.compile(spec if sight is None else {**spec, "params": {"neighbour_sight_m": sight}})


def lives(sight: float | None, policy: str, worlds: int, seed: int = 1) -> dict[str, float]:
    """``policy`` ('scripted', 'random') over ``worlds`` test worlds at one sight -> the module's row."""
    compiled = main_task(sight)
    played = rollout(compiled, policy, worlds, seed=seed)
    decisions = played.lengths / compiled.decision_period  # (worlds, agents)
    world = decisions.max(axis=1)  # a crash ends its world's episode: every vessel's life is the world's
    local = played.statistics["Local Reward"]
    return {"decisions": float(decisions.mean()), "median": float(np.median(decisions)),
            "world_cv": float(world.std() / world.mean()), "local": float(local.mean()),
            "pace": float(local.sum() / decisions.sum()), "return": float(played.returns.mean()),
            "border": float(np.mean(played.terms["crossed_border"] < 0)),
            "collision": float(np.mean(played.terms["collided_with_other_vessel"] < 0))}


def parse_sight(text: str) -> float | None:
    return None if text.strip().lower() in ("none", "null") else float(text)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--worlds", type=int, default=24, help="test worlds a row plays (default 24)")
    parser.add_argument("--sights", default="none,0,15,25,50,100",
                        help="comma-separated params.neighbour_sight_m values, 'none' for the default")
    args = parser.parse_args()
    print(f"{'sight':>6s} {'policy':9s} {'decisions':>9s} {'median':>7s} {'world CV':>8s} {'Local':>7s} {'pace':>5s} "
          f"{'return':>8s} {'border':>6s} {'collide':>7s}   ({args.worlds} test worlds)")
    rows = [("random", None)] + [("scripted", parse_sight(s)) for s in args.sights.split(",")]
    for policy, sight in rows:
        r = lives(sight, policy, args.worlds)
        label = "any" if sight is None else f"{sight:g}"
        print(f"{label:>6s} {policy:9s} {r['decisions']:9.1f} {r['median']:7.1f} {r['world_cv']:8.2f} {r['local']:7.1f} "
              f"{r['pace']:5.2f} {r['return']:8.1f} {r['border']:6.2f} {r['collision']:7.2f}", flush=True)


if __name__ == "__main__":
    main()
