"""Time every environment's step, observation (cameras included), one world's restart and top-down render:
``python benchmarks/bench_observe.py`` (about a minute; island generation dominates the setup).

Plain script, not collected by pytest. For each registered environment's main scenario it
prints the median wall time of ``step``, ``observe`` and ``reset_where`` of one world (a new episode
continuing the seed stream, on a kept island where the environment keeps one) at batch 1 and batch 256,
and of ``render`` of one world, after a few random steps so fires, pebbles and drones are in play.
Some simulators draw their cameras in ``step`` (Ocean Plastic Collection bins pebbles there,
Aerial Wildfire Suppression reads its kept palette image there), others in ``observe``, so read the
two together.
"""

from __future__ import annotations

import numpy as np

import hivex_dsl
from hivex_dsl.evaluation.policies import random_policy
from hivex_dsl.compiler.registry import environments
from hivex_dsl.evaluation.bench import bench_scenario

from bench_procgen import median_ms

BATCHES = (1, 256)


def stepped_state(env_id: str, batch: int):
    """(simulator, state, actions, rng) of ``batch`` worlds after 20 random steps."""
    compiled = bench_scenario(env_id)  # cameras drawn: the blank default skips them
    sim = compiled.entry.make_simulator(compiled)
    rng = np.random.default_rng(0)
    policy = random_policy(sim.action_space, (batch, compiled.agents), rng)
    state = sim.reset(rng, batch)
    for _ in range(20):
        state, _ = sim.step(state, policy(None), rng)
    return sim, state, policy(None), rng


def main() -> None:
    print(f"{'environment':<32} {'case':<22} {'median ms':>10}")
    for env_id in environments():
        for batch in BATCHES:
            sim, state, actions, rng = stepped_state(env_id, batch)
            print(f"{env_id:<32} {f'step, batch {batch}':<22} {median_ms(lambda: sim.step(state, actions, rng), 10):>10.2f}")
            print(f"{env_id:<32} {f'observe, batch {batch}':<22} {median_ms(lambda: sim.observe(state), 10):>10.2f}")
            first = np.arange(batch) == 0
            print(f"{env_id:<32} {f'restart 1, batch {batch}':<22} "
                  f"{median_ms(lambda: sim.reset_where(state, first, rng), 10):>10.2f}")
        print(f"{env_id:<32} {'render one world':<22} {median_ms(lambda: sim.render(state, 0), 5):>10.2f}")


if __name__ == "__main__":
    main()
