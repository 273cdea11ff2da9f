"""Drone-Based Reforestation's logged statistics against its return (issue 33): each relation below holds in the
paper's published cells, to their rounding, and in this toolkit's episodes.

1. Cumulative Distance Reward = 10 x Cumulative Normalized Distance Until Tree Drop: a drop's r_d is 10 sdd / 200 and
   the normalised statistic logs sdd / 200 (all 20 published cells with drops agree to 0.0005).
2. Where drops are paid (the main task, weight 1), the drop reward is r_s + r_d: the drop_seed term's episode sum is
   Cumulative Tree Drop Reward + Cumulative Distance Reward.
3. In Find High Potential Area and Find High Terrain the best-so-far statistic is what the task pays, and the rest of
   the return is the energy penalty, one battery at most where no drone recharges: 0 <= statistic - return <= 1
   (published: 0.82 to 0.997 at every level, with Recharge Energy Count 0; here a drone's first steps on its pad
   add a few thousandths).
4. Group Up pays a pick-up (+1) a return and nothing for grouping, and every return docks a whole charging cycle (10
   steps): return + 1 = Recharge Energy Count / 10 or so (published: 9.2 to 11.5 docked steps a return at every level,
   the battery's -1 taken off; Pick-up Seed, whose episode ends on its one return, 10.6 to 11.1).
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
    return hivex_dsl.compile({"hivex": 1, "environment": ENV, "task": task, "terrain_level": level})


def mean(cell: published.PublishedCell, name: str) -> float:
    return cell.statistic(name)[0]


def test_published_distance_reward_is_ten_times_the_normalized_distance():
    cells = [c for c in published.cells(ENV) if mean(c, "Cumulative Distance Reward")]
    assert len(cells) == 20  # main and Pick-up Seed at ten levels
    for cell in cells:
        normalized = mean(cell, "Cumulative Normalized Distance Until Tree Drop")
        assert mean(cell, "Cumulative Distance Reward") == pytest.approx(10 * normalized, abs=6e-4), cell


@pytest.mark.parametrize("task", ["main", "pick_up_seed"])
@pytest.mark.parametrize("policy", ["scripted", "random"])
def test_our_distance_reward_is_ten_times_the_normalized_distance(task, policy):
    done = rollout(compiled(task), policy, 1)
    normalized = done.statistics["Cumulative Normalized Distance Until Tree Drop"]
    assert np.allclose(done.statistics["Cumulative Distance Reward"], 10 * normalized)
    if policy == "scripted":
        assert (done.statistics["Cumulative Distance Reward"] > 0).all()  # the relation is not 0 = 0


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
    # one battery's worth of energy penalty where a drone never docks again, plus its first steps on the pad, which
    # are penalised (1/1000 a step with a seed) while the docked battery stays full: the scripted pilot needs 4
    charged = done.statistics["Recharge Energy Count"] > 0
    gap = (done.statistics[name] - done.returns)[~charged]
    assert ((gap >= 0.0) & (gap <= 1.0 + 10 / 1000)).all()


GROUP_UP = 2  # the configs' task index


def test_published_group_up_returns_are_one_pick_up_a_docking_cycle_less_one_battery():
    cells = [c for c in published.cells(ENV) if c.task_index == GROUP_UP]
    assert len(cells) == 10
    count = np.array([mean(c, "Recharge Energy Count") for c in cells])
    returns = np.array([c.return_mean for c in cells])
    assert ((count / (returns + 1) > 9.0) & (count / (returns + 1) < 12.0)).all()
    slope, intercept = np.polyfit(count, returns, 1)
    assert 0.09 < slope < 0.11 and -2.0 < intercept < 0.0  # +1 a return of ~10 docked steps, -1 of battery
    pick_up = [c for c in published.cells(ENV) if c.task_index == 3]  # ends on its one return
    assert all(10.0 < mean(c, "Recharge Energy Count") < 11.5 for c in pick_up)


@pytest.mark.parametrize("policy", ["scripted", "random"])
def test_our_group_up_pays_returns_running_back_and_energy_and_nothing_for_grouping(policy):
    done = rollout(compiled("group_up"), policy, 1)
    assert done.compiled.weights["group_up"] == 0.0
    paid = done.weighted("pick_up_seed") + done.weighted("incremental_running_back")
    assert np.allclose(done.returns, paid + sum(done.weighted(t) for t in ENERGY_TERMS))
    if policy == "scripted":
        assert (done.terms["pick_up_seed"] > 0).all()  # the relation is not 0 = 0


@pytest.mark.parametrize("task", ["main", "group_up", "pick_up_seed"])
def test_every_return_docks_a_whole_charging_cycle(task):
    done = rollout(compiled(task), "scripted", 1)
    cycle = round(1 / done.compiled.params.charge_per_step)
    returns = done.terms["pick_up_seed"]
    assert (returns > 0).all()
    assert (done.statistics["Recharge Energy Count"] >= cycle * returns).all()
    if task == "pick_up_seed":  # its episode ends on the return: the cycle is all it docks
        assert (done.statistics["Recharge Energy Count"] == cycle * returns).all()
