"""The scripted fire officer earns more than random resource shuffling, over the same seeds."""

from __future__ import annotations

import numpy as np
import pytest

import hivex_dsl
from hivex_dsl.envs.wildfire_resource_management.resources import TARGETS
from hivex_dsl.envs.wildfire_resource_management.scripted import candidate_offsets, choose_targets
from hivex_dsl.report import collect_returns

SEEDS = (6000, 6001)


@pytest.fixture(scope="module")
def main_task():
    return hivex_dsl.compile("wildfire_resource_management/main")


@pytest.fixture(scope="module")
def runs(main_task):
    """{policy: [(returns (1, 9), term sums), ...] per seed} over one test episode per seed."""
    return {policy: [collect_returns(main_task, policy, episodes=1, split="test", seed=seed) for seed in SEEDS]
            for policy in ("scripted", "random")}


def test_scripted_beats_random_on_the_main_task_on_every_seed(runs):
    for (scripted, _), (random, _) in zip(runs["scripted"], runs["random"]):
        assert scripted.mean() > random.mean()


def test_the_gain_comes_from_the_watch_tower_term_the_only_one_actions_change(runs):
    for (_, scripted), (_, random) in zip(runs["scripted"], runs["random"]):
        assert scripted["watch_tower_performance"].sum() > 3.0 * random["watch_tower_performance"].sum()
        np.testing.assert_allclose(scripted["neighbour_performance"], random["neighbour_performance"])
        np.testing.assert_allclose(scripted["collective_performance"], random["collective_performance"])


def test_the_target_is_the_candidate_nearest_an_approaching_fire():
    candidates = candidate_offsets(450.0)  # centre tower 4: self (0, 0), towers 1 (0, -450), 3 (-450, 0), 5 (450, 0)
    assert candidates[4].tolist() == [[0, 0], [0, -450], [-450, 0], [450, 0]]
    seen = np.ones((1, 9), bool)

    def target(now, before, seen_before=seen):
        fire_now, fire_before = np.zeros((1, 9, 2)), np.zeros((1, 9, 2))
        fire_now[0, 4], fire_before[0, 4] = now, before
        return int(choose_targets(fire_now, fire_before, seen, seen_before, candidates)[0, 4])

    # moving east toward tower 5: 70.7 m -> 51 m from it, receding from the centre
    assert target((400.0, 10.0), (380.0, 10.0)) == 3 and TARGETS[4, 3] == 5
    # moving west: away from tower 5; the nearest it approaches is the centre itself (400 m)
    assert target((400.0, 10.0), (420.0, 10.0)) == 0
    # south-west of the centre, closing on tower 1 (327.6 m -> 304.1 m), not on the centre or tower 3
    assert target((-300.0, -400.0), (-320.0, -380.0)) == 1 and TARGETS[4, 1] == 1
    # a fire that just came into view approaches every candidate: the nearest one, tower 5
    assert target((400.0, 10.0), (0.0, 0.0), seen_before=~seen) == 3
    # moving away from every candidate, or no fire at all: keep everything
    assert target((500.0, 0.0), (480.0, 0.0)) == 0
    assert int(choose_targets(np.zeros((1, 9, 2)), np.zeros((1, 9, 2)), ~seen, ~seen, candidates)[0, 4]) == 0
