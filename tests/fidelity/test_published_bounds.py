"""Every environment against the paper's published test results at level 1 (issue 15).

For every published cell whose PPO return is above 0.5, the all-zeros and the uniform random policy
stay below PPO x 1.1 and the scripted policy reaches at least half of it. Each policy's return is
the mean per-agent return of the first episodes of the test seed stream (seed 6000), two (sixteen for
Aerial Wildfire Suppression's random policy), rolled one after the other in one world (each episode
draws its own world); the random policy is seeded 0.
Level 1 is terrain level 1, or layout pattern 0 for Wind Farm Control. WRM and OPC, whose files
beside this one also check which published statistics fire, carry their own bounds there.
"""

from __future__ import annotations

from functools import lru_cache

import pytest

import hivex_dsl
from hivex_dsl.evaluation import published
from hivex_dsl.evaluation.rollout import rollout

EPISODES = 2
# AWS's returns have a heavy tail: under the release's fire (fire_start and burn_list 'release', issue 52's
# session 89) one random drop on a dense fire at level 1 wets about 125 burning trees, 6,250 at task 1's x50,
# and the second test episode holds one: 1,033 over two episodes, 197 over sixteen, 152 over 24 (published PPO
# 817.8). The original's first training points show such drops too (Extinguishing Trees 9.6 an episode at level
# 6 after 27,000 agent-steps); ours average 0.48 an episode over the first 50,000 (session 89's note).
EPISODES_OF = {("aerial_wildfire_suppression", "random"): 16}
LEVEL_KEY = {"wind_farm_control": ("pattern", 0), "drone_based_reforestation": ("terrain_level", 1),
             "aerial_wildfire_suppression": ("terrain_level", 1)}
# The published cells above 0.5 at level 1, read by hand from the results file: DBR has no result for
# task 2 (Group Up) and published -0.02 for task 5; AWS published -69.6 for task 4 (Protect Village).
EXPECTED_TASKS = {"wind_farm_control": [0, 1], "drone_based_reforestation": [0, 1, 3, 4, 6, 7],
                  "aerial_wildfire_suppression": [0, 1, 2, 3, 5, 6, 7, 8]}


def _cells(env: str) -> list:
    level = LEVEL_KEY[env][1]
    return [c for c in published.cells(env) if c.level == level and c.return_mean > 0.5]


CELLS = [cell for env in LEVEL_KEY for cell in _cells(env)]


def _id(cell) -> str:
    return f"{cell.environment}-task{cell.task_index}"


@lru_cache(maxsize=None)
def mean_return(env: str, task: int, policy: str) -> float:
    key, level = LEVEL_KEY[env]
    compiled = hivex_dsl.compile({"hivex": 1, "environment": env, "task": task, key: level})
    return float(rollout(compiled, policy, EPISODES_OF.get((env, policy), EPISODES), split="test").returns.mean())


@pytest.mark.parametrize("env", sorted(LEVEL_KEY))
def test_the_cells_under_test_are_the_published_positive_ones(env):
    assert [c.task_index for c in _cells(env)] == EXPECTED_TASKS[env]


@pytest.mark.parametrize("policy", ["zeros", "random"])
@pytest.mark.parametrize("cell", CELLS, ids=_id)
def test_a_trivial_policy_does_not_beat_the_published_ppo(cell, policy):
    mean = mean_return(cell.environment, cell.task_index, policy)
    assert mean < 1.1 * cell.return_mean, f"{policy} {mean:.2f} vs published {cell.return_mean:.2f}"


@pytest.mark.parametrize("cell", CELLS, ids=_id)
def test_the_scripted_policy_reaches_half_the_published_ppo(cell):
    mean = mean_return(cell.environment, cell.task_index, "scripted")
    assert mean >= 0.5 * cell.return_mean, f"scripted {mean:.2f} vs published {cell.return_mean:.2f}"
