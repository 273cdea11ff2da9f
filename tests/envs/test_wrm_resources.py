"""Wildfire Resource Management: the neighbour table and the bookkeeping of the towers' resources."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from hypothesis.extra.numpy import arrays

import hivex_dsl
from hivex_dsl.envs.wildfire_resource_management.resources import (
    ADD, NEIGHBOURS, NOOP, SUBTRACT, TARGETS, apply_actions, apply_in_order, grid_offsets, initial_resources,
    total_support)

# Towers 3 * row + col on the 3 x 3 grid (row 0 south):   6 7 8 / 3 4 5 / 0 1 2.
# Neighbours by distance, ties to the lower index. Corners: the two edge towers (distance s), then
# the centre (s * sqrt(2)); edges: their three towers at s; the centre: four at s, 7 dropped.
PAPER_GRID_NEIGHBOURS = [
    [1, 3, 4],
    [0, 2, 4],
    [1, 5, 4],
    [0, 4, 6],
    [1, 3, 5],
    [2, 4, 8],
    [3, 7, 4],
    [4, 6, 8],
    [5, 7, 4],
]


def test_neighbour_table_is_the_documented_one():
    assert NEIGHBOURS.tolist() == PAPER_GRID_NEIGHBOURS


def test_the_process_figure_s_neighbourhoods_are_the_table_s():
    """hivex-environments' docs/images/WRM_process.jpg (towers v0-v8 numbered as here, v0 south-west): v2 sends
    support to v1, v4 and v5, and the 'Neighbourhood' panel of v0 shows v1, v3 and v4."""
    assert set(NEIGHBOURS[2]) == {1, 4, 5} and set(NEIGHBOURS[0]) == {1, 3, 4}


def test_towers_stand_on_the_450_m_grid_in_row_major_order_from_the_south_west():
    metres = grid_offsets() * 450
    assert metres[0].tolist() == [-450, -450] and metres[2].tolist() == [450, -450]
    assert metres[4].tolist() == [0, 0] and metres[7].tolist() == [0, 450] and metres[8].tolist() == [450, 450]


def test_every_neighbour_is_at_least_as_near_as_every_tower_left_out():
    grid = grid_offsets()
    for tower, chosen in enumerate(NEIGHBOURS):
        distance = np.hypot(*(grid - grid[tower]).T)
        others = [t for t in range(9) if t != tower and t not in chosen]
        assert distance[chosen].max() <= distance[others].min()
        assert list(distance[chosen]) == sorted(distance[chosen])


def one_agent(budget: int, allocation: list[int]):
    """A batch of one world where agent 0 holds ``allocation`` (self, n1, n2, n3) and ``budget`` tenths."""
    alloc, free = initial_resources(1, 9, 0)
    alloc[0, 0] = allocation
    free[0, 0] = budget
    return alloc, free


def act(first: list[int]) -> np.ndarray:
    actions = np.zeros((1, 9, 4), np.int64)
    actions[0, 0] = first
    return actions


def test_add_without_budget_does_nothing_and_is_counted():
    alloc, budget = one_agent(0, [10, 0, 0, 0])
    new_alloc, new_budget, impossible = apply_actions(alloc, budget, act([ADD, NOOP, NOOP, NOOP]))
    assert new_alloc[0, 0].tolist() == [10, 0, 0, 0] and new_budget[0, 0] == 0 and impossible[0, 0] == 1


def test_subtract_from_an_empty_allocation_does_nothing_and_is_counted():
    alloc, budget = one_agent(7, [3, 0, 0, 0])
    new_alloc, new_budget, impossible = apply_actions(alloc, budget, act([NOOP, SUBTRACT, SUBTRACT, NOOP]))
    assert new_alloc[0, 0].tolist() == [3, 0, 0, 0] and new_budget[0, 0] == 7 and impossible[0, 0] == 2


def test_a_tenth_freed_earlier_in_the_branch_order_can_be_added_later():
    alloc, budget = one_agent(0, [10, 0, 0, 0])
    new_alloc, new_budget, impossible = apply_actions(alloc, budget, act([SUBTRACT, ADD, NOOP, NOOP]))
    assert new_alloc[0, 0].tolist() == [9, 1, 0, 0] and new_budget[0, 0] == 0 and impossible[0, 0] == 0


def test_a_tenth_freed_later_in_the_branch_order_comes_too_late():
    alloc, budget = one_agent(0, [9, 1, 0, 0])
    new_alloc, new_budget, impossible = apply_actions(alloc, budget, act([ADD, SUBTRACT, NOOP, NOOP]))
    assert new_alloc[0, 0].tolist() == [9, 0, 0, 0] and new_budget[0, 0] == 1 and impossible[0, 0] == 1


def test_the_last_tenth_of_budget_serves_only_the_first_add():
    alloc, budget = one_agent(1, [9, 0, 0, 0])
    new_alloc, new_budget, impossible = apply_actions(alloc, budget, act([NOOP, ADD, ADD, ADD]))
    assert new_alloc[0, 0].tolist() == [9, 1, 0, 0] and new_budget[0, 0] == 0 and impossible[0, 0] == 2


def test_total_support_adds_what_every_agent_gives_each_tower():
    alloc, _ = initial_resources(1, 9, 0)
    alloc[0, 4, 0] = 5  # the centre keeps 0.5
    alloc[0, 0, 3] = 3  # tower 0's neighbour 3 is the centre
    alloc[0, 1, 3] = 2  # tower 1's neighbour 3 is the centre
    alloc[0, 8, 1] = 4  # tower 8's neighbour 1 is tower 5
    support = total_support(alloc)[0]
    assert support.tolist() == [0, 0, 0, 0, 10, 4, 0, 0, 0]


@settings(max_examples=60, deadline=None)
@given(steps=st.lists(arrays(np.int64, (2, 9, 4), elements=st.integers(0, 2)), min_size=1, max_size=60),
       start=st.integers(0, 10))
def test_resources_are_conserved_under_any_action_sequence(steps, start):
    """Per agent: own allocation + given allocations + unallocated budget == 1.0 exactly, each part in [0, 1]."""
    alloc, budget = initial_resources(2, 9, start)
    counted = np.zeros((2, 9), np.int64)
    for actions in steps:
        before = alloc.copy(), budget.copy()
        alloc, budget, impossible = apply_actions(alloc, budget, actions)
        assert np.all(budget + alloc.sum(axis=-1) == 10)
        assert alloc.min() >= 0 and alloc.max() <= 10 and budget.min() >= 0 and budget.max() <= 10
        moved = np.abs(alloc.astype(int) - before[0]).sum(axis=-1)
        assert np.all(moved + impossible == (actions != NOOP).sum(axis=-1))  # each non-noop moves a tenth or counts
        counted += impossible
        support = total_support(alloc)
        assert np.all(support.sum(axis=-1) == alloc.sum(axis=(1, 2)))
    assert counted.min() >= 0


@settings(max_examples=100, deadline=None)
@given(parts=arrays(np.int64, (3, 9, 5), elements=st.integers(0, 10)),
       actions=arrays(np.int64, (3, 9, 4), elements=st.integers(0, 2)))
def test_the_step_table_applies_the_actions_in_order(parts, actions):
    """apply_actions looks each agent's case up; apply_in_order is the rule written out target by target."""
    share = parts * 10 // np.maximum(parts.sum(axis=-1, keepdims=True), 1)  # holdings that sum to at most 10
    alloc = share[..., :4].astype(np.int16)
    budget = (10 - alloc.sum(axis=-1)).astype(np.int16)
    for got, expected in zip(apply_actions(alloc, budget, actions), apply_in_order(alloc, budget, actions)):
        assert got.dtype == expected.dtype and got.shape == expected.shape
        np.testing.assert_array_equal(got, expected)


def test_the_simulator_keeps_the_books_and_the_observation_shows_them():
    # the budget observed as the eighth value (the default observes whether a fire is detected: test_wrm_world.py)
    compiled = hivex_dsl.compile({"hivex": 1, "environment": "wildfire_resource_management",
                                  "params": {"eighth_observation": "budget"}})
    sim = compiled.entry.make_simulator(compiled)
    rng = np.random.default_rng(11)
    state = sim.reset(rng, 2)
    assert np.all(state.budget == 10) and np.all(state.allocation == 0)
    total = np.zeros((2, 9))
    for _ in range(25):
        state, _ = sim.step(state, rng.integers(0, 3, (2, 9, 4)), rng)
        total += state.impossible
        assert np.all(state.budget + state.allocation.sum(axis=-1) == 10)
        support = np.zeros((2, 9))
        for agent in range(9):
            for slot, tower in enumerate(TARGETS[agent]):
                support[:, tower] += state.allocation[:, agent, slot]
        np.testing.assert_array_equal(state.support, support)
        obs = sim.observe(state)
        np.testing.assert_allclose(obs[..., 6], support / 90.0, rtol=1e-6)
        np.testing.assert_allclose(obs[..., 7], state.budget / 10.0, rtol=1e-6)
    np.testing.assert_array_equal(state.impossible_total, total)


def test_impossible_moves_are_counted_in_the_infos_of_both_adapters():
    import hivex_dsl

    scenario = {"hivex": 1, "environment": "wildfire_resource_management", "episode_length": 5}
    env = hivex_dsl.parallel_env(scenario)
    env.reset(seed=3)
    # tower_0 subtracts from its own empty allocation (impossible); tower_1 adds to itself from its full budget
    actions = {a: np.zeros(4, np.int64) for a in env.agents}
    actions["tower_0"] = np.array([2, 0, 0, 0])
    actions["tower_1"] = np.array([1, 0, 0, 0])
    _, _, _, _, infos = env.step(actions)
    assert infos["tower_0"]["env"] == {"impossible_actions": 1, "impossible_actions_episode": 1}
    assert infos["tower_1"]["env"]["impossible_actions"] == 0
    _, _, _, _, infos = env.step({a: np.zeros(4, np.int64) for a in env.agents})
    assert infos["tower_0"]["env"] == {"impossible_actions": 0, "impossible_actions_episode": 1}

    vector = hivex_dsl.vector_env(scenario, num_worlds=2)
    vector.reset(seed=3)
    batch = np.zeros((18, 4), np.int64)
    batch[9] = [2, 2, 2, 2]  # world 1, tower_0: nothing to subtract anywhere
    *_, infos = vector.step(batch)
    assert infos["env/impossible_actions"].tolist() == [0] * 9 + [4] + [0] * 8


@pytest.mark.parametrize("allocatable, kept, refused", [(9, 9, 1), (10, 10, 0)])
def test_an_agent_allocates_at_most_allocatable_tenths(allocatable, kept, refused):
    """Ten adds to itself: by default (9, the original's plateau) the tenth is refused and counted as impossible,
    and a tenth stays in the budget; with allocatable_tenths 10 all ten go."""
    compiled = hivex_dsl.compile({"hivex": 1, "environment": "wildfire_resource_management",
                                  "params": {"allocatable_tenths": allocatable}})
    sim = compiled.entry.make_simulator(compiled)
    rng = np.random.default_rng(0)
    state = sim.reset(rng, 1)
    actions = np.zeros((1, 9, 4), np.int64)
    actions[0, :, 0] = 1  # every agent adds a tenth to itself
    for _ in range(10):
        state, _ = sim.step(state, actions, rng)
    assert state.allocation[0, :, 0].tolist() == [kept] * 9
    assert state.budget[0].tolist() == [10 - kept] * 9
    assert state.impossible_total[0].tolist() == [refused] * 9
    actions[0, :, 0] = 2  # one back, then the add goes through again
    state, _ = sim.step(state, actions, rng)
    actions[0, :, 0] = 1
    state, _ = sim.step(state, actions, rng)
    assert state.allocation[0, :, 0].tolist() == [kept] * 9 and state.impossible[0].tolist() == [0] * 9


def test_an_agent_cannot_start_holding_more_than_it_may_allocate():
    with pytest.raises(hivex_dsl.HivexError, match=r"initial_self_tenths \(10\) must not exceed allocatable_tenths"):
        hivex_dsl.compile({"hivex": 1, "environment": "wildfire_resource_management",
                           "params": {"initial_self_tenths": 10}})


def test_individual_resource_count_is_each_tower_s_support_as_its_episode_ends():
    """By hand: every agent keeps two tenths (agent 4 one) and gives one to its neighbour 1, the lowest-indexed
    tower a spacing away (towers 1, 0, 1, 0, 1, 2, 3, 4, 5 of towers 0-8), so tower 0 receives from towers 1 and
    3, tower 1 from 0, 2 and 4, towers 2-5 from one tower each (5, 6, 7, 8) and towers 6-8 from none."""
    from hivex_dsl.runtime.batched import BatchedEnv

    compiled = hivex_dsl.compile({"hivex": 1, "environment": "wildfire_resource_management", "episode_length": 5})
    env = BatchedEnv(compiled, batch=1, split="test")
    env.reset()
    keep, keep_and_give, nothing = [1, 0, 0, 0], [1, 1, 0, 0], [0, 0, 0, 0]
    fourth_takes_back = np.array([nothing] * 4 + [[2, 0, 0, 0]] + [nothing] * 4)
    for actions in ([keep] * 9, [keep_and_give] * 9, fourth_takes_back, [nothing] * 9, [nothing] * 9):
        env.step(np.array([actions]))
    assert not env.alive.any()  # the 5-step limit ended every tower's episode
    expected = np.array([2 + 2, 2 + 3, 2 + 1, 2 + 1, 1 + 1, 2 + 1, 2, 2, 2]) / 10
    np.testing.assert_allclose(env.statistic_sums()["Individual Resource Count"][0], expected)
    np.testing.assert_allclose(env.state.support[0] / 10, expected)
