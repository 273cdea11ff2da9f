"""The reward terms of Drone-Based Reforestation, as the paper's equations (Appendix, Reward
Description and Calculation: Drone-Based Reforestation). Stateful quantities (the drop's rewards,
running-back increments, the best potential, height and distance so far) are kept by the
simulator's step; the terms read them."""

from __future__ import annotations

import numpy as np

from ...sim.reward.terms import TermRegistry
from .planting import DISTANCE_REWARD_MULTIPLIER, RUNNING_BACK_REWARD, SEED_REWARD_MULTIPLIER

TERMS = TermRegistry("drone_based_reforestation")

GROUP_UP_REWARD = 10.0  # [paper]
CLOSE_TREE_REWARD = 100.0  # [paper]
HEIGHT_BOUND_M = 100.0  # the largest height_bound_m allowed
HALF_EXTENT_M = 200.0  # [paper] the largest half extent the scenario checks allow
MAX_DEPLETION = 0.1  # -1 / the fewest battery steps the params allow (10)


@TERMS.term(
    "drop_seed", title="Drop Seed", paper_row=1, low=0.0, high=SEED_REWARD_MULTIPLIER + DISTANCE_REWARD_MULTIPLIER,
    sign="bonus", timing="event", scope="agent",
    description="At each seed drop: the drop location's quality (0-20, best just outside the forest and away from "
                "planted trees) plus its distance from the station (0-10, only for a seed of some quality).",
    equation="r_sd = r_s + r_d;  r_s = 20 * Remap(det, 2.5, 75, 1, 0) if 2.5 <= det <= 75 and dnt >= 2.5 else 0;  "
             "r_d = 10 * min(sdd / 200, 1) if r_s > 0 else 0",
)
def drop_seed(prev, state, actions, params):
    return state.seed_reward + state.distance_reward


@TERMS.term(
    "deplete_energy_holding_seed", title="Deplete Energy Holding Seed", paper_row=2, low=-MAX_DEPLETION, high=0.0,
    sign="penalty", timing="dense", scope="agent",
    description="Every step the drone carries a seed: the battery share a step costs with a seed.",
    equation="der = -1 / (episode_length_max / 2) = -1 / energy_steps_with_seed (-1/1000) while holding a seed",
)
def deplete_energy_holding_seed(prev, state, actions, params):
    return np.where(prev.holding, -1.0 / params.energy_steps_with_seed, 0.0)


@TERMS.term(
    "deplete_energy_no_seed", title="Deplete Energy No Seed", paper_row=3, low=-MAX_DEPLETION, high=0.0,
    sign="penalty", timing="dense", scope="agent",
    description="Every step the drone flies without a seed: the battery share a step costs without one.",
    equation="der = -1 / episode_length_max = -1 / energy_steps_without_seed (-1/2000) while not holding a seed",
)
def deplete_energy_no_seed(prev, state, actions, params):
    return np.where(prev.holding, 0.0, -1.0 / params.energy_steps_without_seed)


@TERMS.term(
    "pick_up_seed", title="Pick-up Seed", paper_row=4, low=0.0, high=1.0, sign="bonus", timing="event",
    scope="agent",
    description="When the drone returns to the drone station (recharging and picking up a seed); 100 in the "
                "Pick-up Seed sub-task through its weight.",
    equation="r_ps = 1 if the drone reaches the station (distance(p, d) <= d_charge after a trip) else 0",
)
def pick_up_seed(prev, state, actions, params):
    return state.returned.astype(np.float64)


@TERMS.term(
    "pick_up_seed_explored", title="Pick-up Seed (explored distance)", paper_row=4, low=0.0, high=HALF_EXTENT_M,
    sign="bonus", timing="event", scope="agent",
    description="The paper's 0-200 Pick-up Seed cell of Explore Furthest: on returning to the station, the "
                "furthest distance from it explored so far.",
    equation="r_ps = d_old (furthest horizontal distance from the station, at most 200) when the drone returns, else 0",
)
def pick_up_seed_explored(prev, state, actions, params):
    return np.where(state.returned, state.best_distance, 0.0)


@TERMS.term(
    "incremental_running_back", title="Incremental Running Back", paper_row=5, low=0.0, high=RUNNING_BACK_REWARD,
    sign="bonus", timing="event", scope="agent",
    description="After a drop, for each 2.5 m increment closer to the station than before, scaled by the drop's "
                "quality: a whole run home from D metres pays 20 rbm (floor(D / 2.5) - 3) / (D - 3), about a third "
                "of 20 rbm.",
    equation="if d_0 < d_-1 and d_0 >= d_charge / s: r_rb = clip(r_p * rbm / (d_init - d_charge / s), 0, r_p);  "
             "d_0 = floor(|p - dp| / s), d_init = |p - dp| at the drop (metres), rbm = (r_s + r_d) / (sdrm + drm), "
             "r_p = 20, s = 2.5, d_charge = 7.5",
)
def incremental_running_back(prev, state, actions, params):
    return state.running_back


@TERMS.term(
    "group_up", title="Group-up", paper_row=None, low=0.0, high=GROUP_UP_REWARD, sign="bonus", timing="dense",
    scope="agent",
    description="Every step another active drone is closer than 5 m (the paper's reward list has it; its "
                "reward-scale table has no row for it).",
    equation="r_gu = 10 if d_cn < d_thresh (5) else 0,  d_cn = distance to the closest neighbouring drone",
)
def group_up(prev, state, actions, params):
    gap = state.position[:, :, None, :] - state.position[:, None, :, :]
    squared = np.einsum("bijd,bijd->bij", gap, gap)
    others = state.alive[:, None, :] & ~np.eye(state.alive.shape[1], dtype=bool)[None]
    close = (others & (squared < params.group_distance_m ** 2)).any(axis=2)
    return np.where(close, GROUP_UP_REWARD, 0.0)


@TERMS.term(
    "high_fertility_location_delta", title="High Fertility Location Delta", paper_row=6, low=0.0, high=1.0,
    sign="bonus", timing="event", scope="agent",
    description="Each time the drone finds a more fertile seed-drop location than before: the gain in potential.",
    equation="r_fl = pot_current - pot_old if pot_old < pot_current else 0;  pot = Map(det, 2.5, 75, 1, 0) where "
             "2.5 <= det <= 75 and dnt >= 2.5, pot_old starts at the spawn point's potential",
)
def high_fertility_location_delta(prev, state, actions, params):
    return state.best_fertility - prev.best_fertility


@TERMS.term(
    "high_landscape_point_delta", title="High Landscape Point Delta", paper_row=7, low=0.0, high=HEIGHT_BOUND_M,
    sign="bonus", timing="event", scope="agent",
    description="Each time the drone flies higher than before: the gain in height (the drone's own height above sea "
                "level, up to the height bound, as the original's records read; see the reward table's notes).",
    equation="r_h = h(p) - h_old if h_old < h(p) else 0;  h(p) = the drone's height z, h_old starts at 0 (the paper's)",
)
def high_landscape_point_delta(prev, state, actions, params):
    return state.best_height - prev.best_height


@TERMS.term(
    "far_distance_explored_delta", title="Far Distance Explored Delta", paper_row=8, low=0.0, high=HALF_EXTENT_M,
    sign="bonus", timing="event", scope="agent",
    description="Each time the drone gets further from the station than before: the gain in distance.",
    equation="r_fd = d_current - d_old if d_old < d_current else 0;  d = horizontal distance to the station "
             "(at most the half extent 200), d_old starts at the spawn distance",
)
def far_distance_explored_delta(prev, state, actions, params):
    return state.best_distance - prev.best_distance


@TERMS.term(
    "find_close_tree", title="Find Close Tree", paper_row=9, low=0.0, high=CLOSE_TREE_REWARD, sign="bonus",
    timing="event", scope="agent",
    description="When an existing tree is within 20 m of the drone (horizontally).",
    equation="r_ct = 100 if d_cet <= 20 else 0,  d_cet = distance to the closest existing tree",
)
def find_close_tree(prev, state, actions, params):
    return np.where(state.found_tree, CLOSE_TREE_REWARD, 0.0)
