"""A scripted fire officer: keep the whole resource or give it all to the neighbours, whichever the task pays more.

Each tower reads only its own observation (the closest fire's offset now and one step before) and
knows where its neighbours stand, as the person in a watchtower would. From the closest fire it
estimates the performance P of its own tower (exactly) and of each neighbour (from that same fire's
horizontal distance to it) with the paper's law. Keeping pays w_own times the own tower's performance
times r_self and giving each neighbour's performance times the share it gets, times w_neighbours (the
reward table's weights of watch_tower_performance and neighbour_performance; a performance is P times
what the tower holds, which the officer cannot see and takes alike everywhere), so one of the two
corners is best: keep everything when w_own P_own beats w_neighbours times the neighbours' mean
estimated P (the whole share split in three), else give everything. With no fire in anyone's range the
resource waits where the task pays more when fire comes: with the own tower when w_own beats
w_neighbours, else with the neighbours. Under the terms' readings before session 74
(neighbour_term_weight 'given_total': the neighbours' summed P times the whole share given) the
neighbours' P count summed, and idle towers keep only when w_own beats three times w_neighbours.
Keeping adds to the own tower and subtracts from the neighbours; giving adds to all three neighbours
and subtracts from the own tower, so the whole resource moves within about ten steps (four to give).
"""

from __future__ import annotations

from typing import Callable

import numpy as np

from .resources import ADD, NEIGHBOURS_PER_TOWER, SUBTRACT, TARGETS, grid_offsets
from .simulator import FRAME
from .terms import broken_power_law, remapped_distance

KEEP = np.array([ADD] + [SUBTRACT] * NEIGHBOURS_PER_TOWER)
GIVE = np.array([SUBTRACT] + [ADD] * NEIGHBOURS_PER_TOWER)


def candidate_offsets(spacing_m: float) -> np.ndarray:
    """(9, 4, 2) metres from each tower to its candidates: itself (0, 0) and its neighbours 1-3."""
    grid = grid_offsets()
    return (grid[TARGETS] - grid[:, None, :]) * spacing_m


def candidate_distances(fire_now: np.ndarray, fire_before: np.ndarray, seen_now: np.ndarray,
                        seen_before: np.ndarray, candidates: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(distance (B, A, 4) metres from the closest fire to each candidate, inf when none is seen;
    approaching (B, A, 4): seen and nearer than one step before, or just come into view).

    fire_now/fire_before (B, A, 3) metres from the tower to its closest fire now and one step before
    (x, y, z; the 3-D distance for the own tower, the horizontal one for a neighbour),
    seen_now/seen_before (B, A) bool, candidates (A, 4, 2) metres from the tower.
    """
    gap_now = fire_now[..., None, :2] - candidates
    gap_before = fire_before[..., None, :2] - candidates
    d_now, d_before = np.hypot(gap_now[..., 0], gap_now[..., 1]), np.hypot(gap_before[..., 0], gap_before[..., 1])
    d_now[..., 0], d_before[..., 0] = np.linalg.norm(fire_now, axis=-1), np.linalg.norm(fire_before, axis=-1)
    approaching = seen_now[..., None] & (~seen_before[..., None] | (d_now < d_before))
    return np.where(seen_now[..., None], d_now, np.inf), approaching


def estimated_performance(distance: np.ndarray, approaching: np.ndarray, params) -> np.ndarray:
    """(B, A, 4) the paper's P of each candidate for the given distances, 0 beyond distance_threshold_m."""
    in_range = distance <= params.distance_threshold_m
    law = broken_power_law(remapped_distance(np.where(in_range, distance, 0.0), approaching,
                                             params.distance_threshold_m), params.power_law_s, params.power_law_a)
    return np.where(in_range, law, 0.0)


def keep_all(performance: np.ndarray, own_weight: float, neighbour_weight: float,
             given_each: bool = True) -> np.ndarray:
    """(B, A) bool: keep everything (else give everything) for estimated P (B, A, 4) of self and neighbours;
    ``given_each``: each neighbour pays for the share it gets (their mean P counts), else their summed P does."""
    neighbours = neighbour_weight if given_each else NEIGHBOURS_PER_TOWER * neighbour_weight
    keep = own_weight * performance[..., 0]
    give = neighbours * performance[..., 1:].mean(axis=-1)
    idle = (keep == 0.0) & (give == 0.0)
    return np.where(idle, own_weight > neighbours, keep > give)


def scripted_policy(compiled) -> Callable[[np.ndarray], np.ndarray]:
    """observations (B, 9, 16) -> actions (B, 9, 4): all branches toward keeping or toward giving."""
    params = compiled.params
    radius = params.detection_radius_m
    candidates = candidate_offsets(params.tower_spacing_m)
    own = compiled.weights.get("watch_tower_performance", 0.0)
    given = compiled.weights.get("neighbour_performance", 0.0)

    def act(observations: np.ndarray) -> np.ndarray:
        obs = np.asarray(observations, dtype=np.float64)
        now, before = obs[..., 0:3], obs[..., FRAME:FRAME + 3]
        distance, approaching = candidate_distances(now * radius, before * radius, (now != 0).any(axis=-1),
                                                    (before != 0).any(axis=-1), candidates)
        keep = keep_all(estimated_performance(distance, approaching, params), own, given,
                        params.neighbour_term_weight == "given_each")
        return np.where(keep[..., None], KEEP, GIVE).astype(np.int64)

    return act
