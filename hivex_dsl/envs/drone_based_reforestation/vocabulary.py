"""What an expression may read in Drone-Based Reforestation: drones, battery, seeds, the station, planting.

Readers take the simulator's state; the distance to the station is the hypotenuse of the state's
positions (the state keeps positions, not that distance), and the fertility under a drone is sampled
from the state's tree-distance raster as the simulator samples it each step.
"""

from __future__ import annotations

import math

import numpy as np

from ...sim.reward.vocabulary import Vocabulary, flag, quantity
from ...sim.grids import sample_bilinear
from .fertility import fertility, forest_grid


def declare(compiled) -> dict:
    p = compiled.params
    half = compiled.generators["terrain"].extent_m / 2.0
    items = [
        quantity("x_m", "agent", "number", "m", -half, half, "The drone's position east of the world centre."),
        quantity("y_m", "agent", "number", "m", -half, half, "The drone's position north of the world centre."),
        quantity("altitude_m", "agent", "number", "m", 0.0, p.height_bound_m, "The drone's height above sea level."),
        quantity("heading_rad", "agent", "number", "rad", -math.pi, math.pi,
                 "Where the drone faces, counter-clockwise from east."),
        quantity("battery", "agent", "number", "1", 0.0, 1.0, "Energy left in the drone's battery (1 full)."),
        flag("holding_seed", "agent", "The drone carries a seed."),
        flag("alive", "agent", "The drone has energy left."),
        flag("at_station", "agent", "The drone is within charge_radius_m of the station."),
        quantity("distance_to_station_m", "agent", "number", "m", 0.0, 2.0 * math.sqrt(2.0) * half,
                 "Horizontal distance from the drone to the station."),
        quantity("trees_planted", "world", "number", "trees", 0.0, float(p.new_tree_capacity),
                 "Trees planted in the world this episode."),
        flag("returned_to_station", "agent", "The drone came back to the station after a trip this step."),
        flag("found_close_tree", "agent", "An existing tree is within close_tree_radius_m of the drone."),
        flag("planted_tree", "agent", "The drone released its seed this step (planted as a new tree)."),
        quantity("fertility", "agent", "number", "1", 0.0, 1.0,
                 "Soil fertility under the drone: Remap(det, min_tree_distance_m, max_tree_distance_m, 1, 0) of the "
                 "distance det to the nearest existing tree, 0 outside that band (highest just outside the forest "
                 "edge); det is read from the reset's tree-distance raster, bilinearly, as the fertility terms read "
                 "it, and planted trees do not change it."),
    ]
    return {q.name: q for q in items}


def _station_distance(state, events, compiled) -> np.ndarray:
    gap = state.position[..., :2] - state.station[:, None, :2]
    return np.hypot(gap[..., 0], gap[..., 1])


def _fertility(state, events, compiled) -> np.ndarray:
    """(B, A) the hidden fertility field at each drone's (x, y): the simulator's per-step sample of the state's
    (B, m, m) tree-distance raster, remapped by the paper's seed-quality band."""
    p = compiled.params
    det = sample_bilinear(state.tree_distance, forest_grid(compiled.generators["forest"]), state.position[..., :2])
    return fertility(det, p.min_tree_distance_m, p.max_tree_distance_m)


READERS = {
    "x_m": lambda s, e, c: s.position[..., 0],
    "y_m": lambda s, e, c: s.position[..., 1],
    "altitude_m": lambda s, e, c: s.position[..., 2],
    "heading_rad": lambda s, e, c: s.heading,
    "battery": lambda s, e, c: s.energy,
    "holding_seed": lambda s, e, c: s.holding,
    "alive": lambda s, e, c: s.alive,
    "at_station": lambda s, e, c: s.inside,
    "distance_to_station_m": _station_distance,
    "trees_planted": lambda s, e, c: s.new_count.astype(np.float64),
    "returned_to_station": lambda s, e, c: s.returned,
    "found_close_tree": lambda s, e, c: s.found_tree,
    "planted_tree": lambda s, e, c: s.dropped,
    "fertility": _fertility,
}

VOCABULARY = Vocabulary("drone_based_reforestation", declare, READERS)
