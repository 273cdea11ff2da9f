"""Wind Farm Control against the paper's published test results at layout pattern 0 (Default) (issue 15).

For every published cell whose PPO return is above 0.5, the all-zeros and the uniform random policy
stay below PPO x 1.1 and the scripted policy reaches at least half of it. Each policy's return is
the mean per-agent return of the first two episodes of the test seed stream (seed 6000), rolled one
after the other in one world (each episode draws its own wind); the random policy is seeded 0.
"""

from __future__ import annotations

from functools import lru_cache

import pytest

import hivex_dsl
from hivex_dsl import published
from hivex_dsl.rollout import rollout

ENV, LEVEL, EPISODES = "wind_farm_control", 0, 2
CELLS = [c for c in published.cells(ENV) if c.level == LEVEL and c.return_mean > 0.5]


@lru_cache(maxsize=None)
def mean_return(task: int, policy: str) -> float:
    compiled = hivex_dsl.compile({"hivex": 1, "environment": ENV, "task": task, "pattern": LEVEL})
    return float(rollout(compiled, policy, EPISODES, split="test").returns.mean())


def test_the_cells_under_test_are_the_published_positive_ones():
    assert [c.task_index for c in CELLS] == [0, 1]


@pytest.mark.parametrize("policy", ["zeros", "random"])
@pytest.mark.parametrize("cell", CELLS, ids=lambda c: f"task{c.task_index}")
def test_a_trivial_policy_does_not_beat_the_published_ppo(cell, policy):
    mean = mean_return(cell.task_index, policy)
    assert mean < 1.1 * cell.return_mean, f"{policy} {mean:.2f} vs published {cell.return_mean:.2f}"


@pytest.mark.parametrize("cell", CELLS, ids=lambda c: f"task{c.task_index}")
def test_the_scripted_policy_reaches_half_the_published_ppo(cell):
    mean = mean_return(cell.task_index, "scripted")
    assert mean >= 0.5 * cell.return_mean, f"scripted {mean:.2f} vs published {cell.return_mean:.2f}"
