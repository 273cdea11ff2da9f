"""A scripted pilot: refill at the nearest coast, patrol a ring over the forest, fly at fire and drop on it; where
the task pays for finding the village, sweep the island on a spiral instead.

It reads only the vector observation (own position and heading, water, the closest burning tree
within the view square), as a trained policy would.
"""

from __future__ import annotations

from typing import Callable

import numpy as np

from ...base import portable
from ...sim.procgen.wind import wrap_angle

PATROL_RADIUS_M = 380.0  # middle of the forested band between village surroundings and coast
PATROL_LEAD_RAD = np.radians(35.0)  # aim this far ahead along the patrol circle (counter-clockwise)
PREPARE_BAND_M = 40.0  # when preparing trees: drop within this distance of the patrol circle
# the village is found within 150 m of it (horizontally; in 3-D from 100 m above the ground under village_distance
# 'release', about 112 m across over level ground) and stands within 450 m of the centre on each axis: spiral arms
# 200 m apart out to 680 m (past the square's corners, 636 m out, and short of the border) pass within 111 m of every
# such point, one sweep about 2,400 steps at 3 m a step, 1,440 at 5 m (closer arms sweep slower than the fire burns)
SEARCH_ARM_SPACING_M = 200.0
SEARCH_OUTER_M = 680.0


def steer_towards(position: np.ndarray, heading: np.ndarray, target: np.ndarray, turn_rad: float) -> np.ndarray:
    """(B, A) steer in [-1, 1] turning the heading toward ``target`` (B, A, 2) as fast as allowed."""
    gap = target - position
    error = wrap_angle(portable.arctan2(gap[..., 1], gap[..., 0]) - heading)
    return np.clip(error / turn_rad, -1.0, 1.0)


def coast_target(position: np.ndarray, island_half: float, border_half: float) -> np.ndarray:
    """(B, A, 2): the middle of the water ring straight out from the nearest island edge."""
    ring = (island_half + border_half) / 2.0
    along_x = np.abs(position[..., 0]) >= np.abs(position[..., 1])
    sign = np.where(np.sign(position) == 0, 1.0, np.sign(position))
    x = np.where(along_x, sign[..., 0] * ring, position[..., 0])
    y = np.where(along_x, position[..., 1], sign[..., 1] * ring)
    return np.stack([x, y], axis=-1)


def patrol_target(position: np.ndarray, radius: float) -> np.ndarray:
    """(B, A, 2): a point ahead on the patrol circle, so planes sweep the forest ring."""
    angle = portable.arctan2(position[..., 1], position[..., 0]) + PATROL_LEAD_RAD
    return radius * np.stack([np.cos(angle), np.sin(angle)], axis=-1)


def spiral_target(position: np.ndarray, spacing: float, outer: float) -> np.ndarray:
    """(B, A, 2): a point ahead on the outward spiral r = spacing x (arm + angle / 2 pi), counter-clockwise, on the
    arm nearest the plane; past ``outer`` the innermost arm, so the sweep starts over from the centre."""
    angle = portable.arctan2(position[..., 1], position[..., 0])
    turns = np.mod(angle, 2.0 * np.pi) / (2.0 * np.pi)  # [0, 1) of a turn
    arm = np.maximum(np.round(np.hypot(position[..., 0], position[..., 1]) / spacing - turns), 0.0)
    ahead = turns + PATROL_LEAD_RAD / (2.0 * np.pi)
    arm = np.where(spacing * (arm + ahead) > outer, 0.0, arm)
    radius = spacing * (arm + ahead)
    return radius[..., None] * np.stack([np.cos(angle + PATROL_LEAD_RAD), np.sin(angle + PATROL_LEAD_RAD)], axis=-1)


def scripted_policy(compiled) -> Callable[[dict], dict]:
    """observations {vector (B, A, 8), visual} -> actions {continuous (B, A, 1), discrete (B, A, 1)}."""
    p = compiled.params
    scale = p.border_half_extent_m
    turn = np.radians(p.turn_rate_deg)
    reach = (p.drop_points - 1) * p.drop_point_spacing_m
    w = compiled.weights
    # a prepared tree pays as much as an extinguished one (Maximize Preparing Trees): wet the forest band at once
    prepare = w.get("preparing_tree", 0.0) * 1.0 >= w.get("extinguishing_tree", 0.0) * 5.0 > 0.0
    search = w.get("find_village", 0.0) > 0.0  # the observation holds no village: sweep until it is in reach

    def act(observations: dict) -> dict:
        vector = observations["vector"].astype(np.float64)
        position, heading = vector[..., 0:2] * scale, portable.arctan2(vector[..., 3], vector[..., 2])
        water, fire_seen = vector[..., 4] > 0.5, vector[..., 7] > 0.5
        fire = vector[..., 5:7] * scale
        if search:
            target = spiral_target(position, SEARCH_ARM_SPACING_M, SEARCH_OUTER_M)
        else:
            target = np.where(water[..., None], patrol_target(position, PATROL_RADIUS_M),
                              coast_target(position, p.island_half_extent_m, p.border_half_extent_m))
            target = np.where((water & fire_seen)[..., None], fire, target)
        steer = steer_towards(position, heading, target, turn)
        gap = fire - position
        ahead = gap[..., 0] * np.cos(heading) + gap[..., 1] * np.sin(heading)
        across = np.abs(-gap[..., 0] * np.sin(heading) + gap[..., 1] * np.cos(heading))
        on_target = (ahead >= -0.5 * p.drop_radius_m) & (ahead <= reach + 0.5 * p.drop_radius_m)
        drop = water & fire_seen & on_target & (across <= 0.8 * p.drop_radius_m)
        if prepare:
            in_band = np.abs(np.hypot(position[..., 0], position[..., 1]) - PATROL_RADIUS_M) < PREPARE_BAND_M
            drop = drop | (water & ~fire_seen & in_band)
        return {"continuous": steer[..., None].astype(np.float32), "discrete": drop[..., None].astype(np.int64)}

    return act
