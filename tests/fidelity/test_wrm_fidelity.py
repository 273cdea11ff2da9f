"""Wildfire Resource Management against the paper's published test results at terrain level 1, and its fire
against the original's own curves at every level.

For every published cell at level 1 whose PPO return is above 0.5, trivial policies (all-zeros,
uniform random) must stay below the published return plus 10%, and the scripted policy must reach
half of it. Ten episodes, as the audit suite plays: one world on the test seed stream (6000), its first ten
episodes in a row (``hivex_dsl.evaluation.rollout.rollout``), each policy's mean per-agent return over them. The
original's test logged about 24 fires (10 summary points of 500 steps); two episodes were too few here, the test
seed's second fire at level 1 going out after 55 steps.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np
import pytest

import hivex_dsl
from hivex_dsl.evaluation.original import evidence
from hivex_dsl.evaluation.original.evidence import EPISODE_LENGTH
from hivex_dsl.evaluation.published import cells
from hivex_dsl.evaluation.rollout import rollout
from hivex_dsl.runtime.batched import BatchedEnv

ENVIRONMENT = "wildfire_resource_management"
EPISODES = 10
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


def test_collective_performance_reads_what_the_towers_hold():
    """Published Collective Performance at level 1 is 34.5, 34.3 and 34.2 in the three tasks, whose trained towers
    all hold about 0.85-0.89 of a share as their episodes end (the original's pages); point by point on the same
    fires the tasks differ (tests/fidelity/test_wrm_resource_records.py), so the term reads the resources. Ours:
    all-zeros towers hold nothing and earn none of it, random towers (about 0.75 held) less than the officer, who
    allocates all it may; with P alone (performance_weight 'none') every policy earns the same."""
    published = [c.statistic("Collective Performance")[0] for c in CELLS]
    assert max(published) - min(published) < 0.02 * max(published)
    for task in (0, 2):
        collective = {policy: episodes(task, policy).statistics["Collective Performance"].mean()
                      for policy in ("zeros", "random", "scripted")}
        assert collective["zeros"] == 0.0 < collective["random"] < collective["scripted"], collective
    fire_only = {_fire_only_collective(policy) for policy in ("zeros", "random", "scripted")}
    assert max(fire_only) - min(fire_only) < 1e-9 * max(fire_only)


def _fire_only_collective(policy: str) -> float:
    compiled = hivex_dsl.compile({"hivex": 1, "environment": ENVIRONMENT, "terrain_level": 1, "episode_length": 500,
                                  "params": {"performance_weight": "none"}})
    return float(rollout(compiled, policy, 2, split="test").statistics["Collective Performance"].mean())


# Issue 52, item 4: the fire's length per level against the original's Episode Length, averaged over its training
# (hivex_dsl.evaluation.original.evidence.training_average; the three runs and three tasks log one curve per level,
# so every point, the untrained first one included, samples the same fires whatever the policy).
LEVELS = range(1, 11)
FIRST_FIRES = 8  # worlds a level, each its first episode: 80 fires, about 5% standard error on their pooled ratio
POOLED_TOLERANCE = 0.12  # today's main (spread chance 0.2) pooled 1.17 here, 1.22 over 100 fires a level
LEVEL_TOLERANCE = 0.30  # one level's 8 fires: up to about 20% standard error (level 1's fires vary most)
YIELD_TOLERANCE = 0.12


@lru_cache(maxsize=None)
def first_fires(level: int) -> tuple[np.ndarray, np.ndarray]:
    """(lengths (W,), Collective Performance (W,)) of the first episode of W worlds of the training seed stream,
    all-zeros, with a tower's performance its P alone (performance_weight 'none': every tower counts as holding one
    share), so no action changes either: the fire's own length and yield."""
    compiled = hivex_dsl.compile({"hivex": 1, "environment": ENVIRONMENT, "terrain_level": level, "agents": 9,
                                  "episode_length": 500, "seeds": {"train": 5000, "test": 6000},
                                  "params": {"performance_weight": "none"}})
    env = BatchedEnv(compiled, batch=FIRST_FIRES, split="train")
    env.reset()
    actions = np.zeros((FIRST_FIRES, compiled.agents, 4), np.int64)
    while env.alive.any():
        env.step(actions)
    return env.lengths[:, 0].copy(), env.statistic_sums()["Collective Performance"][:, 0].copy()


def original(level: int, panel: str) -> float:
    return evidence.training_average(ENVIRONMENT, 0, level, panel)


def test_the_fire_lasts_as_long_as_the_originals_at_every_level():
    """The original logs a mean over the episodes that ended in each 500-step window, which weighs long fires a
    little more (1% to 6% above the mean over fires here, measured by running worlds as such streams); the
    tolerances take that in."""
    ratios = np.array([first_fires(level)[0].mean() / original(level, EPISODE_LENGTH) for level in LEVELS])
    assert abs(ratios.mean() - 1.0) < POOLED_TOLERANCE, np.round(ratios, 2)
    assert (abs(ratios - 1.0) < LEVEL_TOLERANCE).all(), np.round(ratios, 2)


def test_each_step_of_the_fire_yields_the_originals_collective_performance():
    """The fire's own yield (P alone) against the original's trained towers' Collective Performance a step, from
    level 4 on (at levels 1-3 ours is lower, 0.21-0.24 against 0.27-0.28 a step: the reward table's notes). With
    the resources read and nine tenths allocatable (the defaults), trained towers here yield 0.201-0.230 a step at
    level 1 (the main record's seeds) and 0.242 at level 5 (the grid's point) over the second half of training,
    against the original's 0.256 and 0.264 (the note on the towers' resources)."""
    ratios = []
    for level in LEVELS[3:]:
        lengths, collective = first_fires(level)
        ratios.append((collective.sum() / lengths.sum())
                      / (original(level, "Collective Performance") / original(level, EPISODE_LENGTH)))
    assert abs(np.mean(ratios) - 1.0) < YIELD_TOLERANCE, np.round(ratios, 2)
