"""A seed's way from the drone to the ground and the running back after it: which drones drop this step, the trees
they plant and what each drop pays (r_s, r_d), and the Incremental Running Back bookkeeping a drop starts. Functions
of the simulator (``sim``: its params, forest grid, camera raster and half extent), bound as its methods; arrays are
(B, A) unless said otherwise.
"""

from __future__ import annotations

import numpy as np

from ...base.numeric import clamp
from .camera import NEW_TREE_GRAY, stamp_disks
from .fertility import (distance_reward, logged_tree_distance, nearest_new_tree_distance, nearest_tree_distance,
                        same_step_distance, seed_reward, storage_slots)
from .types import DroneState

SEED_REWARD_MULTIPLIER = 20.0  # [paper] sdrm
DISTANCE_REWARD_MULTIPLIER = 10.0  # [paper] drm
RUNNING_BACK_REWARD = 20.0  # [paper] r_p


def wanted_drops(sim, state: DroneState, actions, distance: np.ndarray, alive: np.ndarray | None) -> np.ndarray:
    """Living drones that hold a seed, are at least drop_min_distance_m from the station (``distance``, 3D) and ask
    to drop it."""
    if not np.count_nonzero(state.holding):  # nobody can drop a seed (skips the ops below)
        return np.zeros(distance.shape, bool)
    asked = (np.asarray(actions["discrete"])[..., 0] == 1) & state.holding
    return alive_only(asked & (distance >= sim.params.drop_min_distance_m), alive)


def plant(sim, state: DroneState, wants: np.ndarray, position: np.ndarray
          ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Release the seeds of the drones that ``wants`` to drop one, as far as the stores allow, and plant them at
    ``position`` (B, A, 3). Returns the drops made, their r_s, r_d and det, and the planted-tree counts (B,)."""
    r_s, r_d, det = np.zeros(wants.shape), np.zeros(wants.shape), np.zeros(wants.shape)
    drops = releases(sim, state, wants)
    world, agent = np.nonzero(drops)
    if len(world):  # every wish may be refused by full stores
        r_s[world, agent], r_d[world, agent], det[world, agent] = drop(sim, state, position[world, agent, :2], world)
    return drops, r_s, r_d, det, state.new_count + np.bincount(world, minlength=len(state.new_count))


def releases(sim, state: DroneState, wants: np.ndarray) -> np.ndarray:
    """The drones whose wish to drop is granted: all, unless their world's store of planted trees is full (the
    last in agent order keep their seeds)."""
    world, agent = np.nonzero(wants)
    full = storage_slots(state.new_count, world) >= sim.params.new_tree_capacity
    granted = wants.copy()
    granted[world[full], agent[full]] = False
    return granted


def drop(sim, state: DroneState, points: np.ndarray, world: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Plant the seeds released at ``points`` (M, 2) of worlds ``world`` (M,, sorted): each becomes a new tree,
    written into ``new_trees``, ``new_quality`` and the camera raster in place. Returns r_s, r_d and det (M,), det
    being exact at any distance (0 in a world without trees)."""
    p = sim.params
    det = nearest_tree_distance(state.tree_xy, sim.forest_grid, world, points, p.max_tree_distance_m)
    dnt = nearest_new_tree_distance(state.new_trees[:, : int(state.new_count.max())], world, points)
    dnt = np.minimum(dnt, same_step_distance(world, points))
    seed = seed_reward(det, dnt, p.min_tree_distance_m, p.max_tree_distance_m, SEED_REWARD_MULTIPLIER)
    sdd = np.hypot(*(points - state.station[world, :2]).T)
    slot = storage_slots(state.new_count, world)
    state.new_trees[world, slot] = points
    state.new_quality[world, slot] = seed / SEED_REWARD_MULTIPLIER
    stamp_disks(state.camera, sim.raster, world, points, p.tree_crown_radius_m, NEW_TREE_GRAY)
    return (seed, distance_reward(seed, sdd, sim.half, DISTANCE_REWARD_MULTIPLIER),
            logged_tree_distance(state.tree_xy, world, points, det))


def running_back(sim, state: DroneState, increment: np.ndarray, alive: np.ndarray | None) -> np.ndarray:
    """r_rb: paid when a drone running back reaches a closer increment than any since its drop, down to
    d_charge / s. The paper's r_p * rbm / (d_init - d_charge / s) with d_init the drop's station distance in
    metres, as the paper defines it (d_0 alone is "in incremental steps"): a whole run back from D metres pays
    r_p * rbm * (floor(D / s) - d_charge / s) / (D - d_charge / s), about r_p * rbm * 0.3 for the original's
    drops 25-50 m out, what its Drop Seed and main-task records leave for this term (the reward table's note
    "Incremental Running Back's d_init")."""
    p = sim.params
    closer = alive_only(state.back_active & (increment < state.back_best), alive)
    if not np.count_nonzero(closer):  # (count_nonzero is the cheapest "any" on small arrays)
        return np.zeros(closer.shape)
    first_inside = p.charge_radius_m / p.running_back_step_m  # d_charge / s: the increments inside pay nothing
    span = state.back_init - first_inside  # metres less increments, as the paper writes it; > 0 for any drop
    reward = RUNNING_BACK_REWARD * state.back_multiplier / np.where(span > 0, span, 1.0)
    paid = closer & (span > 0) & (increment >= first_inside)
    return np.where(paid, clamp(reward, 0.0, RUNNING_BACK_REWARD), 0.0)


def running_back_fields(state: DroneState, drops: np.ndarray, distance: np.ndarray, increment: np.ndarray,
                        outside: np.ndarray, r_s: np.ndarray, r_d: np.ndarray, dropping: bool) -> dict[str, np.ndarray]:
    """The running-back bookkeeping after this step: a drop starts it (d_init its station ``distance`` in metres),
    reaching the station ends it. Without a drop (``dropping`` false) the drop-time fields stay."""
    best = np.where(state.back_active, np.minimum(state.back_best, increment), state.back_best)
    if not dropping:
        return {"back_active": state.back_active & outside, "back_best": best}
    return {"back_active": (state.back_active | drops) & outside,
            "back_init": np.where(drops, distance, state.back_init),
            "back_best": np.where(drops, increment, best),
            "back_multiplier": np.where(drops, (r_s + r_d) / (SEED_REWARD_MULTIPLIER + DISTANCE_REWARD_MULTIPLIER),
                                        state.back_multiplier)}


def alive_only(mask: np.ndarray, alive: np.ndarray | None) -> np.ndarray:
    """``mask & alive``; ``alive`` None stands for every drone alive, the common case, which needs no op."""
    return mask if alive is None else mask & alive
