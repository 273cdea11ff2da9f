"""The statistics Drone-Based Reforestation logs ("DroneBasedReforestation/<name>"), read from the drone state.

The best-so-far statistics (highest potential, point, distance) are summed as per-step increases of the
drone's best value, so an episode's sum is how far the best rose above where it started (the spawn point's
value for potential and distance, 0 for the height): what the matching delta term pays, unweighted (the
published values of these statistics are close to their tasks' returns, e.g. 46.8 against 45.9 in Find High
Terrain).
"""

from __future__ import annotations

import numpy as np

from ...sim.statistics import StatisticSet
from .planting import DISTANCE_REWARD_MULTIPLIER

STATISTICS = StatisticSet("drone_based_reforestation", "DroneBasedReforestation")


@STATISTICS.counter("Tree Drop Count", "Seeds the drone released (each planted as a new tree).")
def tree_drop_count(prev, state, actions, params):
    return state.dropped


@STATISTICS.counter("Recharge Energy Count", "Steps the drone spent within the charge radius of the drone station, "
                    "charging or not, from its first step (the pad it starts on included); 0 in the tasks whose "
                    "station is inert (Find Closest Tree, Find High Potential Area, Find High Terrain).")
def recharge_energy_count(prev, state, actions, params):
    return state.inside & state.alive & state.logs_docking


@STATISTICS.counter("Out of Energy Count", "Times the drone's battery ran empty (its episode ends); on the world's "
                    "last physics step, where the time limit ends the episode too, not for its last drone in agent "
                    "order (the original counts 2 of 3 such run-outs: the reward table's notes).")
def out_of_energy_count(prev, state, actions, params):
    ran_out = prev.alive & ~state.alive
    if not np.count_nonzero(ran_out) or not np.count_nonzero(state.steps_left <= 0):
        return ran_out
    counted = ran_out.copy()
    counted[:, -1] &= state.steps_left > 0  # the time limit ended the last drone's episode before its battery did
    return counted


@STATISTICS.counter("Cumulative Tree Drop Reward", "The seed-quality part r_s of each drop's reward, whatever "
                    "the task pays for drops (the original logs it where drops are weighted 0).")
def tree_drop_reward(prev, state, actions, params):
    return state.seed_reward


@STATISTICS.counter("Cumulative Distance Reward", "The station-distance part r_d of each drop's reward, whatever "
                    "the task pays for drops.")
def distance_reward(prev, state, actions, params):
    return state.distance_reward


@STATISTICS.counter("Cumulative Distance Until Tree Drop", "Metres the drone flew (its 3-D path) from taking "
                    "its seed (its spawn or its last return) to each drop.")
def distance_until_tree_drop(prev, state, actions, params):
    if not np.count_nonzero(state.dropped):  # most steps: nobody dropped (counts 0 for everyone)
        return state.dropped
    return np.where(state.dropped, state.flown, 0.0)


@STATISTICS.counter("Cumulative Normalized Distance Until Tree Drop",
                    "The normalised station distance r_d / 10 of each drop of some quality.")
def normalized_distance_until_tree_drop(prev, state, actions, params):
    return state.distance_reward * (1.0 / DISTANCE_REWARD_MULTIPLIER)


@STATISTICS.counter("Cumulative Distance to Existing Trees", "Metres from each drop to the nearest existing tree "
                    "(det, exact at any distance; the published 61.8 over 1.04 drops in the main task and 63.5 over "
                    "0.93 in Drop Seed are 59-68 m a drop).")
def distance_to_existing_trees(prev, state, actions, params):
    return state.drop_tree_distance


@STATISTICS.counter("Highest Potential Soild Found", "The rise of the best seed-drop potential found (the logged name's typo kept).")
def highest_potential_found(prev, state, actions, params):
    return state.best_fertility - prev.best_fertility


@STATISTICS.counter("Highest Point on Terrain Found", "The highest point (metres above sea level) the drone reached, "
                    "summed as its rises from 0 (the paper's h_old = 0).")
def highest_point_found(prev, state, actions, params):
    return state.best_height - prev.best_height


@STATISTICS.counter("Furthest Distance Explored", "The rise of the furthest horizontal distance (metres) from the station.")
def furthest_distance_explored(prev, state, actions, params):
    return state.best_distance - prev.best_distance


STATISTICS.cannot_compute(
    "Save Location Count",
    "the paper describes no save-location action or event (it is 0 in every published cell)")
