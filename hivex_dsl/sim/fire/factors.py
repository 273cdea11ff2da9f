"""The weather factors of spread counted once per cell of a coarse weather grid, for :func:`.spread.fire_step`.

A simulator that samples its weather on a coarse (G x G) grid per world and reads each forest cell's
nearest grid cell (as :func:`hivex_dsl.envs.island.conditions_reader` does) can count the factors hot,
dry and low overcast once per grid cell when it samples, then pass a :class:`FactorGrid` to
``fire_step`` instead of the ``conditions`` callable: each pair then looks its count up instead of
calling back; both paths compare with :func:`factor_count`.
"""

from __future__ import annotations

import numpy as np

from .engine import FireSpec


def factor_count(temperature: np.ndarray, humidity: np.ndarray, overcast: np.ndarray, spec: FireSpec) -> np.ndarray:
    """int8 number of the weather factors of spread that hold (hot, dry, low overcast), shaped like the fields:
    the one place these thresholds are compared, for the callable and the FactorGrid paths alike."""
    hot = temperature > spec.hot_temperature
    dry = humidity < spec.dry_humidity
    low = overcast < spec.low_overcast
    return hot.astype(np.int8) + dry + low


def count_factors(conditions: np.ndarray, spec: FireSpec) -> np.ndarray:
    """(B, G * G) int8 number of true weather factors at each cell of ``conditions`` (B, G, G, 3)
    (temperature, humidity, overcast)."""
    counts = factor_count(conditions[..., 0], conditions[..., 1], conditions[..., 2], spec)
    return counts.reshape(len(conditions), -1)


def grid_cell_table(lookup: np.ndarray, grid_cells: int) -> np.ndarray:
    """(C * C,) int64 row-major index of the weather-grid cell (of ``grid_cells`` per side) holding each
    forest cell, from the (C,) grid row (or column) ``lookup`` of each forest row (or column)."""
    table = (lookup[:, None] * grid_cells + lookup[None, :]).reshape(-1).astype(np.int64)
    table.flags.writeable = False
    return table


class FactorGrid:
    """Weather factor counts (B, G * G) int8 of :func:`count_factors` and the grid cell (C * C,) of every
    forest cell (:func:`grid_cell_table`); the count of a spec other than the one counted is undefined."""

    __slots__ = ("counts", "cell_table")

    def __init__(self, counts: np.ndarray, cell_table: np.ndarray):
        if counts.dtype != np.int8 or counts.ndim != 2:
            raise ValueError(f"counts must be a (B, G * G) int8 array, got {counts.dtype} {counts.shape}")
        self.counts = counts
        self.cell_table = cell_table

    def at(self, flat: np.ndarray, area: int) -> np.ndarray:
        """(N,) int8 factor count at the flat forest cells ``flat`` (N,) of worlds with ``area`` cells each."""
        if len(self.counts) == 1:  # one world: flat indices are its cells
            return self.counts.take(self.cell_table.take(flat))
        world, cell = np.divmod(flat, area)
        return self.counts.take(world * self.counts.shape[1] + self.cell_table.take(cell))
