"""Wildfire Resource Management: the paper's power law and reward equations on hand-built states,
and the reward table's task order."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

import hivex_dsl
from hivex_dsl.envs.wildfire_resource_management.params import WildfireResourceParams
from hivex_dsl.envs.wildfire_resource_management.terms import (
    broken_power_law, collective_performance, neighbour_performance, remapped_distance, tower_performance,
    watch_tower_performance)
from hivex_dsl.envs.wildfire_resource_management.types import Sighting

PARAMS = WildfireResourceParams()
FIRE_ONLY = PARAMS.model_copy(update={"performance_weight": "none"})  # a tower's performance is its P alone
# the own-tower and neighbourhood terms as this project read them until session 74: P r_self^2, sum P x r_given
AS_PRINTED = PARAMS.model_copy(update={"own_term_weight": "kept_squared", "neighbour_term_weight": "given_total"})

# P = (1 + (d' * 1000 / 270)^5)^(-1/2) with d' = 0.5 -/+ 0.5 min(1, d / 200) (approaching / not), by hand:
#   d = 0:              d' = 0.5,  (1.851852)^5 = 21.778662  -> 22.778662^-0.5 = 0.2095250
#   d = 100, approach:  d' = 0.25, (0.925926)^5 = 0.680583   -> 1.680583^-0.5  = 0.7713829
#   d = 100, not:       d' = 0.75, (2.777778)^5 = 165.38104  -> 166.38104^-0.5 = 0.0775260
#   d = 200, approach:  d' = 0,                                 P = 1
#   d = 200, not:       d' = 1,    (3.703704)^5 = 696.91722  -> 697.91722^-0.5 = 0.0378528
HAND = [(0.0, True, 0.2095250), (0.0, False, 0.2095250), (100.0, True, 0.7713829), (100.0, False, 0.0775260),
        (200.0, True, 1.0), (200.0, False, 0.0378528)]


@pytest.mark.parametrize("distance, approaching, expected", HAND)
def test_power_law_matches_hand_computed_values(distance, approaching, expected):
    remapped = remapped_distance(np.array([distance]), np.array([approaching]), 200.0)
    assert broken_power_law(remapped, 270.0, 5.0)[0] == pytest.approx(expected, abs=5e-7)


def test_performance_falls_with_distance_for_a_receding_fire_and_rises_for_an_approaching_one():
    distance = np.linspace(0.0, 200.0, 21)
    near_to_far = broken_power_law(remapped_distance(distance, np.zeros(21, bool), 200.0), 270.0, 5.0)
    approaching = broken_power_law(remapped_distance(distance, np.ones(21, bool), 200.0), 270.0, 5.0)
    assert np.all(np.diff(near_to_far) < 0) and np.all(np.diff(approaching) > 0)
    assert np.all((approaching > 0) & (approaching <= 1)) and np.all(near_to_far > 0)


def test_a_fire_beyond_the_threshold_gives_no_performance():
    """The equation is defined up to d_thresh: an approaching fire at 450 m used to read as d1n = 1 (clipped)
    and P = 1, the best a tower can do; now it is idle_performance (0), as is one at 600 m. At exactly 200 m
    an approaching fire gives d' = 0 and P = 1, a receding one 0.0378528 (the hand values above)."""
    distance = np.array([[450.0, 600.0, 200.0, 200.0, 199.0, np.inf, 100.0, 250.0, 0.0]])
    approaching = np.array([[True, False, True, False, True, False, True, True, False]])
    sighting = Sighting(cell=np.zeros((1, 9), np.int64), cells=400, offset=np.zeros((1, 9, 3)), distance=distance,
                        approaching=approaching)
    # 199 m approaching: d' = 0.5 - 0.5 * 0.995 = 0.0025, (0.0092593)^5 = 6.8e-11 -> P = 1.0 to 1e-10
    expected = [0.0, 0.0, 1.0, 0.0378528, 1.0, 0.0, 0.7713829, 0.0, 0.2095250]
    np.testing.assert_allclose(tower_performance(SimpleNamespace(sighting=sighting), PARAMS)[0], expected, atol=1e-6)


def hand_state(keep_centre: int = 5):
    """One world: tower 4 sees a fire 100 m away that approaches, tower 1 one 100 m away that does not,
    no other tower sees fire (P = idle = 0). The centre keeps ``keep_centre`` tenths for itself, tower 1
    keeps everything, tower 0 gives 2 tenths to tower 1 and 1 to tower 4 (its neighbours 1, 3, 4) and
    keeps 7 unallocated, tower 7 gives 4, 3, 3 tenths to its neighbours 4, 6, 8."""
    distance = np.full((1, 9), np.inf)
    distance[0, 4] = distance[0, 1] = 100.0
    approaching = np.zeros((1, 9), bool)
    approaching[0, 4] = True
    sighting = Sighting(cell=np.zeros((1, 9), np.int64), cells=400,
                        offset=np.zeros((1, 9, 3)), distance=distance, approaching=approaching)
    allocation = np.zeros((1, 9, 4), np.int16)
    allocation[0, 4, 0] = keep_centre
    allocation[0, 1, 0] = 10
    allocation[0, 0, 1:] = (2, 0, 1)
    allocation[0, 7, 1:] = (4, 3, 3)
    return SimpleNamespace(sighting=sighting, allocation=allocation)


P_CENTRE, P_SOUTH = 0.7713829, 0.0775260  # towers 4 and 1 above


def test_watch_tower_performance_as_printed_is_p_times_own_share_squared():
    value = watch_tower_performance(None, hand_state(keep_centre=5), None, AS_PRINTED)[0]
    assert value[4] == pytest.approx(P_CENTRE * 0.5 * 0.5, abs=1e-6)
    assert value[1] == pytest.approx(P_SOUTH * 1.0 * 1.0, abs=1e-6)
    assert np.all(value[[0, 2, 3, 5, 6, 7, 8]] == 0.0)


def test_neighbour_performance_given_total_is_the_neighbours_sum_weighted_by_what_the_agent_gives_them():
    value = neighbour_performance(None, hand_state(), None, AS_PRINTED)[0]
    # tower 0 (neighbours 1, 3, 4) gives 0.3 in all: (0.0775260 + 0 + 0.7713829) * 0.3 = 0.2546727
    assert value[0] == pytest.approx(0.2546727, abs=1e-6)
    # tower 7 (neighbours 4, 6, 8) gives 1.0: (0.7713829 + 0 + 0) * 1.0, however it splits it
    assert value[7] == pytest.approx(0.7713829, abs=1e-6)
    # towers 1 and 4 give nothing (tower 4's neighbours 1, 3, 5 sum to 0.0775260, times 0); nor do the rest
    assert np.all(value[[1, 2, 3, 4, 5, 6, 8]] == 0.0)


def test_collective_performance_is_the_root_mean_square_of_all_nine():
    value = collective_performance(None, hand_state(), None, FIRE_ONLY)[0]
    expected = np.sqrt((P_CENTRE ** 2 + P_SOUTH ** 2) / 9.0)  # 0.2584230, below 1 so 1 - |1 - x| = x
    assert value == pytest.approx(np.full(9, expected), abs=1e-6)
    assert expected == pytest.approx(0.2584230, abs=1e-6)


def test_idle_performance_applies_to_towers_without_fire():
    idle = FIRE_ONLY.model_copy(update={"idle_performance": 0.5})
    value = collective_performance(None, hand_state(), None, idle)[0, 0]
    assert value == pytest.approx(np.sqrt((P_CENTRE ** 2 + P_SOUTH ** 2 + 7 * 0.25) / 9.0), abs=1e-6)


def test_the_collective_and_individual_read_p_times_what_a_tower_holds():
    """The hand state's supports: the centre keeps 5 and receives 1 from tower 0 (its neighbour 3) and 4 from tower
    7 (its neighbour 1): 1.0; tower 1 keeps 10 and receives 2 from tower 0 (its neighbour 1): 1.2. The own-tower
    and neighbourhood terms as printed read P alone, whatever performance_weight says."""
    from hivex_dsl.envs.wildfire_resource_management.resources import total_support
    from hivex_dsl.envs.wildfire_resource_management.statistics import individual_performance

    resources = PARAMS
    assert resources.performance_weight == "resources"  # the default
    state = hand_state(keep_centre=5)
    state.support = total_support(state.allocation)
    assert state.support[0, [4, 1]].tolist() == [10, 12]
    held = individual_performance(None, state, None, resources)[0]
    assert held[4] == pytest.approx(P_CENTRE * 1.0, abs=1e-6) and held[1] == pytest.approx(P_SOUTH * 1.2, abs=1e-6)
    # sqrt((0.7713829^2 + (0.0775260 * 1.2)^2) / 9) = sqrt(0.6036858 / 9) = 0.2589908
    assert collective_performance(None, state, None, resources)[0, 0] == pytest.approx(0.2589908, abs=1e-6)
    printed_fire_only = AS_PRINTED.model_copy(update={"performance_weight": "none"})
    np.testing.assert_array_equal(watch_tower_performance(None, state, None, AS_PRINTED),
                                  watch_tower_performance(None, state, None, printed_fire_only))
    np.testing.assert_array_equal(neighbour_performance(None, state, None, AS_PRINTED),
                                  neighbour_performance(None, state, None, printed_fire_only))
    np.testing.assert_allclose(individual_performance(None, state, None, FIRE_ONLY)[0, [4, 1]], [P_CENTRE, P_SOUTH],
                               atol=1e-6)


HELD_KEPT = AS_PRINTED.model_copy(update={"own_term_weight": "held_kept"})
GIVEN_EACH = AS_PRINTED.model_copy(update={"neighbour_term_weight": "given_each"})
ALLOCATED_KEPT = PARAMS.model_copy(update={"own_term_weight": "allocated_kept"})


def test_the_own_term_reads_the_share_kept_and_the_neighbour_term_what_they_hold_by_default():
    assert (PARAMS.own_term_weight, PARAMS.neighbour_term_weight) == ("kept", "given_each")


def supported_hand_state():
    from hivex_dsl.envs.wildfire_resource_management.resources import total_support

    state = hand_state(keep_centre=5)
    state.support = total_support(state.allocation)  # the centre holds 1.0, tower 1 holds 1.2 (the test above)
    return state


def test_held_kept_pays_the_tower_s_performance_times_the_share_it_keeps():
    """Tower 4: 0.7713829 x 1.0 held x 0.5 kept = 0.3856915 (0.1928457 as P r^2); tower 1: 0.0775260 x 1.2 x 1.0 =
    0.0930312 (0.0775260 as P r^2). Under performance_weight 'none' the tower's performance is P: P x r_self."""
    value = watch_tower_performance(None, supported_hand_state(), None, HELD_KEPT)[0]
    np.testing.assert_allclose(value, [0, 0.0930312, 0, 0, 0.3856915, 0, 0, 0, 0], atol=1e-6)
    fire_only = HELD_KEPT.model_copy(update={"performance_weight": "none"})
    value = watch_tower_performance(None, supported_hand_state(), None, fire_only)[0]
    np.testing.assert_allclose(value[[1, 4]], [P_SOUTH * 1.0, P_CENTRE * 0.5], atol=1e-6)


def centre_giving_hand_state():
    """The supported hand state with the centre giving 0.2 to tower 1 (it keeps 0.5 and receives 0.5 from 0 and 7)."""
    from hivex_dsl.envs.wildfire_resource_management.resources import total_support

    state = supported_hand_state()
    state.allocation[0, 4, 1] = 2
    state.support = total_support(state.allocation)
    state.budget = 10 - state.allocation.sum(-1)
    return state


def test_allocated_kept_pays_p_times_what_the_agent_allocated_times_the_share_it_keeps():
    """The centre keeps 0.5 and gives 0.2 to tower 1 (allocated 0.7): 0.7713829 x 0.7 x 0.5 = 0.2699840, whatever the
    0.5 that towers 0 and 7 give it (held_kept: 0.7713829 x 1.0 held x 0.5 = 0.3856915); tower 1 keeps its whole
    1.0: 0.0775260; tower 0 keeps nothing: 0."""
    state = centre_giving_hand_state()
    value = watch_tower_performance(None, state, None, ALLOCATED_KEPT)[0]
    np.testing.assert_allclose(value, [0, 0.0775260, 0, 0, 0.2699840, 0, 0, 0, 0], atol=1e-6)
    assert watch_tower_performance(None, state, None, HELD_KEPT)[0, 4] == pytest.approx(0.3856915, abs=1e-6)


def test_kept_pays_p_times_the_share_kept_whatever_is_given_or_received():
    """The centre keeps 0.5, gives 0.2 to tower 1 and receives 0.5 from towers 0 and 7: 0.7713829 x 0.5 = 0.3856915
    (allocated_kept 0.2699840, the test above); tower 1 keeps its whole 1.0 and receives 0.4: 0.0775260 x 1.0. The
    default reads it so."""
    state = centre_giving_hand_state()
    value = watch_tower_performance(None, state, None, PARAMS)[0]
    np.testing.assert_allclose(value, [0, 0.0775260, 0, 0, 0.3856915, 0, 0, 0, 0], atol=1e-6)


def test_given_each_pays_each_neighbour_s_performance_times_the_share_given_it():
    """Tower 0 gives 0.2 to tower 1 (P 0.0775260, holding 1.2) and 0.1 to tower 4 (P 0.7713829, holding 1.0):
    0.0186062 + 0.0771383 = 0.0957445; tower 7 gives 0.4 to tower 4 and 0.3 each to towers 6 and 8 (no fire):
    0.3085532. With P alone: 0.0155052 + 0.0771383 = 0.0926435 and 0.3085532 again."""
    value = neighbour_performance(None, supported_hand_state(), None, GIVEN_EACH)[0]
    np.testing.assert_allclose(value, [0.0957445, 0, 0, 0, 0, 0, 0, 0.3085532, 0], atol=1e-6)
    fire_only = GIVEN_EACH.model_copy(update={"performance_weight": "none"})
    value = neighbour_performance(None, supported_hand_state(), None, fire_only)[0]
    np.testing.assert_allclose(value[[0, 7]], [0.0926435, 0.3085532], atol=1e-6)


@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 2**32 - 1))
def test_given_each_sums_over_a_world_to_each_tower_s_performance_times_what_it_received(seed):
    """Every tenth given is held by the neighbour it was given to, so summed over a world's nine towers the
    neighbourhood term read per neighbour is sum_j P_j held_j received_j, and held_kept's is sum_j P_j held_j kept_j:
    together, under held_kept, the tower performances weighted by what they hold (the world's sum of P_j held_j^2)."""
    from hivex_dsl.envs.wildfire_resource_management.resources import total_support
    from hivex_dsl.envs.wildfire_resource_management.statistics import individual_performance

    rng = np.random.default_rng(seed)
    allocation = np.zeros((4, 9, 4), np.int16)
    for world in range(4):
        for tower in range(9):
            allocation[world, tower] = rng.multinomial(int(rng.integers(0, 11)), np.full(4, 0.25))
    distance = rng.uniform(0.0, 300.0, (4, 9))
    sighting = Sighting(cell=np.zeros((4, 9), np.int64), cells=400, offset=np.zeros((4, 9, 3)), distance=distance,
                        approaching=rng.random((4, 9)) < 0.5)
    state = SimpleNamespace(sighting=sighting, allocation=allocation, support=total_support(allocation))
    params = PARAMS.model_copy(update={"own_term_weight": "held_kept"})  # with given_each, the default
    performance = individual_performance(None, state, None, params)  # (4, 9) P x held
    held, kept = state.support / 10, allocation[..., 0] / 10
    np.testing.assert_allclose(neighbour_performance(None, state, None, params).sum(-1),
                               (performance * (held - kept)).sum(-1), rtol=1e-9, atol=1e-12)
    paid = neighbour_performance(None, state, None, params) + watch_tower_performance(None, state, None, params)
    np.testing.assert_allclose(paid.sum(-1), (performance * held).sum(-1), rtol=1e-9, atol=1e-12)


def test_a_tower_holding_more_than_its_share_overshoots_and_the_equation_s_absolute_value_bites():
    """Every other tower gives its whole share to the centre (it is each one's neighbour 1, 2 or 3), which keeps
    its own and sees an approaching fire at 200 m (P = 1): it holds 9.0, the root mean square is sqrt(81 / 9) = 3
    and the term 1 - |1 - 3| = -1, where P alone gives sqrt(1 / 9) = 1/3."""
    from hivex_dsl.envs.wildfire_resource_management.resources import total_support

    distance = np.full((1, 9), np.inf)
    distance[0, 4] = 200.0
    approaching = np.zeros((1, 9), bool)
    approaching[0, 4] = True
    sighting = Sighting(cell=np.zeros((1, 9), np.int64), cells=400, offset=np.zeros((1, 9, 3)), distance=distance,
                        approaching=approaching)
    allocation = np.zeros((1, 9, 4), np.int16)
    for tower, slot in {0: 3, 1: 3, 2: 3, 3: 2, 4: 0, 5: 2, 6: 3, 7: 1, 8: 3}.items():
        allocation[0, tower, slot] = 10
    state = SimpleNamespace(sighting=sighting, allocation=allocation, support=total_support(allocation))
    assert state.support[0].tolist() == [0, 0, 0, 0, 90, 0, 0, 0, 0]
    assert collective_performance(None, state, None, PARAMS)[0, 0] == pytest.approx(-1.0)  # the contract's low
    assert collective_performance(None, state, None, FIRE_ONLY)[0, 0] == pytest.approx(1 / 3)


def compile_task(task):
    return hivex_dsl.compile({"hivex": 1, "environment": "wildfire_resource_management", "task": task})


def test_tasks_follow_the_papers_table_and_the_leaderboard_and_work_by_name():
    """Paper table columns: 1. main, 2. keep all (own x10), 3. distribute all (neighbours x10)."""
    expected = {"main": (0, [1, 1, 1]), "keep_all": (1, [10, 1, 1]), "distribute_all": (2, [1, 10, 1])}
    for name, (index, weights) in expected.items():
        by_name, by_index = compile_task(name), compile_task(index)
        assert by_name.task_index == by_index.task_index == index and by_index.task_name == name
        assert list(by_name.weights.values()) == weights
        assert by_name.ends_on == ("fire_out",)


def test_the_task_order_discrepancy_is_stated_in_the_notes():
    entry = compile_task("main").entry
    for notes in (entry.notes, entry.reward_table.notes):
        text = " ".join(notes)
        assert "Distribute All: 1" in text and "keep_all" in text and "distribute_all" in text
    assert any("tower 4 (x 0, y 0): 1, 3, 5" in note for note in entry.notes)


def test_bundled_scenarios_cover_the_three_tasks_and_the_paper_grid():
    for name in ("main", "keep_all", "distribute_all"):
        compiled = hivex_dsl.compile(f"wildfire_resource_management/{name}")
        assert compiled.task_name == name and compiled.agents == 9 and compiled.episode_length == 500
    suite = hivex_dsl.compile_all("wildfire_resource_management/paper_suite")
    grid = [(level, task) for level in range(1, 11) for task in range(3)]
    assert sorted((c.level, c.task_index) for c in suite) == grid


@settings(max_examples=8, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), steps=st.integers(1, 80))
def test_terms_keep_their_contracts_on_random_rollouts(seed, steps):
    """The generic contract test draws 1 or 3 agents, which WRM (exactly 9 towers) cannot compile."""
    compiled = compile_task("main")
    sim = compiled.entry.make_simulator(compiled)
    rng = np.random.default_rng(seed)
    state = sim.reset(rng, 3)
    for _ in range(steps):
        prev, (state, _) = state, sim.step(state, rng.integers(0, 3, (3, 9, 4)), rng)
    for term in compiled.entry.terms:
        value = term(prev, state, None, compiled.params)
        assert value.shape == (3, 9) and np.all(np.isfinite(value)), term.name
        assert np.all((value >= term.contract.low) & (value <= term.contract.high)), term.name


@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), allocated=st.booleans())
def test_the_own_term_is_blind_to_what_the_neighbours_give_and_pays_the_kept_share(seed, allocated):
    """Under kept (the default) a tower's own term is P x (its kept tenths / 10), under allocated_kept P x (its
    allocated tenths / 10) x (its kept tenths / 10), whatever the other towers allocate: redrawing every other
    tower's row leaves the centre's as it was."""
    from hivex_dsl.envs.wildfire_resource_management.resources import total_support

    rng = np.random.default_rng(seed)
    params = ALLOCATED_KEPT if allocated else PARAMS

    def state_of(allocation):
        distance = np.linspace(10.0, 190.0, 9)[None].repeat(2, 0)
        sighting = Sighting(cell=np.zeros((2, 9), np.int64), cells=400, offset=np.zeros((2, 9, 3)),
                            distance=distance, approaching=np.zeros((2, 9), bool))
        return SimpleNamespace(sighting=sighting, allocation=allocation, support=total_support(allocation),
                               budget=10 - allocation.sum(-1))

    allocation = np.stack([[rng.multinomial(int(rng.integers(0, 10)), np.full(4, 0.25)) for _ in range(9)]
                           for _ in range(2)]).astype(np.int16)
    redrawn = np.stack([[rng.multinomial(int(rng.integers(0, 10)), np.full(4, 0.25)) for _ in range(9)]
                        for _ in range(2)]).astype(np.int16)
    redrawn[:, 4] = allocation[:, 4]  # the centre's own row kept, every other tower's redrawn
    before = watch_tower_performance(None, state_of(allocation), None, params)
    after = watch_tower_performance(None, state_of(redrawn), None, params)
    np.testing.assert_array_equal(before[:, 4], after[:, 4])
    p = tower_performance(state_of(allocation), params)
    weight = allocation.sum(-1) / 10 if allocated else 1.0
    np.testing.assert_allclose(before, p * weight * allocation[..., 0] / 10, rtol=1e-12)
