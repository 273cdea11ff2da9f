"""The distances between the vessels of each world (crashes and the vector observation's nearest vessel), for
the simulator's steps and resets and for respawned vessels."""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from ...base.numeric import all_true


@lru_cache(maxsize=16)
def _others(agents: int) -> tuple[np.ndarray, np.ndarray]:
    """(A, A) read-only masks leaving each vessel out of its own distances: True off the diagonal,
    and inf on the diagonal with 0 elsewhere (to add)."""
    others = ~np.eye(agents, dtype=bool)
    self_distance = np.where(others, 0.0, np.inf)
    for array in (others, self_distance):
        array.setflags(write=False)
    return others, self_distance


def neighbour_distances(position: np.ndarray, active: np.ndarray) -> np.ndarray:
    """(B, A, A) distances between active vessels; inf on the diagonal and for inactive vessels."""
    gap = position[:, :, None, :] - position[:, None, :, :]  # (B, A, A, 2)
    square = gap * gap
    distance = np.sqrt(square[..., 0] + square[..., 1])
    others, self_distance = _others(position.shape[1])
    if all_true(active):
        return distance + self_distance
    return np.where(active[:, :, None] & active[:, None, :] & others, distance, np.inf)
