"""The shared, batched wildfire engine of Aerial Wildfire Suppression and Wildfire Resource Management.

Conventions (grid, cell coordinates, in-place ownership of ``trees``) are in :mod:`.engine`.
"""

from .engine import (
    FireSpec,
    FireState,
    TreeState,
    any_burning,
    burning_count,
    cell_coords,
    cell_xy,
    fire_copy,
    fire_put_worlds,
    fire_reset,
    fire_reset_where,
    fire_take_worlds,
    length_in_cells,
)
from .factors import FactorGrid, count_factors, grid_cell_table
from .search import closest_burning
from .spread import Conditions, Winds, fire_step, fire_step_unchecked
from .water import douse

__all__ = [
    "Conditions",
    "FactorGrid",
    "FireSpec",
    "FireState",
    "TreeState",
    "Winds",
    "any_burning",
    "burning_count",
    "cell_coords",
    "cell_xy",
    "closest_burning",
    "count_factors",
    "douse",
    "fire_copy",
    "fire_put_worlds",
    "fire_reset",
    "fire_reset_where",
    "fire_take_worlds",
    "fire_step",
    "fire_step_unchecked",
    "grid_cell_table",
    "length_in_cells",
]
