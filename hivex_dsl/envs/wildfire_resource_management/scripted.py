"""A scripted fire officer: move every tenth to the tower (own or neighbour) the observed fire approaches most closely.

Each tower reads only its own observation (the closest fire's offset now and one step before) and
knows where its neighbours stand, as the person in a watchtower would. The fire counts as approaching
a candidate tower when its distance to it shrank since the previous frame (or the fire just came
into view). The target gets an add, every other branch a subtract, so within about ten steps all of
the tower's resource sits on the target; with no approaching fire in view the tower keeps it all.
"""

from __future__ import annotations

from typing import Callable

import numpy as np

from .resources import ADD, SUBTRACT, TARGETS, grid_offsets
from .simulator import FRAME


def candidate_offsets(spacing_m: float) -> np.ndarray:
    """(9, 4, 2) metres from each tower to its candidates: itself (0, 0) and its neighbours 1-3."""
    grid = grid_offsets()
    return (grid[TARGETS] - grid[:, None, :]) * spacing_m


def choose_targets(fire_now: np.ndarray, fire_before: np.ndarray, seen_now: np.ndarray, seen_before: np.ndarray,
                   candidates: np.ndarray) -> np.ndarray:
    """(B, A) index 0-3 of the candidate nearest to an approaching fire (0, the own tower, when none).

    fire_now/fire_before (B, A, 2) metres from the tower to its closest fire now and one step before,
    seen_now/seen_before (B, A) bool, candidates (A, 4, 2) metres from the tower.
    """
    d_now = np.linalg.norm(fire_now[..., None, :] - candidates, axis=-1)
    d_before = np.linalg.norm(fire_before[..., None, :] - candidates, axis=-1)
    approaching = seen_now[..., None] & (~seen_before[..., None] | (d_now < d_before))
    score = np.where(approaching, d_now, np.inf)
    return np.where(approaching.any(axis=-1), np.argmin(score, axis=-1), 0)


def scripted_policy(compiled) -> Callable[[np.ndarray], np.ndarray]:
    """observations (B, 9, 16) -> actions (B, 9, 4): add to the chosen target, subtract from the other three."""
    radius = compiled.params.detection_radius_m
    candidates = candidate_offsets(compiled.params.tower_spacing_m)

    def act(observations: np.ndarray) -> np.ndarray:
        obs = np.asarray(observations, dtype=np.float64)
        now, before = obs[..., 0:3], obs[..., FRAME:FRAME + 3]
        target = choose_targets(now[..., :2] * radius, before[..., :2] * radius, (now != 0).any(axis=-1),
                                (before != 0).any(axis=-1), candidates)
        actions = np.full(obs.shape[:-1] + (candidates.shape[1],), SUBTRACT, np.int64)
        np.put_along_axis(actions, target[..., None], ADD, axis=-1)
        return actions

    return act
