"""A scripted turbine controller a wind engineer would write: turn toward the task's ideal heading."""

from __future__ import annotations

from typing import Callable

import numpy as np

from ...base import portable
from ...sim.procgen.wind import wrap_angle


def ideal_heading(heading: np.ndarray, wind: np.ndarray, perpendicular: bool) -> np.ndarray:
    """Face upwind (Generate Energy) or the nearer of the two headings across the wind (Avoid Damage)."""
    if not perpendicular:
        return wind + np.pi
    left, right = wind + np.pi / 2, wind - np.pi / 2
    closer_left = np.abs(wrap_angle(left - heading)) <= np.abs(wrap_angle(right - heading))
    return np.where(closer_left, left, right)


def scripted_policy(compiled) -> Callable[[np.ndarray], np.ndarray]:
    """observations (B, A, 6) -> actions (B, A): rotate toward the ideal heading, hold within half a step."""
    weights = compiled.weights
    perpendicular = weights.get("avoid_damage", 0.0) > weights.get("generate_energy", 0.0)
    tolerance = np.radians(compiled.params.rotation_speed_deg) / 2.0

    def act(observations: np.ndarray) -> np.ndarray:
        heading = portable.arctan2(observations[..., 3], observations[..., 2])
        wind = portable.arctan2(observations[..., 5], observations[..., 4])
        error = wrap_angle(ideal_heading(heading, wind, perpendicular) - heading)
        return np.where(error > tolerance, 1, np.where(error < -tolerance, 2, 0)).astype(np.int64)

    return act
