"""The scripted fire officer: keeps or gives by the task's weights, and earns more than random shuffling."""

from __future__ import annotations

import numpy as np
import pytest

import hivex_dsl
from hivex_dsl.envs.wildfire_resource_management.params import WildfireResourceParams
from hivex_dsl.envs.wildfire_resource_management.scripted import (candidate_distances, candidate_offsets,
                                                                   estimated_performance, keep_all)
from hivex_dsl.evaluation.report import collect_returns

SEEDS = (6000, 6001)


@pytest.fixture(scope="module")
def runs():
    """{task: {policy: [(returns (1, 9), term sums), ...] per seed}} over one test episode per seed."""
    tasks = {}
    for task in ("main", "distribute_all"):
        compiled = hivex_dsl.compile(f"wildfire_resource_management/{task}")
        tasks[task] = {policy: [collect_returns(compiled, policy, episodes=1, split="test", seed=seed)
                                for seed in SEEDS] for policy in ("scripted", "random")}
    return tasks


@pytest.mark.parametrize("task", ["main", "distribute_all"])
def test_scripted_beats_random_on_every_seed(runs, task):
    for (scripted, _), (random, _) in zip(runs[task]["scripted"], runs[task]["random"]):
        assert scripted.mean() > random.mean()


def test_the_gain_comes_from_the_terms_the_actions_change(runs):
    """Giving everything earns more of the neighbour term than random shuffling, and the collective term, which
    reads what each tower holds, more too: the officer allocates all it may (nine tenths) where random towers end
    their episodes holding about three quarters of a share (39.9 and 86.5 against 24.1 and 43.7 a tower on the two
    test fires)."""
    for (_, scripted), (_, random) in zip(runs["distribute_all"]["scripted"], runs["distribute_all"]["random"]):
        assert scripted["neighbour_performance"].sum() > random["neighbour_performance"].sum()
        assert scripted["collective_performance"].sum() > 1.5 * random["collective_performance"].sum()


def test_candidate_distances_and_approach_from_the_towers_own_view():
    candidates = candidate_offsets(450.0)  # centre tower 4: self (0, 0), towers 1 (0, -450), 3 (-450, 0), 5 (450, 0)
    assert candidates[4].tolist() == [[0, 0], [0, -450], [-450, 0], [450, 0]]
    now, before = np.zeros((1, 9, 3)), np.zeros((1, 9, 3))
    now[0, 4], before[0, 4] = (300.0, 0.0, 40.0), (320.0, 0.0, 40.0)  # moving west, toward the centre
    seen = np.ones((1, 9), bool)
    distance, approaching = candidate_distances(now, before, seen, seen, candidates)
    # own: 3-D sqrt(300^2 + 40^2) = 302.65; tower 1: hypot(300, 450) = 540.83; tower 3: 750; tower 5: 150
    np.testing.assert_allclose(distance[0, 4], [302.6549, 540.8327, 750.0, 150.0], atol=1e-4)
    # before: own sqrt(320^2 + 40^2) = 322.49 (shrank); tower 1 hypot(320, 450) = 552.18 (shrank); tower 3
    # 770 (shrank); tower 5: 130 (grew)
    assert approaching[0, 4].tolist() == [True, True, True, False]
    unseen = ~seen
    distance, approaching = candidate_distances(now, before, unseen, seen, candidates)
    assert np.isinf(distance).all() and not approaching.any()
    _, approaching = candidate_distances(now, before, seen, unseen, candidates)  # just came into view
    assert approaching.all()


def test_estimated_performance_is_the_law_within_the_threshold_only():
    params = WildfireResourceParams()
    distance = np.array([[[100.0, 100.0, 250.0, np.inf]]])
    approaching = np.array([[[True, False, True, False]]])
    # 100 m approaching: d' = 0.25, (0.925926)^5 = 0.680583 -> 1.680583^-0.5 = 0.7713829;
    # 100 m receding: d' = 0.75, (2.777778)^5 = 165.38104 -> 166.38104^-0.5 = 0.0775260; beyond 200 m: 0
    np.testing.assert_allclose(estimated_performance(distance, approaching, params)[0, 0],
                               [0.7713829, 0.0775260, 0.0, 0.0], atol=1e-6)


def test_keep_or_give_compares_the_weighted_corners():
    """Giving splits the share over three neighbours, each paying its performance for its third: their mean P."""
    performance = np.array([[[0.5, 0.1, 0.1, 0.1], [0.2, 0.3, 0.0, 0.0], [0.0, 0.0, 0.0, 0.0],
                             [0.2, 0.9, 0.0, 0.0]]])
    # main (1, 1): 0.5 > 0.1 keeps; 0.2 > 0.1 keeps; nothing in range: 1 > 1 is false, gives; 0.2 < 0.3 gives
    assert keep_all(performance, 1.0, 1.0).tolist() == [[True, True, False, False]]
    # keep_all (10, 1): 5 > 0.1, 2 > 0.1, idle 10 > 1, 2 > 0.3: keeps
    assert keep_all(performance, 10.0, 1.0).tolist() == [[True, True, True, True]]
    # distribute_all (1, 10): 0.5 < 1, 0.2 < 1, idle gives, 0.2 < 3
    assert keep_all(performance, 1.0, 10.0).tolist() == [[False, False, False, False]]


def test_under_the_readings_before_the_neighbours_p_counted_summed():
    performance = np.array([[[0.5, 0.1, 0.1, 0.1], [0.2, 0.3, 0.0, 0.0], [0.0, 0.0, 0.0, 0.0]]])
    # main (1, 1): 0.5 > 0.3 keeps; 0.2 < 0.3 gives; nothing in range: 1 > 3 * 1 is false, gives
    assert keep_all(performance, 1.0, 1.0, given_each=False).tolist() == [[True, False, False]]
    # keep_all (10, 1): 5 > 0.3, 2 > 0.3; nothing in range: 10 > 3 keeps
    assert keep_all(performance, 10.0, 1.0, given_each=False).tolist() == [[True, True, True]]
    # distribute_all (1, 10): 0.5 < 3, 0.2 < 3, idle gives
    assert keep_all(performance, 1.0, 10.0, given_each=False).tolist() == [[False, False, False]]


@pytest.mark.parametrize("task, keeps", [("keep_all", True), ("distribute_all", False)])
def test_the_resource_ends_where_the_task_pays(task, keeps):
    """Towers that have seen no fire (within 600 m) hold everything they can allocate in keep_all and give it in
    distribute_all after twelve steps (nine tenths move in at most nine; the tenth stays, allocatable_tenths 9)."""
    compiled = hivex_dsl.compile(f"wildfire_resource_management/{task}")
    sim = compiled.entry.make_simulator(compiled)
    policy = compiled.entry.scripted_policy(compiled)
    rng = np.random.default_rng(6000)
    state = sim.reset(rng, 1)
    idle = ~state.sighting.seen[0]
    for _ in range(12):
        state, _ = sim.step(state, policy(sim.observe(state)), rng)
        idle &= ~state.sighting.seen[0]
    own, given = state.allocation[0, :, 0], state.allocation[0, :, 1:].sum(axis=-1)
    assert idle.any()
    assert compiled.params.allocatable_tenths == 9
    if keeps:
        assert np.all(own[idle] == 9)
    else:
        assert np.all(given[idle] == 9)
    np.testing.assert_array_equal(state.budget[0], 10 - state.allocation[0].sum(axis=-1))
    assert state.budget[0].min() == 1
