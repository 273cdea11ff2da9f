"""The batched state of Drone-Based Reforestation, and the shapes the simulator, render and respawn share."""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

STATION_PAD_M = 3.0  # radius of the pad the camera and renderer draw
VECTOR_SIZE = 10


class Flight(NamedTuple):
    """The drones after one step of flight, B worlds of A drones."""

    position: np.ndarray  # (B, A, 3)
    xy: np.ndarray  # (B, A, 2) the horizontal position (position[..., :2], a view or the array it was built from)
    z: np.ndarray  # (B, A) the height (position[..., 2], likewise)
    heading: np.ndarray  # (B, A)
    direction: np.ndarray  # (B, A, 2) cos and sin of the heading
    ground: np.ndarray  # (B, A) terrain height below each drone
    tree_distance: np.ndarray | None  # (B, A) sampled from the state's tree_distance raster (None at reset)


@dataclass(frozen=True)
class DroneState:
    """B worlds of A drones. Metres, radians; (x, y) horizontal, z height; station at the centre.

    The world arrays ``camera``, ``new_trees`` and ``new_quality`` only grow during an episode: a
    planted tree is written into them in place, so a state and the one before it share them (no
    reward term reads them). Every other array is fresh in each state.
    """

    # the world, fixed for an episode
    heights: np.ndarray  # (B, n, n) terrain height grid (procgen Terrain convention)
    tree_distance: np.ndarray  # (B, m, m) float32 distance from each forest cell centre to the nearest tree
    tree_xy: np.ndarray  # (B, m, m, 2) float32 existing tree of each forest cell, FAR_M where empty
    station: np.ndarray  # (B, 3) station pad position (x, y, ground height)
    # the world, growing in place
    camera: np.ndarray  # (B, R, R) uint8 grayscale raster the cameras see
    new_trees: np.ndarray  # (B, C, 2) float32 planted trees (every released seed), FAR_M in empty slots
    new_quality: np.ndarray  # (B, C) float32 each planted tree's seed quality r_s / 20 in [0, 1] (0: poor spot)
    new_count: np.ndarray  # (B,) int64 planted trees so far
    steps_left: np.ndarray  # (B,) int64 physics steps to the world's time limit (0 on its last step)
    # the drones
    position: np.ndarray  # (B, A, 3)
    heading: np.ndarray  # (B, A) facing angle from +x, counter-clockwise
    ground: np.ndarray  # (B, A) terrain height below each drone
    energy: np.ndarray  # (B, A) battery in [0, 1]
    holding: np.ndarray  # (B, A) bool, carrying a seed
    alive: np.ndarray  # (B, A) bool, energy left (a drone with an empty battery is frozen)
    inside: np.ndarray  # (B, A) bool, within the charge radius of the station
    logs_docking: np.ndarray  # (B, A) bool, the station logs this drone's docked steps (false in the tasks where it is inert)
    docked_steps: np.ndarray  # (B, A) int64 consecutive steps docked (alive within the charge radius), 0 outside
    away: np.ndarray  # (B, A) bool, has been return_min_distance_m from the station since its last return
    best_fertility: np.ndarray  # (B, A) pot_old: best seed-drop potential found so far
    best_height: np.ndarray  # (B, A) h_old: highest ground found so far
    best_distance: np.ndarray  # (B, A) d_old: furthest horizontal distance from the station so far
    back_active: np.ndarray  # (B, A) bool, running back to the station after a drop
    back_init: np.ndarray  # (B, A) d_init: metres from the station (3-D) at the drop
    back_best: np.ndarray  # (B, A) int64 d_-1: closest increment reached since the drop
    back_multiplier: np.ndarray  # (B, A) rbm of the last drop
    flown: np.ndarray  # (B, A) metres flown (3-D path) since the drone last took a seed: its spawn or a return
    # what happened in the last step (all zero / false after a reset)
    dropped: np.ndarray  # (B, A) bool, released a seed (planted as a new tree at the ground below)
    seed_reward: np.ndarray  # (B, A) r_s of the drop
    distance_reward: np.ndarray  # (B, A) r_d of the drop
    drop_tree_distance: np.ndarray  # (B, A) det of the drop: metres to the nearest existing tree, at any distance
    returned: np.ndarray  # (B, A) bool, arrived back at the station (and picked up a seed if it had none)
    found_tree: np.ndarray  # (B, A) bool, an existing tree within close_tree_radius_m
    running_back: np.ndarray  # (B, A) r_rb paid this step
    frames: np.ndarray  # (B, A, 20) float32 vector observation, newest stack first
