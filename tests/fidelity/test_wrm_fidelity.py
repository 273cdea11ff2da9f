"""Wildfire Resource Management against the paper's published test results at terrain level 1.

For every published cell at level 1 whose PPO return is above 0.5, trivial policies (all-zeros,
uniform random) must stay below the published return plus 10%, and the scripted policy must reach
half of it. The two episodes are those of the paper's test protocol: one world on the test seed
stream (6000), its first two episodes in a row (``hivex_dsl.evaluation.rollout.rollout``: the second keeps the
island and lights a new fire), each policy's mean per-agent return over both.
"""

from __future__ import annotations

from functools import lru_cache

import pytest

import hivex_dsl
from hivex_dsl.evaluation.published import cells
from hivex_dsl.evaluation.rollout import rollout

ENVIRONMENT = "wildfire_resource_management"
EPISODES = 2
MARGIN = 1.1
CELLS = [c for c in cells(ENVIRONMENT) if c.level == 1 and c.return_mean > 0.5]
NEIGHBOURS, SELF = "Reward for Moving Resources to Neighbours", "Reward for Moving Resources to Self"


@lru_cache(maxsize=None)
def episodes(task: int, policy: str):
    compiled = hivex_dsl.compile({"hivex": 1, "environment": ENVIRONMENT, "task": task, "terrain_level": 1,
                                  "agents": 9, "episode_length": 500, "seeds": {"train": 5000, "test": 6000}})
    return rollout(compiled, policy, EPISODES, split="test")


def test_every_task_has_a_published_level_one_cell():
    assert [c.task_index for c in CELLS] == [0, 1, 2]


@pytest.mark.parametrize("policy", ["zeros", "random"])
@pytest.mark.parametrize("cell", CELLS, ids=lambda c: f"task{c.task_index}")
def test_a_trivial_policy_stays_below_the_published_ppo(cell, policy):
    mean = episodes(cell.task_index, policy).returns.mean()
    assert mean < MARGIN * cell.return_mean, f"{policy} {mean:.1f} vs published {cell.return_mean:.1f}"


@pytest.mark.parametrize("cell", CELLS, ids=lambda c: f"task{c.task_index}")
def test_the_scripted_policy_reaches_half_the_published_ppo(cell):
    mean = episodes(cell.task_index, "scripted").returns.mean()
    assert mean >= 0.5 * cell.return_mean, f"scripted {mean:.1f} vs published {cell.return_mean:.1f}"


@pytest.mark.parametrize("cell", CELLS, ids=lambda c: f"task{c.task_index}")
def test_the_scripted_policy_is_paid_by_the_terms_the_published_policy_was(cell):
    """Published: task 0 and 2 pay for giving (Neighbours 49.4 and 513 against Self 0.2), task 1 for keeping
    (Self 143 against Neighbours 1.3). The scripted officer follows the task's weights the same way, so
    keeping everything is not best in every task."""
    published = {name: cell.statistic(name)[0] for name in (NEIGHBOURS, SELF)}
    ours = {name: episodes(cell.task_index, "scripted").statistics[name].mean() for name in (NEIGHBOURS, SELF)}
    assert (published[NEIGHBOURS] > published[SELF]) == (ours[NEIGHBOURS] > ours[SELF])


def test_collective_performance_does_not_depend_on_the_task_or_the_policy():
    """Published Collective Performance at level 1 is 34.5, 34.3 and 34.2 in the three tasks, whose policies
    keep or give almost everything: the term reads no action. Ours pays the same to every policy."""
    published = [c.statistic("Collective Performance")[0] for c in CELLS]
    assert max(published) - min(published) < 0.02 * max(published)
    ours = {episodes(task, policy).statistics["Collective Performance"].mean()
            for task in (0, 2) for policy in ("zeros", "random", "scripted")}
    assert max(ours) - min(ours) < 1e-9 * max(ours)


# Issue 52, item 7: the original's Episode Length and Collective Performance curves at terrain level 7, averaged
# over its training (three runs), read from original-plots/WildfireResourceManagement/*_difficulty_7_task_0.pdf
ORIGINAL_LEVEL7_EPISODE_LENGTH = 204.1
ORIGINAL_LEVEL7_COLLECTIVE = 50.4


def test_this_fire_burns_longer_than_the_originals_with_the_same_yield_per_step():
    """Why a trivial policy earns more than the published PPO at levels 6, 7, 9 and 10 (the reward table's notes):
    the fire lasts longer here, each of its steps yielding the original's Collective Performance per step."""
    compiled = hivex_dsl.compile({"hivex": 1, "environment": ENVIRONMENT, "terrain_level": 7, "agents": 9,
                                  "episode_length": 500, "seeds": {"train": 5000, "test": 6000}})
    done = rollout(compiled, "zeros", 20, split="test")
    lengths, collective = done.lengths[:, 0], done.statistics["Collective Performance"][:, 0]
    spread = lengths.std() / len(lengths) ** 0.5
    assert lengths.mean() - 2 * spread > 1.1 * ORIGINAL_LEVEL7_EPISODE_LENGTH  # at least a tenth longer
    per_step = collective.sum() / lengths.sum()
    assert per_step == pytest.approx(ORIGINAL_LEVEL7_COLLECTIVE / ORIGINAL_LEVEL7_EPISODE_LENGTH, rel=0.05)
