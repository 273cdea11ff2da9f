"""Ocean Plastic Collection: how far apart vessels keep and how widely each roams, for any policy (issue 52).

The original's trained worlds crash about six times a thousand world-decisions; this toolkit's trained vessels,
seeing their neighbours or blind to them (params.neighbour_sight_m 0), about four, while collectors that do not
dodge (the scripted skipper blind to its neighbours) crash at the original's rate (the reward table's note on blind
vessels). Vessels that do not dodge meet by chance, and how often depends on where they go: apart or together, each
in a corner of the map or across all of it. This plays a policy on the main task's test worlds and reads, at every
decision, each vessel's position (its vector observation's first two components times the half extent):

- the distance between every pair of a world's vessels, its mean and the share of pairs within ``NEAR_M``;
- each vessel's stray, its mean distance from its own mean position over a world-episode (a vessel keeping to a
  patch strays little, one crossing the map much);
- beside them, what vessels placed uniformly and independently on the square would give: a mean pair distance of
  0.5214 of the side (the square line picking constant) and a mean distance from the centre of 0.3826 of it.

    python benchmarks/opc_territory.py [--checkpoint PT ...] [--policies scripted,random] [--worlds N]
        [--params '{"neighbour_sight_m": 0}']

Each row: the policy, its world-episodes' mean life (decisions), world-crashes a thousand world-decisions, the mean
pair distance, the share of pairs within ``NEAR_M`` and the mean stray.
"""

from __future__ import annotations

import argparse
import json
import sys
from typing import Any, Callable

import numpy as np

import hivex_dsl
from hivex_dsl.evaluation.rollout import rollout

ENV = "ocean_plastic_collection"
NEAR_M = 40.0
PAIR_MEAN_OF_SIDE = 0.5214054  # E|X - Y| for X, Y uniform on the unit square
CENTRE_MEAN_OF_SIDE = 0.3825978  # E|X - centre| for X uniform on the unit square


def main_task(params: dict[str, Any]) -> hivex_dsl.CompiledScenario:
    spec = {"hivex": 1, "environment": ENV, "task": 0, "agents": 3, "episode_length": 5000,
            "seeds": {"train": 5000, "test": 6000}}
    return hivex_dsl.compile({**spec, "params": params} if params else spec)


def pair_distances(positions: np.ndarray) -> np.ndarray:
    """(T, A, 2) positions -> (T, A (A - 1) / 2) the distance between every pair of vessels at every decision."""
    first, second = np.triu_indices(positions.shape[1], k=1)
    return np.linalg.norm(positions[:, first] - positions[:, second], axis=-1)


def strays(positions: np.ndarray) -> np.ndarray:
    """(T, A, 2) one world-episode's positions -> (A,) each vessel's mean distance from its own mean position."""
    return np.linalg.norm(positions - positions.mean(axis=0), axis=-1).mean(axis=0)


def recording(act: Callable[..., Any], half_extent: float) -> tuple[Callable[..., Any], list[np.ndarray]]:
    """A policy that logs each decision's (A, 2) positions in metres before acting as ``act`` does."""
    log: list[np.ndarray] = []

    def policy(observations: Any, *rest: Any, **named: Any) -> Any:
        log.append(np.asarray(observations["vector"])[0, :, 0:2] * half_extent)
        return act(observations, *rest, **named)

    if getattr(act, "takes_action_mask", False):
        policy.takes_action_mask = True  # type: ignore[attr-defined]
    return policy, log


def named_policy(name: str, compiled: hivex_dsl.CompiledScenario) -> Callable[..., Any]:
    """'scripted' or 'random' as a callable, or a checkpoint's sampled policy."""
    if name in ("scripted", "random"):
        from hivex_dsl.evaluation.policies import make_policy
        from hivex_dsl.runtime.batched import BatchedEnv

        core = BatchedEnv(compiled, batch=1, split="test")
        return make_policy(name, compiled, core.sim.action_space, core.shape, seed=1)
    from hivex_dsl.train.evaluate import checkpoint_policies

    return checkpoint_policies(name)(compiled)


def territory(compiled: hivex_dsl.CompiledScenario, act: Callable[..., Any], worlds: int) -> dict[str, float]:
    """The module's row for one policy over ``worlds`` test worlds."""
    half_extent = compiled.generators["pollution"].half_extent_m
    policy, log = recording(act, half_extent)
    played = rollout(compiled, policy, worlds, seed=1)
    lives = played.decisions.max(axis=1)  # a crash ends its world: every vessel lives the world's life
    positions = np.array(log)
    if len(positions) != lives.sum():
        raise RuntimeError(f"logged {len(positions)} decisions, the episodes hold {lives.sum()}")
    episodes = np.split(positions, np.cumsum(lives)[:-1])
    pairs = pair_distances(positions)
    return {"life": float(lives.mean()), "crashes": 1000.0 * worlds / float(lives.sum()),
            "pair_m": float(pairs.mean()), "near": float(np.mean(pairs < NEAR_M)),
            "stray_m": float(np.mean([strays(e) for e in episodes if len(e) > 1]))}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--checkpoint", action="append", default=[], help="a trained policy (repeatable)")
    parser.add_argument("--policies", default="scripted,random", help="scripted and/or random, comma-separated")
    parser.add_argument("--worlds", type=int, default=16)
    parser.add_argument("--params", default="{}", help="the scenario's params, as JSON")
    args = parser.parse_args(argv)
    compiled = main_task(json.loads(args.params))
    side = 2 * compiled.generators["pollution"].half_extent_m
    print(f"uniform and independent on the {side:.0f} m square: pair distance {PAIR_MEAN_OF_SIDE * side:.0f} m, "
          f"distance from the centre {CENTRE_MEAN_OF_SIDE * side:.0f} m")
    names = [*args.checkpoint, *(p for p in args.policies.split(",") if p)]
    for name in names:
        row = territory(compiled, named_policy(name, compiled), args.worlds)
        print(f"{name}: life {row['life']:.0f}, {row['crashes']:.1f} crashes a thousand world-decisions, pair "
              f"distance {row['pair_m']:.0f} m ({row['near']:.0%} within {NEAR_M:.0f} m), stray {row['stray_m']:.0f} m")
    return 0


if __name__ == "__main__":
    sys.exit(main())
