"""Drone-Based Reforestation's logged statistics against its return (issue 33): each relation below holds in the
paper's published cells, to their rounding, and in this toolkit's episodes.

1. Cumulative Distance Reward = 10 x Cumulative Normalized Distance Until Tree Drop: a drop's r_d is 10 sdd / 200 and
   the normalised statistic logs sdd / 200 (all 20 published cells with drops agree to 0.0005).
2. Where drops are paid (the main task, weight 1), the drop reward is r_s + r_d: the drop_seed term's episode sum is
   Cumulative Tree Drop Reward + Cumulative Distance Reward.
3. In Find High Potential Area and Find High Terrain the best-so-far statistic is what the task pays, and the rest of
   the return is the energy penalty, one battery at most where no drone recharges: 0 <= statistic - return <= 1
   (published: 0.82 to 0.997 at every level, with Recharge Energy Count 0; here too: the drones start seedless and
   drain from the first step, 1/2000 of a battery a step, so an episode costs at most one battery).
4. Pick-up Seed pays a pick-up (+1) a return, and every return docks a whole charging cycle (10 steps): return + 1 =
   Recharge Energy Count / 10 or so (published: 9.2 to 11.5 docked steps a return at every level, the battery's -1
   taken off; Drop Seed, whose episode ends on its one return, 10.6 to 11.1).
5. Drop Seed pays its drops and +100 for the return that ends its episode (issue 52): the published return is
   100 x (1 - Out of Energy Count) + Cumulative Tree Drop Reward + Cumulative Distance Reward to within its spread at
   every level, and above 100 where the drops pay more than the battery costs (8 of 10 levels). The run home's
   running back (about 1.1) is within that spread; test_dbr_running_back.py checks it.
"""

from __future__ import annotations

import numpy as np
import pytest

import hivex_dsl
from hivex_dsl.evaluation import published
from hivex_dsl.evaluation.rollout import rollout

ENV = "drone_based_reforestation"
ENERGY_TERMS = ("deplete_energy_holding_seed", "deplete_energy_no_seed")
BEST_SO_FAR = {"find_high_potential_area": ("Highest Potential Soild Found", "high_fertility_location_delta"),
               "find_high_terrain": ("Highest Point on Terrain Found", "high_landscape_point_delta")}


def compiled(task: str, level: int = 1):
    """The task with the camera drawn: the scripted pilot finds the forest with it (blind, its drops pay little)."""
    return hivex_dsl.compile({"hivex": 1, "environment": ENV, "task": task, "terrain_level": level,
                              "params": {"camera_images": "rendered"}})


def mean(cell: published.PublishedCell, name: str) -> float:
    return cell.statistic(name)[0]


def test_published_distance_reward_is_ten_times_the_normalized_distance():
    cells = [c for c in published.cells(ENV) if mean(c, "Cumulative Distance Reward")]
    assert len(cells) == 20  # main and Drop Seed at ten levels
    for cell in cells:
        normalized = mean(cell, "Cumulative Normalized Distance Until Tree Drop")
        assert mean(cell, "Cumulative Distance Reward") == pytest.approx(10 * normalized, abs=6e-4), cell


@pytest.mark.parametrize("task", ["main", "drop_seed"])
@pytest.mark.parametrize("policy", ["scripted", "random"])
def test_our_distance_reward_is_ten_times_the_normalized_distance(task, policy):
    done = rollout(compiled(task), policy, 1)
    normalized = done.statistics["Cumulative Normalized Distance Until Tree Drop"]
    assert np.allclose(done.statistics["Cumulative Distance Reward"], 10 * normalized)
    if policy == "scripted":  # the relation is not 0 = 0: every drop of the pilot's pays a distance reward
        dropped = done.statistics["Tree Drop Count"] > 0
        assert dropped.sum() >= 2 and (done.statistics["Cumulative Distance Reward"][dropped] > 0).all()


@pytest.mark.parametrize("policy", ["scripted", "random"])
def test_the_main_task_pays_each_drop_its_tree_drop_reward_plus_its_distance_reward(policy):
    done = rollout(compiled("main"), policy, 1)
    logged = done.statistics["Cumulative Tree Drop Reward"] + done.statistics["Cumulative Distance Reward"]
    assert done.compiled.weights["drop_seed"] == 1.0
    assert np.allclose(done.terms["drop_seed"], logged)
    if policy == "scripted":
        assert (logged > 0).all()


@pytest.mark.parametrize("task", sorted(BEST_SO_FAR))
def test_published_best_so_far_statistics_exceed_the_return_by_at_most_one_battery(task):
    name, _ = BEST_SO_FAR[task]
    index = published.paper_cell(compiled(task)).task_index
    cells = [c for c in published.cells(ENV) if c.task_index == index]
    assert len(cells) == 10
    for cell in cells:
        assert mean(cell, "Recharge Energy Count") == 0.0, cell
        assert 0.0 <= mean(cell, name) - cell.return_mean <= 1.0, cell


@pytest.mark.parametrize("task", sorted(BEST_SO_FAR))
@pytest.mark.parametrize("policy", ["scripted", "random"])
def test_our_best_so_far_statistic_is_what_the_task_pays_and_the_rest_is_energy(task, policy):
    name, term = BEST_SO_FAR[task]
    done = rollout(compiled(task), policy, 1)
    assert np.allclose(done.statistics[name], done.weighted(term))
    energy = sum(done.weighted(t) for t in ENERGY_TERMS)
    assert np.allclose(done.returns, done.statistics[name] + energy)
    # at most one seedless battery's worth of energy penalty (2,000 steps at 1/2000) where a drone never docks
    charged = done.statistics["Recharge Energy Count"] > 0
    gap = (done.statistics[name] - done.returns)[~charged]
    assert ((gap >= 0.0) & (gap <= 1.0 + 1e-9)).all()


PICK_UP_SEED, DROP_SEED = 3, 4  # this toolkit's task indices (the configs that ran: 2 and 3)


def test_published_pick_up_seed_returns_are_one_pick_up_a_docking_cycle_less_one_battery():
    cells = [c for c in published.cells(ENV) if c.task_index == PICK_UP_SEED]
    assert len(cells) == 10
    count = np.array([mean(c, "Recharge Energy Count") for c in cells])
    returns = np.array([c.return_mean for c in cells])
    assert ((count / (returns + 1) > 9.0) & (count / (returns + 1) < 12.0)).all()
    slope, intercept = np.polyfit(count, returns, 1)
    assert 0.09 < slope < 0.11 and -2.0 < intercept < 0.0  # +1 a return of ~10 docked steps, -1 of battery
    drop = [c for c in published.cells(ENV) if c.task_index == DROP_SEED]  # ends on its one return
    assert all(10.0 < mean(c, "Recharge Energy Count") < 11.5 for c in drop)


@pytest.mark.parametrize("policy", ["scripted", "random"])
def test_our_pick_up_seed_pays_returns_running_back_and_energy_and_nothing_for_drops(policy):
    done = rollout(compiled("pick_up_seed"), policy, 1)
    assert done.compiled.weights["group_up"] == 0.0 and done.compiled.weights["drop_seed"] == 0.0
    paid = done.weighted("pick_up_seed") + done.weighted("incremental_running_back")
    assert np.allclose(done.returns, paid + sum(done.weighted(t) for t in ENERGY_TERMS))
    if policy == "scripted":
        assert (done.terms["pick_up_seed"] > 0).all()  # the relation is not 0 = 0


def test_our_group_up_pays_its_grouping():
    """Group Up has no record of its own (the configs that ran have no such task); it pays the paper's Group-up reward,
    which the scripted pilot earns by meeting the others at the station."""
    done = rollout(compiled("group_up"), "scripted", 1)
    assert done.compiled.weights["group_up"] == 1.0
    paid = sum(done.weighted(t) for t in ("group_up", "pick_up_seed", "incremental_running_back", *ENERGY_TERMS))
    assert np.allclose(done.returns, paid)
    assert (done.terms["group_up"] > 0).all()


def test_published_drop_seed_returns_are_the_logged_statistics_times_our_weights():
    """A Drop Seed drone-episode ends on its return (+100, pick_up_seed weighted 100) unless the battery runs out
    first, and pays its drops (drop_seed weighted 1, logged as Tree Drop Reward + Distance Reward): the published
    return is their sum to within its spread at every level. With drops weighted 0 (the former reading, which
    filed this cell under Pick-up Seed) it misses by 4.1-5.6, beyond the spread at most levels."""
    weights = compiled("drop_seed").weights
    cells = [c for c in published.cells(ENV) if c.task_index == DROP_SEED]
    assert len(cells) == 10
    above_100 = 0
    for cell in cells:
        returns = 1.0 - mean(cell, "Out of Energy Count")
        drops = mean(cell, "Cumulative Tree Drop Reward") + mean(cell, "Cumulative Distance Reward")
        predicted = weights["pick_up_seed"] * returns + weights["drop_seed"] * drops
        assert abs(cell.return_mean - predicted) <= cell.return_std, cell
        above_100 += cell.return_mean > 100.0
    assert above_100 == 8


def test_our_drop_seed_returns_exceed_100_as_the_original_s_do():
    """The scripted pilot drops its seed near the forest and flies back: +100 for the return that ends its episode,
    plus the drop and its run home (the running back, weighted 1 as the paper's column: tests/fidelity/
    test_dbr_running_back.py), less the battery. (A pilot that finds no spot before its battery runs low comes home
    with its seed: the return still ends the episode, 100 less the battery.)"""
    done = rollout(compiled("drop_seed"), "scripted", 1)
    assert (done.terms["pick_up_seed"] == 1.0).all()  # one return each, which ends the episode
    logged = done.statistics["Cumulative Tree Drop Reward"] + done.statistics["Cumulative Distance Reward"]
    dropped = done.statistics["Tree Drop Count"] > 0
    assert np.allclose(done.weighted("drop_seed"), logged) and dropped.sum() >= 2 and (logged[dropped] > 0).all()
    energy = sum(done.weighted(t) for t in ENERGY_TERMS)
    running_back = done.weighted("incremental_running_back")
    assert (running_back[dropped] > 0).all() and (running_back[~dropped] == 0).all()
    assert np.allclose(done.returns, 100.0 + logged + running_back + energy)
    assert (done.returns[dropped] > 100.0).all()


@pytest.mark.parametrize("task", ["main", "pick_up_seed", "drop_seed"])
def test_every_return_docks_a_whole_charging_cycle(task):
    done = rollout(compiled(task), "scripted", 1)
    cycle = round(1 / done.compiled.params.charge_per_step)
    returns = done.terms["pick_up_seed"]
    assert (returns > 0).all()
    assert (done.statistics["Recharge Energy Count"] >= cycle * returns).all()
    if task == "drop_seed":  # its episode ends on the return: the cycle, and a pass over the pad shorter than one
        assert (done.statistics["Recharge Energy Count"] < cycle * (returns + 1)).all()


@pytest.mark.parametrize("level", [1, 10])
def test_a_climb_only_policy_reaches_the_published_find_high_terrain_statistic_at_every_level(level):
    """The original's Find High Terrain statistic is 44.5-47.2 m at every level, its training runs' summary points up
    to 53.5-56.3 m (their mean) and 62.7 m (their band), its untrained policy's about 24 m (issue 52): the drones' own
    height, from 0 as the paper's h_old, under a bound above every point. A drone that only climbs reaches the bound
    at every level; the former reading (the rise above the spawn under a 40 m bound) gave 36-37 m at level 1 and 31 m
    at level 10."""
    task = compiled("find_high_terrain", level)
    done = rollout(task, "scripted", 1)  # the scripted pilot only climbs in this task
    reached = done.statistics["Highest Point on Terrain Found"]
    assert np.allclose(reached, task.params.height_bound_m)
    cells = [c for c in published.cells(ENV) if c.task_index == published.paper_cell(task).task_index]
    assert len(cells) == 10
    assert max(mean(c, "Highest Point on Terrain Found") + 2 * c.statistic("Highest Point on Terrain Found")[1]
               for c in cells) < task.params.height_bound_m
    assert (reached > mean(published.paper_cell(task), "Highest Point on Terrain Found")).all()
    # random flying stays below the paper's PPO; at period 5 it climbs above the untrained policy's 24 m (holding
    # its up/down five steps): an open gap, the reward table's Find High Terrain note
    random = rollout(task, "random", 1).statistics["Highest Point on Terrain Found"]
    assert random.mean() < mean(published.paper_cell(task), "Highest Point on Terrain Found")
