"""Distances on a plot page, for the tests of the PDF reader and of the original's curves."""

from __future__ import annotations

import numpy as np


def distance_to_polyline(points: np.ndarray, vertices: np.ndarray) -> np.ndarray:
    """Each of ``points`` (m, 2)'s shortest distance to the line through ``vertices`` (k, 2): (m,)."""
    if len(vertices) == 1:
        return np.linalg.norm(points - vertices[0], axis=1)
    a, b = vertices[:-1], vertices[1:]
    ab = b - a
    t = np.clip(((points[:, None] - a[None]) * ab[None]).sum(-1) / np.maximum((ab ** 2).sum(-1), 1e-300), 0, 1)
    return np.linalg.norm(points[:, None] - (a[None] + t[..., None] * ab[None]), axis=-1).min(axis=1)
