"""Ocean Plastic Collection reward terms against the paper's equations, its reward table and scenarios."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

import hivex_dsl
from hivex_dsl import ScenarioError
from hivex_dsl.envs.ocean_plastic_collection.camera import build_field
from hivex_dsl.envs.ocean_plastic_collection.terms import (
    close_to_other_vessel, collect_trash, collide_with_trash, collided_with_other_vessel, crossed_border,
    lowest_collected_trash_count, nearby_trash_count_delta)

ENV = "ocean_plastic_collection"
# The paper's "Main- and Sub-Task Reward Scale" table for OPC, row by row (tasks 1-4 = indices 0-3).
PAPER_MATRIX = {
    "collect_trash": [1, 1, 1, -1],
    "lowest_collected_trash_count": [1, 1, 1, 0],
    "crossed_border": [1, 1, 1, 1],
    "collided_with_other_vessel": [1, 1, 1, 1],
    "close_to_other_vessel": [0, 0, 1, 0],
    "nearby_trash_count_delta": [0, 1, 0, 0],
    "collide_with_trash": [0, 0, 0, 1],
}


@pytest.fixture(scope="module")
def sim():
    sc = hivex_dsl.compile({"hivex": 1, "environment": ENV, "agents": 3})
    return sc.entry.make_simulator(sc)


@pytest.fixture(scope="module")
def state(sim):
    return sim.reset(np.random.default_rng(0), 2)


def test_collect_trash_is_the_count_collected_this_step(sim, state):
    new = replace(state, collected=np.array([[0, 2, 1], [5, 0, 0]]))
    np.testing.assert_array_equal(collect_trash(state, new, None, sim.params), [[0, 2, 1], [5, 0, 0]])


def test_lowest_collected_count_pays_everyone_a_hundredth_of_the_world_minimum_per_pebble_collected(sim, state):
    """World 0: vessels hold 7, 3 and 12 pebbles after this step, two of them picked up 2 and 1 now: each of
    the 3 pebbles pays every vessel 0.01 x 3 (the lowest count), 0.09. World 1: lowest 40, but nothing was
    collected this step, so nothing is paid (the term pays on collection, not on every step)."""
    new = replace(state, collected_total=np.array([[7, 3, 12], [40, 41, 40]]),
                  collected=np.array([[0, 2, 1], [0, 0, 0]]))
    np.testing.assert_allclose(lowest_collected_trash_count(state, new, None, sim.params),
                               [[0.09, 0.09, 0.09], [0.0, 0.0, 0.0]])


def test_the_lowest_count_term_pays_the_world_minimum_once_per_pebble_over_an_episode(sim, state):
    """Hand-computed episode: three vessels; step 1 vessel 0 takes a pebble (lowest count 0: pays 0),
    step 2 vessels 1 and 2 take one each (lowest 1: 2 pebbles x 0.01 x 1 = 0.02), step 3 nothing (0),
    step 4 vessel 0 takes 3 (lowest 1: 3 x 0.01 = 0.03). Every vessel's episode sum is 0.05, where paying
    0.01 x the lowest count on every step would give 0 + 0.01 + 0.01 + 0.01 = 0.03."""
    steps = [([1, 0, 0], [1, 0, 0]), ([0, 1, 1], [1, 1, 1]), ([0, 0, 0], [1, 1, 1]), ([3, 0, 0], [4, 1, 1])]
    total = sum(lowest_collected_trash_count(state, replace(state, collected=np.array([now]),
                                                            collected_total=np.array([held])), None, sim.params)
                for now, held in steps)
    np.testing.assert_allclose(total, [[0.05, 0.05, 0.05]])


def test_crash_terms_are_minus_100_on_their_events(sim, state):
    new = replace(state, crossed_border=np.array([[True, False, False], [False, False, True]]),
                  collided_vessel=np.array([[False, True, True], [False, False, False]]))
    np.testing.assert_array_equal(crossed_border(state, new, None, sim.params), [[-100, 0, 0], [0, 0, -100]])
    np.testing.assert_array_equal(collided_with_other_vessel(state, new, None, sim.params),
                                  [[0, -100, -100], [0, 0, 0]])


def test_collide_with_trash_is_minus_1_whenever_a_pebble_was_touched(sim, state):
    """The prose's -1 (the equation's -100 was copied from the vessel-collision block): once per step that
    touches plastic, however many pebbles. In Avoid Plastic it is what a touch costs: Collect Trash's -1 a pebble is
    logged in Local but not paid there (the reward table's Local note), so a step taking 4 pebbles costs 1."""
    new = replace(state, collected=np.array([[0, 1, 4], [0, 0, 0]]))
    np.testing.assert_array_equal(collide_with_trash(state, new, None, sim.params), [[0, -1, -1], [0, 0, 0]])


def test_close_to_other_vessel_pays_1_within_10_m_inclusive(sim, state):
    """The prose's +1 at a distance smaller than or equal to 10 (the equation prints 10 at d < 10)."""
    new = replace(state, closest=np.array([[9.99, 10.0, np.inf], [0.5, 25.0, 10.01]]))
    np.testing.assert_array_equal(close_to_other_vessel(state, new, None, sim.params), [[1, 1, 0], [1, 0, 0]])


def test_nearby_delta_pays_only_rises_above_the_episodes_highest_count(sim, state):
    """The prose's running maximum: a vessel pays only what its nearby count rises above the highest count
    of its episode so far. World 0, vessel 0: best 0, now 4, pays 4; vessel 1: best 10, now 6 (a fall),
    pays 0; vessel 2: best 7, now 9, pays 2 even though the previous step's count was 3 (the equation's
    rise over the previous step would pay 6). World 1: best 12; a count back at 12 after a dip pays 0
    (the previous-step reading would pay 12 - 0 = 12), 13 pays 1, 3 pays 0."""
    before = replace(state, nearby=np.array([[0, 10, 3], [3, 0, 3]]),
                     nearby_best=np.array([[0, 10, 7], [12, 12, 12]]))
    after = replace(state, nearby=np.array([[4, 6, 9], [12, 13, 3]]))
    np.testing.assert_array_equal(nearby_trash_count_delta(before, after, None, sim.params), [[4, 0, 2], [0, 1, 0]])


def test_an_episode_pays_its_highest_nearby_count_however_the_count_wanders(sim, state):
    """Hand-computed: counts 5, 2, 8, 8, 3, 8, 10, 1 over eight steps pay 5, 0, 3, 0, 0, 0, 2, 0 = 10, the
    highest count; the rise over the previous step would pay 5 + 6 + 5 + 2 = 18."""
    counts = [5, 2, 8, 8, 3, 8, 10, 1]
    prev, paid = replace(state, nearby=np.zeros((2, 3), np.int64), nearby_best=np.zeros((2, 3), np.int64)), []
    for count in counts:
        nearby = np.full((2, 3), count, np.int64)
        new = replace(prev, nearby=nearby, nearby_best=np.maximum(prev.nearby_best, nearby))
        paid.append(nearby_trash_count_delta(prev, new, None, sim.params)[0, 0])
        prev = new
    assert paid == [5, 0, 3, 0, 0, 0, 2, 0]


def test_the_simulator_keeps_each_vessels_highest_nearby_count(sim):
    """The state's running maximum is what the simulator builds, step after step, from the counts it senses."""
    state, rng = sim.reset(np.random.default_rng(11), 2), np.random.default_rng(12)
    assert not state.nearby_best.any()
    best = np.zeros_like(state.nearby)
    for _ in range(40):
        state, _ = sim.step(state, rng.integers(0, [2, 3], size=(2, 3, 2)), rng)
        best = np.maximum(best, state.nearby)
        np.testing.assert_array_equal(state.nearby_best, best)
    assert best.any()


def test_the_first_step_pays_the_whole_nearby_count_as_the_paper_starts_from_zero(sim):
    # Vessel at the origin facing +x; pebbles at 10, 24.9 (near) and 25, 30 m (not strictly within 25 m).
    start = sim.reset(np.random.default_rng(3), 1)
    pebbles = np.array([[[0.0, 10.0], [-24.9, 0.0], [0.0, -25.0], [30.0, 0.0], [150.0, 150.0]]])
    start = replace(start, position=np.array([[[0.0, 0.0], [100.0, 100.0], [-100.0, -100.0]]]),
                    heading=np.zeros((1, 3)), speed=np.zeros((1, 3)), pebbles=build_field(pebbles, sim.geometry))
    assert start.nearby[0, 0] == 0 and start.nearby_best[0, 0] == 0
    new, _ = sim.step(start, np.zeros((1, 3, 2), np.int64), np.random.default_rng(4))
    assert new.nearby[0].tolist() == [2, 0, 0]
    assert nearby_trash_count_delta(start, new, None, sim.params)[0].tolist() == [2.0, 0.0, 0.0]
    again, _ = sim.step(new, np.zeros((1, 3, 2), np.int64), np.random.default_rng(5))
    assert nearby_trash_count_delta(new, again, None, sim.params)[0].tolist() == [0.0, 0.0, 0.0]


def test_reward_table_mirrors_the_paper_row_for_row():
    entry = hivex_dsl.compile({"hivex": 1, "environment": ENV}).entry
    table = entry.reward_table
    assert table.task_names == ("plastic_collection", "find_highest_polluted_area", "group_up", "avoid_plastic")
    assert {term: list(row) for term, row in table.matrix.items()} == PAPER_MATRIX
    assert list(table.matrix) == list(PAPER_MATRIX)
    assert [term.contract.paper_row for term in entry.terms] == [1, 2, 3, 4, 5, 6, 7]


def test_bundled_scenarios_are_the_papers_tasks_with_three_vessels_for_5000_steps():
    suite = hivex_dsl.compile_all("scenarios/ocean_plastic_collection/paper_suite.yaml")
    assert [sc.task_index for sc in suite] == [0, 1, 2, 3]
    for name, index in [("main", 0), ("find_highest_polluted_area", 1), ("group_up", 2), ("avoid_plastic", 3)]:
        sc = hivex_dsl.compile(f"scenarios/{ENV}/{name}.yaml")
        assert (sc.task_index, sc.agents, sc.episode_length) == (index, 3, 5000)
        assert (sc.seeds.train, sc.seeds.test) == (5000, 6000)
        assert sc.generators["pollution"].half_extent_m == 200.0


def test_the_heat_map_and_spawn_must_describe_one_world():
    with pytest.raises(ScenarioError, match="differs from generators.pollution.half_extent_m"):
        hivex_dsl.compile({"hivex": 1, "environment": ENV, "generators": {"pollution": {"half_extent_m": 300.0}}})
    sc = hivex_dsl.compile({"hivex": 1, "environment": ENV, "generators": {
        "pollution": {"half_extent_m": 300.0}, "spawn": {"half_extent_m": 300.0}}})
    state = sc.entry.make_simulator(sc).reset(np.random.default_rng(0), 1)
    assert np.abs(state.pebbles.positions).max() <= 300.0 and np.abs(state.pebbles.positions).max() > 200.0


def test_vessels_that_cannot_all_spawn_are_a_compile_error():
    with pytest.raises(ScenarioError, match="12 vessels 100 m apart"):
        hivex_dsl.compile({"hivex": 1, "environment": ENV, "agents": 12,
                           "generators": {"spawn": {"min_spacing_m": 100.0}}})
