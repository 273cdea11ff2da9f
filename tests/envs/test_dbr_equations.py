"""Drone-Based Reforestation reward equations and station rules on small hand-built worlds.

Every world here is flat ground at 0 m with the station pad at the origin and trees placed by
hand on forest cell centres (x, y = -198 + 4 k), so every distance is known exactly.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

import hivex_dsl
from hivex_dsl.evaluation.rollout import rollout
from hivex_dsl.envs.drone_based_reforestation.camera import NEW_TREE_GRAY, to_byte
from hivex_dsl.envs.drone_based_reforestation.fertility import FAR_M, distance_reward, seed_reward, tree_distance_raster
from hivex_dsl.envs.drone_based_reforestation.statistics import distance_to_existing_trees
from hivex_dsl.sim.grids import sample_bilinear
from hivex_dsl.sim.reward.composer import RewardComposer

ENV = "drone_based_reforestation"


def simulator(agents: int = 1, **params):
    compiled = hivex_dsl.compile({"hivex": 1, "environment": ENV, "agents": agents, "params": params})
    return compiled, compiled.entry.make_simulator(compiled)


def hand_world(sim, drones, trees=(), holding=True, energy=1.0, away=True, heading=0.0, heights=None):
    """One world: flat ground (or ``heights``), trees at forest cell centres, drones at ``drones`` (A, 3)."""
    state = sim.reset(np.random.default_rng(0), 1)
    grid = sim.forest_grid
    tree_xy = np.full((1, grid.n, grid.n, 2), FAR_M, np.float32)
    for x, y in trees:
        col, row = int(round((x - grid.origin) / grid.cell)), int(round((y - grid.origin) / grid.cell))
        tree_xy[0, row, col] = (x, y)
    heights = np.zeros_like(state.heights) if heights is None else np.array(heights)[None]
    station = np.array([[0.0, 0.0, heights[0, sim.terrain_grid.n // 2, sim.terrain_grid.n // 2]]])
    position = np.asarray(drones, np.float64)[None]
    shape = position.shape[:2]
    distance = np.linalg.norm(position - station[:, None], axis=-1)
    state = replace(
        state, heights=heights, tree_xy=tree_xy, station=station, camera=sim._cameras(heights, tree_xy, station),
        tree_distance=tree_distance_raster(tree_xy[..., 0] < FAR_M, grid.cell, sim.tree_reach_m),
        new_trees=np.full_like(state.new_trees, FAR_M), new_count=np.zeros(1, np.int64), position=position,
        heading=np.full(shape, heading), ground=sample_bilinear(heights, sim.terrain_grid, position[..., :2]),
        energy=np.full(shape, energy), holding=np.full(shape, holding), alive=np.ones(shape, bool),
        inside=distance <= sim.params.charge_radius_m,
        away=np.full(shape, away),
        back_active=np.zeros(shape, bool), best_fertility=np.zeros(shape), best_height=np.zeros(shape),
        best_distance=np.zeros(shape))
    return state


def act(agents: int = 1, throttle=0.0, steer=0.0, updown=0.0, drop=0):
    continuous = np.zeros((1, agents, 3), np.float32)
    continuous[..., 0], continuous[..., 1], continuous[..., 2] = throttle, steer, updown
    return {"continuous": continuous, "discrete": np.full((1, agents, 1), drop, np.int64)}


def term(compiled, name, prev, state, actions):
    return compiled.entry.terms[name](prev, state, actions, compiled.params)


# ------------------------------------------------------------------ the drop seed equations
@pytest.mark.parametrize("det, dnt, expected", [
    (2.5, 10.0, 20.0),  # right at dot_min: full quality
    (38.75, 10.0, 10.0),  # halfway between 2.5 and 75
    (75.0, 10.0, 0.0),  # at dot_max: quality 0
    (10.0, 10.0, 20.0 * 65.0 / 72.5),
    (2.4, 10.0, 0.0),  # under the canopy
    (75.1, 10.0, 0.0),  # too far from the forest
    (10.0, 2.4, 0.0),  # too close to a planted tree
    (10.0, 2.5, 20.0 * 65.0 / 72.5),
])
def test_seed_reward_is_the_paper_remap_times_20(det, dnt, expected):
    assert seed_reward(np.array([det]), np.array([dnt]), 2.5, 75.0, 20.0)[0] == pytest.approx(expected)


@pytest.mark.parametrize("seed, sdd, expected", [(5.0, 50.0, 2.5), (5.0, 200.0, 10.0), (5.0, 283.0, 10.0), (0.0, 50.0, 0.0)])
def test_distance_reward_is_sdd_over_200_times_10_only_for_a_good_seed(seed, sdd, expected):
    assert distance_reward(np.array([seed]), np.array([sdd]), 200.0, 10.0)[0] == pytest.approx(expected)


def test_a_drop_12_m_from_the_forest_and_50_m_from_the_station_plants_a_tree_worth_r_s_plus_r_d():
    compiled, sim = simulator()
    state = hand_world(sim, [(50.0, 2.0, 10.0)], trees=[(62.0, 2.0)])
    new, outcome = sim.step(state, act(drop=1), np.random.default_rng(1))
    r_s, r_d = 20.0 * (75.0 - 12.0) / 72.5, 10.0 * np.hypot(50.0, 2.0) / 200.0  # det 12 m, sdd 50.04 m
    assert term(compiled, "drop_seed", state, new, act(drop=1))[0, 0] == pytest.approx(r_s + r_d)
    assert new.dropped[0, 0] and outcome.events["planted_tree"][0, 0] and not new.holding[0, 0]
    assert new.new_count[0] == 1 and np.allclose(new.new_trees[0, 0], (50.0, 2.0))
    assert new.new_quality[0, 0] == pytest.approx(r_s / 20.0)
    column, row = sim.raster.index(np.array([50.0, 2.0]))
    assert new.camera[0, row, column] == to_byte(NEW_TREE_GRAY)


@pytest.mark.parametrize("drone, trees, why", [
    ((50.0, 2.0, 10.0), [(50.0, 2.0)], "over a tree"),
    ((50.0, 2.0, 10.0), [(130.0, 2.0)], "80 m from the forest"),
    ((50.0, 2.0, 10.0), [], "no forest at all"),
])
def test_a_drop_on_a_poor_spot_pays_nothing_and_plants_a_tree_of_quality_0(drone, trees, why):
    compiled, sim = simulator()
    state = hand_world(sim, [drone], trees=trees)
    new, _ = sim.step(state, act(drop=1), np.random.default_rng(1))
    assert term(compiled, "drop_seed", state, new, act(drop=1))[0, 0] == 0.0, why
    assert new.dropped[0, 0] and not new.holding[0, 0]
    assert new.new_count[0] == 1 and new.new_quality[0, 0] == 0.0


@pytest.mark.parametrize("trees, logged", [
    ([(62.0, 2.0), (-100.0, 2.0)], 12.0),  # within dot_max: the det the drop's reward used
    ([(130.0, 2.0), (-150.0, 2.0)], 80.0),  # beyond dot_max (no reward), still measured: the nearest of the two
    ([(50.0, 98.0)], 96.0),  # one tree 96 m away, straight north of the drop
    ([], 0.0),  # a world without trees has no distance to log
])
def test_cumulative_distance_to_existing_trees_logs_each_drops_det_at_any_distance(trees, logged):
    compiled, sim = simulator()
    state = hand_world(sim, [(50.0, 2.0, 10.0)], trees=trees)
    new, _ = sim.step(state, act(drop=1), np.random.default_rng(1))
    assert new.dropped[0, 0]
    assert distance_to_existing_trees(state, new, act(drop=1), compiled.params)[0, 0] == pytest.approx(logged)
    after, _ = sim.step(new, act(), np.random.default_rng(2))  # no drop: nothing logged
    assert distance_to_existing_trees(new, after, act(), compiled.params)[0, 0] == 0.0


def test_a_seed_within_2_5_m_of_a_planted_tree_has_no_quality_and_one_3_m_away_has():
    compiled, sim = simulator()
    state = hand_world(sim, [(50.0, 2.0, 10.0)], trees=[(62.0, 2.0)])
    first, _ = sim.step(state, act(drop=1), np.random.default_rng(1))
    moved = replace(first, holding=np.ones((1, 1), bool), position=np.array([[[50.0, 4.0, 10.0]]]))
    second, _ = sim.step(moved, act(drop=1), np.random.default_rng(1))  # 2 m from the first
    assert second.dropped[0, 0] and second.seed_reward[0, 0] == 0.0 and second.distance_reward[0, 0] == 0.0
    further = replace(second, holding=np.ones((1, 1), bool), position=np.array([[[50.0, 7.0, 10.0]]]))
    third, _ = sim.step(further, act(drop=1), np.random.default_rng(1))  # 3 m from the second, 5 m from the first
    assert third.new_count[0] == 3 and third.new_quality[0, :3].tolist() == pytest.approx(
        [63.0 / 72.5, 0.0, (75.0 - np.hypot(12.0, 5.0)) / 72.5])
    assert third.seed_reward[0, 0] == pytest.approx(20.0 * (75.0 - np.hypot(12.0, 5.0)) / 72.5)


def test_of_two_drones_dropping_side_by_side_on_one_step_the_later_one_gets_no_quality():
    compiled, sim = simulator(agents=2)
    state = hand_world(sim, [(50.0, 2.0, 10.0), (51.0, 2.0, 10.0)], trees=[(62.0, 2.0)])
    new, _ = sim.step(state, act(agents=2, drop=1), np.random.default_rng(1))
    assert new.new_count[0] == 2 and new.seed_reward[0, 0] > 0.0 and new.seed_reward[0, 1] == 0.0


def test_no_seed_is_released_over_the_station_pad_or_without_a_seed():
    compiled, sim = simulator()
    at_pad = hand_world(sim, [(3.0, 0.0, 3.0)], trees=[(30.0, 2.0)], away=False)
    new, _ = sim.step(at_pad, act(drop=1), np.random.default_rng(1))
    assert not new.dropped[0, 0] and new.holding[0, 0]
    empty = hand_world(sim, [(50.0, 2.0, 10.0)], trees=[(62.0, 2.0)], holding=False)
    new, _ = sim.step(empty, act(drop=1), np.random.default_rng(1))
    assert not new.dropped[0, 0] and new.new_count[0] == 0


def test_once_the_store_of_planted_trees_is_full_drones_keep_their_seeds():
    compiled, sim = simulator(agents=3, new_tree_capacity=16)
    state = hand_world(sim, [(50.0, 2.0, 10.0), (60.0, 30.0, 10.0), (-50.0, 2.0, 10.0)], trees=[(62.0, 2.0)])
    state = replace(state, new_count=np.array([14]))
    new, _ = sim.step(state, act(agents=3, drop=1), np.random.default_rng(1))
    assert new.dropped[0].tolist() == [True, True, False] and new.holding[0].tolist() == [False, False, True]
    assert new.new_count[0] == 16
    again, _ = sim.step(new, act(agents=3, drop=1), np.random.default_rng(2))  # a full store refuses every wish
    assert not again.dropped.any() and again.holding[0].tolist() == [False, False, True]


# ------------------------------------------------------------------ incremental running back
def increment(x: float, z: float = 10.0) -> int:
    """The paper's d_0 = floor(|p - dp| / 2.5) for a drone at (x, 2, z) and the station at the origin."""
    return int(np.floor(np.sqrt(x * x + 4.0 + z * z) / 2.5))


def test_running_back_pays_20_rbm_over_d_init_in_metres_minus_3_once_per_increment():
    """The paper's r_rb = r_p * rbm / (d_init - d_charge / s), d_init the drop's distance to the station (metres:
    the paper gives d_0 alone "in incremental steps"). A drop at (50, 2, 10): d_init = sqrt(2604) = 51.03 m, so each
    increment pays 20 rbm / 48.03, not 20 rbm / 17 (d_init read as its increment, 20, before issue 52)."""
    compiled, sim = simulator()
    state = hand_world(sim, [(50.0, 2.0, 10.0)], trees=[(62.0, 2.0)], heading=np.pi)
    state, _ = sim.step(state, act(drop=1), np.random.default_rng(1))
    rbm = (20.0 * (75.0 - 12.0) / 72.5 + 10.0 * np.hypot(50.0, 2.0) / 200.0) / 30.0
    d_init = np.sqrt(50.0 ** 2 + 2.0 ** 2 + 10.0 ** 2)
    assert state.back_init[0, 0] == pytest.approx(d_init)
    per_increment = 20.0 * rbm / (d_init - 7.5 / 2.5)
    paid, x, best = [], 50.0, increment(50.0)
    for _ in range(30):  # fly 30 m toward the station at 1 m per step
        prev = state
        state, _ = sim.step(state, act(throttle=1.0), np.random.default_rng(1))
        x -= 1.0
        expected = per_increment if increment(x) < best else 0.0
        best = min(best, increment(x))
        value = term(compiled, "incremental_running_back", prev, state, act(throttle=1.0))[0, 0]
        assert value == pytest.approx(expected), f"at x = {x}"
        paid.append(value)
    assert sum(v > 0 for v in paid) == increment(50.0) - increment(20.0)
    # turning around and coming back over the same increments pays nothing more
    state = replace(state, heading=np.zeros((1, 1)))
    for throttle in [1.0] * 6 + [-1.0] * 6:
        prev = state
        state, _ = sim.step(state, act(throttle=throttle), np.random.default_rng(1))
        assert term(compiled, "incremental_running_back", prev, state, act(throttle=throttle))[0, 0] == 0.0


def test_running_back_ends_at_the_station_and_pays_nothing_for_a_drop_near_it():
    compiled, sim = simulator(drop_min_distance_m=7.5)  # a drop just outside the charge radius
    near = hand_world(sim, [(9.0, 2.0, 2.0)], trees=[(30.0, 2.0)], heading=np.pi)
    state, _ = sim.step(near, act(drop=1), np.random.default_rng(1))
    assert state.dropped[0, 0] and increment(9.0, 2.0) == 3  # its increment is d_charge / s: none closer pays
    total = 0.0
    for _ in range(8):
        prev = state
        state, _ = sim.step(state, act(throttle=1.0), np.random.default_rng(1))
        total += term(compiled, "incremental_running_back", prev, state, act(throttle=1.0))[0, 0]
    assert total == 0.0 and not state.back_active[0, 0]


# ------------------------------------------------------------------ the station
def test_returning_drone_recharges_picks_up_a_seed_and_earns_the_pick_up_reward():
    """Docked, the battery gains charge_per_step (0.1) a step; the return (the seed and its reward) comes on the last
    step of a whole charging cycle, 1 / 0.1 = 10 docked steps, the battery full then: from 0.2995 it is full after 8
    steps and the drone waits 2 more. Recharge Energy Count counts every docked step, full or not."""
    from hivex_dsl.envs.drone_based_reforestation.statistics import STATISTICS

    compiled, sim = simulator()
    recharges = STATISTICS["Recharge Energy Count"].counter
    state = hand_world(sim, [(8.5, 0.0, 2.0)], holding=False, energy=0.3, heading=np.pi)
    state = replace(state, best_distance=np.array([[60.0]]))
    new, outcome = sim.step(state, act(throttle=1.0), np.random.default_rng(1))  # to 7.5 m, 2 m up: 7.77 m
    assert not new.inside[0, 0] and new.energy[0, 0] == pytest.approx(0.3 - 1 / 2000)
    charged, counted = new, 0
    for step in range(1, 11):  # docked at 6.5 m, then drifting to the pad; 0.2995 + 0.1 k, at most 1
        prev, (charged, outcome) = charged, sim.step(charged, act(throttle=1.0 if step == 1 else 0.0),
                                                     np.random.default_rng(1))
        counted += int(recharges(prev, charged, act(), compiled.params)[0, 0])
        assert charged.inside[0, 0] and charged.docked_steps[0, 0] == step
        back = step == 10
        assert charged.energy[0, 0] == pytest.approx(min(1.0, 0.2995 + 0.1 * step))
        assert charged.returned[0, 0] == back and bool(outcome.events["returned_to_station"][0, 0]) == back
        assert charged.holding[0, 0] == back
    assert counted == 10
    assert new.flown[0, 0] == pytest.approx(1.0) and charged.flown[0, 0] == 0.0  # the new seed's path starts here
    assert term(compiled, "pick_up_seed", prev, charged, act())[0, 0] == 1.0
    assert term(compiled, "pick_up_seed_explored", prev, charged, act())[0, 0] == 60.0
    after, _ = sim.step(charged, act(), np.random.default_rng(1))  # staying at the pad is no new return
    assert not after.returned[0, 0] and term(compiled, "pick_up_seed", charged, after, act())[0, 0] == 0.0
    # lingering at the station after the return is no charging: the full battery drains as anywhere (with the new
    # seed, 1/1000 a step); the step is still counted docked
    assert after.energy[0, 0] == pytest.approx(1.0 - 1 / 1000) and recharges(charged, after, act(), compiled.params)[0, 0]


def test_a_docking_lasts_the_whole_charging_cycle_whatever_the_battery_held():
    """The published Recharge Energy Count is about 10 docked steps a return whether the battery came back nearly
    empty (main task) or nearly full (Pick-up Seed, Group Up): a drone back with 0.95 is full on its first docked
    step yet returns on the tenth, and one that leaves before then has made no return (its count starts again)."""
    compiled, sim = simulator()
    state = hand_world(sim, [(6.0, 0.0, 2.0)], holding=False, energy=0.95)
    returns = []
    for _ in range(10):
        state, _ = sim.step(state, act(), np.random.default_rng(1))
        returns.append(bool(state.returned[0, 0]))
        assert state.energy[0, 0] == 1.0
    assert returns == [False] * 9 + [True] and state.holding[0, 0]
    early = hand_world(sim, [(6.0, 0.0, 2.0)], holding=False, energy=0.95, heading=0.0)
    for _ in range(5):
        early, _ = sim.step(early, act(), np.random.default_rng(1))
    assert early.docked_steps[0, 0] == 5
    while early.inside[0, 0]:  # leaves the station at full throttle, outward
        early, _ = sim.step(early, act(throttle=1.0), np.random.default_rng(1))
        assert not early.returned[0, 0]
    assert early.docked_steps[0, 0] == 0 and not early.holding[0, 0]


def test_recharge_energy_count_counts_every_docked_step_from_the_start_where_the_station_serves():
    """The original's untrained policy logs 41 docked steps a drone-episode in the main task, whose drones start on the
    pad, and 0 in Find Closest Tree, Find High Potential Area and Find High Terrain at every point, though their drones
    start there too: the count runs from the first step, the pad included, and is 0 where the station is inert."""
    from hivex_dsl.envs.drone_based_reforestation.statistics import STATISTICS

    recharges = STATISTICS["Recharge Energy Count"].counter
    for task, counted in (("main", 3 * 20), ("explore_furthest", 3 * 20), ("find_high_terrain", 0),
                          ("find_closest_tree", 0), ("find_high_potential_area", 0)):
        compiled = hivex_dsl.compile({"hivex": 1, "environment": ENV, "agents": 3, "task": task})
        sim = compiled.entry.make_simulator(compiled)
        state, total = sim.reset(np.random.default_rng(0), 1), 0
        for _ in range(20):  # hovering on the spawn circle, inside the charge radius
            prev, (state, _) = state, sim.step(state, act(agents=3), np.random.default_rng(1))
            assert state.inside.all()
            total += int(recharges(prev, state, act(agents=3), compiled.params).sum())
        assert total == counted, task


def test_charge_per_step_1_refills_at_once():
    compiled, sim = simulator(charge_per_step=1.0)
    state = hand_world(sim, [(7.0, 0.0, 2.0)], holding=False, energy=0.3)
    state, _ = sim.step(state, act(), np.random.default_rng(1))
    assert state.inside[0, 0] and state.energy[0, 0] == 1.0 and state.returned[0, 0] and state.holding[0, 0]


def test_hovering_across_the_charge_radius_neither_charges_nor_returns():
    """A drone that has not been return_min_distance_m away is on no return: inside the charge radius or out, its
    battery drains 1/2000 a seedless step (8 steps: 0.5 - 0.004), and it takes no seed."""
    compiled, sim = simulator(throttle="signed")
    state = hand_world(sim, [(9.0, 0.0, 2.0)], holding=False, energy=0.5, away=False, heading=np.pi)
    for throttle in (1.0, 1.0, 1.0, -1.0, -1.0, -1.0, 1.0, 1.0):
        state, _ = sim.step(state, act(throttle=throttle), np.random.default_rng(1))
        assert not state.returned[0, 0] and not state.holding[0, 0]
    assert state.inside[0, 0] and state.energy[0, 0] == pytest.approx(0.5 - 8 / 2000)


def test_drones_start_at_the_station_with_a_seed_and_a_full_battery():
    compiled = hivex_dsl.compile(f"{ENV}/main")
    sim = compiled.entry.make_simulator(compiled)
    state = sim.reset(np.random.default_rng(4), 2)
    assert state.inside.all() and state.holding.all() and (state.energy == 1.0).all() and not state.away.any()


def test_pick_up_seed_starts_drones_as_explore_furthest_and_drop_seed_at_the_station_with_one():
    """The original's Pick-up Seed page logs at its first training point exactly what Explore Furthest's does (the
    reward table's note "Pick-up Seed's start and the returns that reload"): its drones start as those do, seedless at
    the station (the paper's text starts them at random; this toolkit did until issue 52). Its Drop Seed page logs
    about one drop and one docking a drone-episode, the drop about 23 m from the station after a 45 m path, and its
    untrained policy earns about 60-75: drones that start at the station holding a seed, as in the main task."""
    starts = {}
    for task in ("pick_up_seed", "explore_furthest", "drop_seed"):
        compiled = hivex_dsl.compile(f"{ENV}/{task}")
        starts[task] = compiled.entry.make_simulator(compiled).reset(np.random.default_rng(4), 4)
    pick_up, explore = starts["pick_up_seed"], starts["explore_furthest"]
    assert np.array_equal(pick_up.position, explore.position) and np.array_equal(pick_up.energy, explore.energy)
    assert pick_up.inside.all() and not pick_up.holding.any() and not pick_up.away.any()
    state = starts["drop_seed"]
    assert state.inside.all() and state.holding.all() and not state.away.any()


def test_in_the_seedless_tasks_a_return_pays_but_hands_over_no_seed_and_no_charge():
    """Pick-up Seed's drones return 9-14 times an episode, Explore Furthest's dock 78-95 steps, yet neither page logs
    a drop at any point (with the policy's entropy still at its start, 1.42-1.44, a held seed would be dropped), and
    both run out in about 0.6 of drone-episodes, the 2 of 3 last-step run-outs of one seedless battery never
    refilled (the reward table's note). So a docking there is a return (+1 on the last of its 10 steps) that leaves
    the drone seedless and draining 1/2000 a step, docked or not."""
    compiled = hivex_dsl.compile({"hivex": 1, "environment": ENV, "task": "pick_up_seed"})
    sim = compiled.entry.make_simulator(compiled)
    state = hand_world(sim, [(8.5, 0.0, 2.0)], holding=False, energy=0.3, heading=np.pi)
    state, _ = sim.step(state, act(throttle=1.0), np.random.default_rng(1))  # 7.77 m: docked from the next step
    for step in range(1, 11):
        prev = state
        state, outcome = sim.step(state, act(throttle=1.0 if step == 1 else 0.0), np.random.default_rng(1))
        assert state.docked_steps[0, 0] == step and state.returned[0, 0] == (step == 10)
        assert state.energy[0, 0] == pytest.approx(0.3 - (step + 1) / 2000) and not state.holding[0, 0]
    assert compiled.weights["pick_up_seed"] * term(compiled, "pick_up_seed", prev, state, act())[0, 0] == 1.0
    assert bool(outcome.events["returned_to_station"][0, 0])


def test_a_drop_s_reward_statistics_are_logged_where_a_scenario_weighs_drops_0():
    """A main task that weighs drop_seed 0 (no paper task does since issue 52: the seedless tasks never hold a seed)
    logs a drop's statistics as the drop's reward as computed all the same. The scripted pilot drops near the forest,
    flies back for a seed and drops again."""
    compiled = hivex_dsl.compile({"hivex": 1, "environment": ENV, "task": "main", "terrain_level": 1,
                                  "weights": {"drop_seed": 0.0}, "params": {"camera_images": "rendered"}})
    assert compiled.weights["drop_seed"] == 0.0
    done = rollout(compiled, "scripted", 1)
    drops = done.statistics["Tree Drop Count"]
    assert (drops >= 1).all()
    assert (done.statistics["Cumulative Tree Drop Reward"] > 0).all()
    assert "drop_seed" not in done.terms  # a term weighted 0 is not computed, nor paid


# ------------------------------------------------------------------ energy
def test_energy_drains_1_1000_with_a_seed_and_1_2000_without_and_an_empty_battery_ends_only_that_drone():
    compiled, sim = simulator(agents=2)
    state = hand_world(sim, [(100.0, 0.0, 10.0), (-100.0, 0.0, 10.0)], energy=0.0105)
    state = replace(state, holding=np.array([[True, False]]))
    prev, (state, outcome) = state, sim.step(state, act(agents=2), np.random.default_rng(1))
    assert state.energy[0].tolist() == pytest.approx([0.0095, 0.01])
    assert term(compiled, "deplete_energy_holding_seed", prev, state, act(agents=2))[0].tolist() == [-0.001, 0.0]
    assert term(compiled, "deplete_energy_no_seed", prev, state, act(agents=2))[0].tolist() == [0.0, -0.0005]
    for _ in range(9):
        state, outcome = sim.step(state, act(agents=2, throttle=1.0), np.random.default_rng(1))
    assert outcome.terminated[0].tolist() == [False, False]
    state, outcome = sim.step(state, act(agents=2, throttle=1.0), np.random.default_rng(1))
    assert outcome.terminated[0].tolist() == [True, False] and state.energy[0, 0] == 0.0
    frozen = state.position[0, 0].copy()
    state, outcome = sim.step(state, act(agents=2, throttle=1.0, drop=1), np.random.default_rng(1))
    assert np.array_equal(state.position[0, 0], frozen) and not state.dropped[0, 0] and state.energy[0, 0] == 0.0
    assert not outcome.terminated[0, 1] and state.position[0, 1, 0] != -100.0


# ------------------------------------------------------------------ the exploration terms
def test_group_up_pays_10_while_another_live_drone_is_closer_than_5_m():
    compiled, sim = simulator(agents=3)
    state = hand_world(sim, [(50.0, 0.0, 10.0), (50.0, 4.0, 10.0), (50.0, 40.0, 10.0)])
    new, _ = sim.step(state, act(agents=3), np.random.default_rng(1))
    assert term(compiled, "group_up", state, new, act(agents=3))[0].tolist() == [10.0, 10.0, 0.0]
    dead = replace(new, alive=np.array([[True, False, True]]))
    assert term(compiled, "group_up", new, dead, act(agents=3))[0].tolist() == [0.0, 10.0, 0.0]
    apart = hand_world(sim, [(50.0, 0.0, 10.0), (50.0, 5.5, 10.0), (50.0, 40.0, 10.0)])
    new, _ = sim.step(apart, act(agents=3), np.random.default_rng(1))
    assert term(compiled, "group_up", apart, new, act(agents=3))[0].tolist() == [0.0, 0.0, 0.0]


def test_find_close_tree_pays_100_within_20_m():
    compiled, sim = simulator()
    for y, expected in ((18.0, 100.0), (26.0, 0.0)):  # drone over a forest cell centre 16 m / 24 m from the tree
        state = hand_world(sim, [(2.0, y, 10.0)], trees=[(2.0, 2.0)])
        new, outcome = sim.step(state, act(), np.random.default_rng(1))
        assert term(compiled, "find_close_tree", state, new, act())[0, 0] == expected
        assert outcome.events["found_close_tree"][0, 0] == (expected > 0)


def test_high_fertility_delta_pays_the_gain_in_potential_and_ignores_spots_next_to_planted_trees():
    compiled, sim = simulator()
    state = hand_world(sim, [(2.0, 18.0, 10.0)], trees=[(2.0, 2.0)])  # det 16 m: potential 59 / 72.5
    gains = []
    for y in (18.0, 18.0, 10.0, 30.0):  # det 16, 16, 8 (potential 67 / 72.5), 28
        moved = replace(state, position=np.array([[[2.0, y, 10.0]]]))
        prev, (state, _) = moved, sim.step(moved, act(), np.random.default_rng(1))
        gains.append(term(compiled, "high_fertility_location_delta", prev, state, act())[0, 0])
    assert gains == pytest.approx([59.0 / 72.5, 0.0, 8.0 / 72.5, 0.0])
    crowded = hand_world(sim, [(2.0, 10.0, 10.0)], trees=[(2.0, 2.0)])
    crowded.new_trees[0, 0] = (3.0, 10.0)
    crowded = replace(crowded, new_count=np.array([1]))
    new, _ = sim.step(crowded, act(), np.random.default_rng(1))
    assert term(compiled, "high_fertility_location_delta", crowded, new, act())[0, 0] == 0.0


def test_high_landscape_delta_pays_each_new_height_of_the_drone_not_of_the_ground_below():
    # the published "Highest Point on Terrain Found" is 44.5-47.2 m at every terrain level 1-10 (our level-1 peaks
    # are 8 m, level-10 peaks 30 m): the original rewards the drone's own height, up to the height bound
    compiled, sim = simulator()
    coords = sim.terrain_grid.origin + sim.terrain_grid.cell * np.arange(sim.terrain_grid.n)
    slope = np.broadcast_to(np.clip(coords / 10.0, 0.0, None)[None, :], (sim.terrain_grid.n,) * 2)  # h = x / 10
    state = hand_world(sim, [(50.0, 30.0, 20.0)], heights=slope)
    gains = []
    top = compiled.params.height_bound_m
    for x, z in ((50.0, 20.0), (62.5, 20.0), (40.0, 26.0), (70.0, 23.0), (70.0, top - 0.2)):  # ground 5, 6.25, 4, 7, 7
        moved = replace(state, position=np.array([[[x, 30.0, z]]]))
        prev, (state, _) = moved, sim.step(moved, act(updown=1.0), np.random.default_rng(1))  # climbs 0.5 m
        gains.append(term(compiled, "high_landscape_point_delta", prev, state, act(updown=1.0))[0, 0])
    # heights after the step: 20.5, 20.5, 26.5, 23.5, the bound: gains from 0
    assert gains == pytest.approx([20.5, 0.0, 6.0, 0.0, top - 26.5])


def test_far_distance_delta_pays_each_new_furthest_distance_capped_at_the_half_extent():
    compiled, sim = simulator()
    state = hand_world(sim, [(30.0, 40.0, 10.0)])
    gains = []
    for x, y in ((30.0, 40.0), (0.0, 80.0), (10.0, 10.0), (190.0, 190.0)):  # 50, 80, 14, 269 -> 200
        moved = replace(state, position=np.array([[[x, y, 10.0]]]))
        prev, (state, _) = moved, sim.step(moved, act(), np.random.default_rng(1))
        gains.append(term(compiled, "far_distance_explored_delta", prev, state, act())[0, 0])
    assert gains == pytest.approx([50.0, 30.0, 0.0, 120.0])


# ------------------------------------------------------------------ issue 15: the readings the published results support
def test_a_12_m_drop_pays_one_running_back_increment_not_a_second_on_entering_the_charge_radius():
    compiled, sim = simulator(drop_min_distance_m=7.5)  # a drop 12 m out
    state = hand_world(sim, [(12.0, 2.0, 1.5)], trees=[(22.0, 2.0)], heading=np.pi)
    state, _ = sim.step(state, act(drop=1), np.random.default_rng(1))
    r_s = 20.0 * (75.0 - 10.0) / 72.5  # det 10 m
    r_d = 10.0 * np.hypot(12.0, 2.0) / 200.0
    rbm = (r_s + r_d) / 30.0
    d_init = np.sqrt(144.0 + 4.0 + 2.25)  # 12.26 m, increment 4
    paid = []
    for _ in range(10):  # 12 m -> 2 m: increments 3 (7.5-10 m), then 2 and 1 inside the charge radius
        prev = state
        state, _ = sim.step(state, act(throttle=1.0), np.random.default_rng(1))
        paid.append(term(compiled, "incremental_running_back", prev, state, act(throttle=1.0))[0, 0])
    # one increment (4 -> 3) pays r_p * rbm / (12.26 - 3) = 0.59 (before issue 52: r_p * rbm / (4 - 3) = 6.4); the
    # increments inside the charge radius pay nothing (before issue 15 the next one paid again)
    assert sum(paid) == pytest.approx(20.0 * rbm / (d_init - 3.0)) and sum(v > 0 for v in paid) == 1


def test_a_whole_run_back_from_51_m_pays_17_increments_of_r_p_rbm_over_d_init_minus_3():
    """From (50, 2, 10), 51.03 m and increment 20, straight home: increments 19 down to 3 pay, 17 of them, each
    20 rbm / 48.03: 7.08 rbm in all, where d_init read as the increment (before issue 52) paid the whole 20 rbm."""
    compiled, sim = simulator()
    state = hand_world(sim, [(50.0, 2.0, 10.0)], trees=[(54.0, 2.0)], heading=np.pi)
    state, _ = sim.step(state, act(drop=1), np.random.default_rng(1))
    rbm = (20.0 * (75.0 - 4.0) / 72.5 + 10.0 * np.hypot(50.0, 2.0) / 200.0) / 30.0  # det 4 m
    total = 0.0
    for _ in range(60):
        prev = state
        state, _ = sim.step(state, act(throttle=1.0, updown=-1.0), np.random.default_rng(1))
        total += term(compiled, "incremental_running_back", prev, state, act(throttle=1.0))[0, 0]
    assert total == pytest.approx(17 * 20.0 * rbm / (np.sqrt(2604.0) - 3.0))
    assert total == pytest.approx(7.08 * rbm, abs=0.01)


def test_the_first_step_after_reset_pays_nothing_in_the_potential_and_distance_terms_and_the_height_from_0():
    compiled = hivex_dsl.compile({"hivex": 1, "environment": ENV, "terrain_level": 3})
    sim = compiled.entry.make_simulator(compiled)
    state = sim.reset(np.random.default_rng(11), 3)
    spawn = state.position
    horizontal = np.hypot(spawn[..., 0] - state.station[:, None, 0], spawn[..., 1] - state.station[:, None, 1])
    assert np.allclose(state.best_distance, horizontal) and np.all(state.best_height == 0.0)
    hover = {"continuous": np.zeros((3, 3, 3), np.float32), "discrete": np.zeros((3, 3, 1), np.int64)}
    new, _ = sim.step(state, hover, np.random.default_rng(1))
    for name in ("high_fertility_location_delta", "far_distance_explored_delta"):
        assert np.all(term(compiled, name, state, new, hover) == 0.0), name
    # the paper's h_old = 0: the first step pays the height the drone hovers at (station + 2 m)
    paid = term(compiled, "high_landscape_point_delta", state, new, hover)
    assert np.allclose(paid, spawn[..., 2]) and np.all(paid > 2.0)


@pytest.mark.parametrize("agents, radius", [(3, 6.0), (4, 7.0710678), (12, 19.3185165)])
def test_drones_start_on_a_circle_at_least_10_m_apart_so_none_is_grouped_up_at_the_start(agents, radius):
    # radius max(6, 10 / (2 sin(pi / A))): 3 drones 10.4 m apart on 6 m; 12 drones on 19.3 m (on 6 m: 3.1 m apart)
    compiled = hivex_dsl.compile({"hivex": 1, "environment": ENV, "agents": agents, "terrain_level": 1})
    sim = compiled.entry.make_simulator(compiled)
    state = sim.reset(np.random.default_rng(2), 2)
    offset = state.position[..., :2] - state.station[:, None, :2]
    assert np.allclose(np.hypot(offset[..., 0], offset[..., 1]), radius)
    gaps = np.linalg.norm(state.position[:, :, None] - state.position[:, None], axis=-1) + 1e9 * np.eye(agents)
    assert gaps.min() >= 10.0 - 1e-6
    hover = {"continuous": np.zeros((2, agents, 3), np.float32), "discrete": np.zeros((2, agents, 1), np.int64)}
    new, _ = sim.step(state, hover, np.random.default_rng(1))
    assert np.all(term(compiled, "group_up", state, new, hover) == 0.0)
    assert not state.away.any()  # starting outside the charge radius is no trip: no pick-up reward for flying in


def test_group_up_drones_start_scattered_like_pick_up_seed():
    compiled = hivex_dsl.compile(f"{ENV}/group_up")
    sim = compiled.entry.make_simulator(compiled)
    state = sim.reset(np.random.default_rng(4), 4)
    horizontal = np.linalg.norm(state.position[..., :2] - state.station[:, None, :2], axis=-1)
    assert (horizontal >= 20.0 - 1e-9).all() and not state.holding.any()


def test_a_seed_dropped_just_outside_the_pad_earns_what_the_original_s_drops_near_the_station_did():
    """Trees are cleared within 45 m of the station: det >= 45 - 9 = 36 m, so a drop 9 m out earns at most
    r_s + r_d = 20 (75 - 36) / 72.5 + 10 x 9 / 200 = 11.2, and the forest's patches lie at uneven distances: over 32
    worlds x 3 directions such drops earn 4.5 on average (8 worlds: 2.9), near the original's 4.1 a drop within 20 m
    of the station (tests/fidelity/test_dbr_drop_pay.py; its untrained policy's first drops, 19 m out, 4.9 + 1.0)."""
    compiled = hivex_dsl.compile({"hivex": 1, "environment": ENV, "terrain_level": 1})
    sim = compiled.entry.make_simulator(compiled)
    state = sim.reset(np.random.default_rng(5), 32)
    angle = np.linspace(0.0, 2.0 * np.pi, 3, endpoint=False)
    xy = state.station[:, None, :2] + 9.0 * np.stack([np.cos(angle), np.sin(angle)], axis=-1)[None]
    state = replace(state, position=np.concatenate([xy, np.full(xy.shape[:2] + (1,), 30.0)], axis=-1))
    drop = {"continuous": np.zeros((32, 3, 3), np.float32), "discrete": np.ones((32, 3, 1), np.int64)}
    new, _ = sim.step(state, drop, np.random.default_rng(1))
    assert new.dropped.all()
    pay = term(compiled, "drop_seed", state, new, drop)
    assert np.all(pay <= 20.0 * (75.0 - 36.0) / 72.5 + 10.0 * 9.0 / 200.0 + 1e-9)
    assert 3.0 < pay.mean() < 6.5


def test_explore_furthest_pays_the_explored_distance_over_the_half_extent():
    # published: "Furthest Distance Explored" 152 m but a return of 8.0, so the metres cannot be paid 1:1
    compiled = hivex_dsl.compile({"hivex": 1, "environment": ENV, "task": "explore_furthest", "agents": 1})
    sim = compiled.entry.make_simulator(compiled)
    composer = RewardComposer(compiled.entry.terms, compiled.weights)
    state = replace(hand_world(sim, [(80.0, 0.0, 10.0)]), best_distance=np.array([[50.0]]))
    new, _ = sim.step(state, act(), np.random.default_rng(1))  # hovering 80 m out, 50 m the furthest before
    rewards, terms = composer(state, new, act(), compiled.params, (1, 1))
    assert terms["far_distance_explored_delta"][0, 0] == pytest.approx(30.0)  # the term stays in metres
    assert rewards[0, 0] == pytest.approx(30.0 / 200.0 - 1.0 / 1000.0)  # holding a seed: -1/1000 a step


def test_distance_until_tree_drop_is_the_path_flown_since_the_seed_was_taken():
    """The published ratio of "Cumulative Distance Until Tree Drop" to its normalised station distance (x 200 for a
    straight line) is 303 in the main task and 389 in Pick-up Seed: the original logs the path flown, not the
    station distance. By hand: 6 steps east at full throttle, a U-turn leg back west, then the drop."""
    from hivex_dsl.envs.drone_based_reforestation.statistics import STATISTICS

    compiled, sim = simulator()
    state = hand_world(sim, [(100.0, 0.0, 10.0)])
    assert state.flown.tolist() == [[0.0]]
    rng = np.random.default_rng(1)
    path = 0.0
    for actions in [act(throttle=1.0)] * 6 + [act(throttle=1.0, steer=1.0)] * 3:
        before = state.position.copy()
        state, _ = sim.step(state, actions, rng)
        path += float(np.linalg.norm(state.position - before))
    assert path > 6 * sim.params.drone_speed_m * 0.99  # it flew, at about drone_speed_m a step
    prev, (state, _) = state, sim.step(state, act(drop=1), rng)
    assert state.dropped[0, 0]
    counter = STATISTICS["Cumulative Distance Until Tree Drop"].counter
    assert counter(prev, state, act(drop=1), compiled.params)[0, 0] == pytest.approx(path)  # hovering adds nothing
    straight = np.hypot(*(state.position[0, 0, :2] - state.station[0, :2]))
    assert path != pytest.approx(straight)


@pytest.mark.parametrize("mapping, throttle, metres", [("forward", 1.0, 1.0), ("forward", 0.5, 0.5),
                                                        ("forward", -1.0, 0.0), ("forward", -0.3, 0.0),
                                                        ("signed", -1.0, -1.0), ("signed", 0.5, 0.5)])
def test_the_throttle_flies_forward_only_unless_signed(mapping, throttle, metres):
    """'forward' (the default): max(a, 0) x drone_speed_m (1 m) along the heading, a negative throttle hovers;
    'signed': a x drone_speed_m, backwards below 0."""
    compiled, sim = simulator(throttle=mapping)
    state = hand_world(sim, [(30.0, 0.0, 5.0)], heading=np.pi / 2)  # facing +y
    state, _ = sim.step(state, act(throttle=throttle), np.random.default_rng(1))
    assert state.position[0, 0, :2] == pytest.approx([30.0, metres])


@pytest.mark.parametrize("distance_m, drops", [(10.0, False), (17.4, False), (17.6, True), (40.0, True)])
def test_a_seed_drops_only_drop_min_distance_m_from_the_station(distance_m, drops):
    """The default drop_min_distance_m is 17.5 m (3D; the drone 2 m over flat ground at the station's height)."""
    compiled, sim = simulator()
    horizontal = float(np.sqrt(distance_m**2 - 2.0**2))
    state = hand_world(sim, [(horizontal, 0.0, 2.0)], trees=[(horizontal + 10.0, 0.0)])
    state, _ = sim.step(state, act(drop=1), np.random.default_rng(1))
    assert bool(state.dropped[0, 0]) is drops and bool(state.holding[0, 0]) is not drops


def test_drop_min_distance_m_below_the_charge_radius_is_refused():
    with pytest.raises(Exception, match="drop_min_distance_m"):
        simulator(drop_min_distance_m=5.0)
