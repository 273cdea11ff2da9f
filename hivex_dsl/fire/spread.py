"""One fire step of every world: spread from the burning trees, burn-out, the end of the fire.

Every burning tree tries each existing tree of the (2r+1) x (2r+1) cells around it (not itself,
inside the grid) once, an independent draw per (burning, target) pair, with probability
``min(1, spread_chance_per_factor * n)``; ``n`` counts the target within ``downwind_cone_deg``
of the wind direction seen from the source, the target higher than the source, and at the
source temperature > hot, humidity < dry, overcast < low. A target tried by several burning trees
thus ignites with probability ``1 - prod(1 - p)``. The work is proportional to the front: K
burning trees x (2r+1)^2 cells, gathered from flat indices; nothing scans the grid.
"""

from __future__ import annotations

from functools import lru_cache
from typing import Callable

import numpy as np

from ..procgen.wind import wrap_angle
from .engine import FireSpec, FireState, TreeState, split_flat, vector

# conditions(world (N,), row (N,), col (N,)) int64 -> (temperature (N,), humidity (N,), overcast (N,)) in [0, 1]
Conditions = Callable[[np.ndarray, np.ndarray, np.ndarray], tuple[np.ndarray, np.ndarray, np.ndarray]]
FACTORS = 5
CONE_TOLERANCE_RAD = 1e-9  # "within" is inclusive: a diagonal exactly 45 degrees off the wind counts


@lru_cache(maxsize=16)
def block_offsets(radius: int) -> tuple[np.ndarray, np.ndarray]:
    """(N,) int64 row and col offsets of the (2r+1)^2 block around a cell, without the cell, row-major."""
    span = np.arange(-radius, radius + 1)
    rows, cols = (a.ravel() for a in np.meshgrid(span, span, indexing="ij"))
    keep = (rows != 0) | (cols != 0)
    rows, cols = rows[keep], cols[keep]
    rows.flags.writeable = cols.flags.writeable = False
    return rows, cols


def downwind_table(downwind_rad: np.ndarray, d_row: np.ndarray, d_col: np.ndarray, cone_deg: float) -> np.ndarray:
    """(B, N) bool: offset (d_row, d_col) lies within ``cone_deg`` of world b's downwind direction.

    ``downwind_rad`` (B,) is the direction the wind blows to, counter-clockwise from +x; an offset's
    direction is atan2(d_row, d_col) since rows run along y and columns along x.
    """
    gap = np.abs(wrap_angle(np.arctan2(d_row, d_col)[None, :] - downwind_rad[:, None]))
    return gap <= np.radians(cone_deg) + CONE_TOLERANCE_RAD


def weather_factors(spec: FireSpec, conditions: Conditions, world: np.ndarray, row: np.ndarray,
                    col: np.ndarray) -> np.ndarray:
    """(N,) int8: how many of hot, dry and low overcast hold at the cells (world, row, col), each (N,)."""
    fields = conditions(world, row, col)
    if len(fields) != 3:
        raise ValueError(f"conditions must return (temperature, humidity, overcast), got {len(fields)} arrays")
    temperature, humidity, overcast = (np.asarray(f) for f in fields)
    for name, field in zip(("temperature", "humidity", "overcast"), (temperature, humidity, overcast)):
        if field.shape != world.shape:
            raise ValueError(f"conditions returned {name} of shape {field.shape}, expected {world.shape}")
    hot = temperature > spec.hot_temperature
    dry = humidity < spec.dry_humidity
    low = overcast < spec.low_overcast
    return hot.astype(np.int8) + dry + low


def _inside(row: np.ndarray, col: np.ndarray, d_row: np.ndarray, d_col: np.ndarray, radius: int,
            cells: int) -> np.ndarray:
    """(K, N) bool: cell (row + d_row, col + d_col) of each source (K,) lies on the grid."""
    span = np.arange(-radius, radius + 1)
    rows = row[:, None] + span
    cols = col[:, None] + span
    rows_ok = (rows >= 0) & (rows < cells)
    cols_ok = (cols >= 0) & (cols < cells)
    return rows_ok[:, d_row + radius] & cols_ok[:, d_col + radius]


def _unique(values: np.ndarray) -> np.ndarray:
    """Sorted distinct values of ``values`` (N,). np.unique is far slower; the values come in
    ascending runs (one per burning tree and block row), which timsort (kind="stable") exploits."""
    ordered = np.sort(values, kind="stable")
    keep = np.ones(len(ordered), bool)
    keep[1:] = ordered[1:] != ordered[:-1]
    return ordered[keep]


def spread(state: FireState, rng: np.random.Generator, spec: FireSpec, downwind_rad: np.ndarray,
           height: np.ndarray, conditions: Conditions) -> np.ndarray:
    """Sorted flat indices (I,) int64 of the existing trees the burning trees set alight this step.

    ``height`` is the flat (B * C * C,) cell height. Draws one float32 uniform per (burning tree,
    existing target) pair, in burning-list order, then row-major block order.
    """
    cells, radius = state.cells, spec.spread_radius_cells
    trees = state.trees.reshape(-1)
    reach = radius * (cells + 1)  # the farthest a target's flat index lies from its source's
    index = np.int32 if trees.size + reach < 2**31 else np.int64  # int32 halves the memory traffic of the pairs
    src = state.burning.astype(index)
    world, row, col = split_flat(src, cells)
    d_row, d_col = block_offsets(radius)
    target = src[:, None] + (d_row * cells + d_col).astype(index)[None, :]
    tried = np.take(trees, target, mode="clip") == TreeState.EXISTING  # clip: off-grid targets are masked below
    edge = np.flatnonzero((row < radius) | (row >= cells - radius) | (col < radius) | (col >= cells - radius))
    if edge.size:  # only sources near the border have blocks reaching off the grid
        tried[edge] &= _inside(row[edge], col[edge], d_row, d_col, radius, cells)
    pick = np.flatnonzero(tried)
    if pick.size == 0:
        return np.zeros(0, np.int64)
    k, o = np.divmod(pick.astype(index), index(len(d_row)))
    t = target.reshape(-1)[pick]
    first = np.ones(len(k), bool)  # k ascends with pick: runs of one source each
    first[1:] = k[1:] != k[:-1]
    sources = k[first]  # only the burning trees that try something need weather
    at = (world[sources], row[sources], col[sources])
    weather = weather_factors(spec, conditions, *(a.astype(np.int64) for a in at))
    factors = weather[np.cumsum(first) - 1]
    factors += downwind_table(downwind_rad, d_row, d_col, spec.downwind_cone_deg)[world[k], o]
    factors += height[t] > height[src[k]]
    chance = np.minimum(1.0, spec.spread_chance_per_factor * np.arange(FACTORS + 1)).astype(np.float32)
    hit = rng.random(len(pick), dtype=np.float32) < chance[factors]
    return _unique(t[hit]).astype(np.int64)


def fire_step(state: FireState, rng: np.random.Generator, spec: FireSpec, downwind_rad: np.ndarray,
              cell_height: np.ndarray, conditions: Conditions) -> FireState:
    """Advance every world by one fire step; writes ``state.trees`` in place (``state`` is consumed).

    downwind_rad (B,) direction the wind blows to per world (radians from +x towards +y);
    cell_height (B, C, C) terrain height at cell centres (C-contiguous, else copied each call);
    ``conditions`` (see :data:`Conditions`) is called at most once, with the burning trees that have
    an existing tree in their block. Spread (:func:`spread`) uses the trees burning at the start;
    then their ages grow by one, those reaching ``burn_steps`` become BURNT and leave the list, and
    the new ignitions join it with age 0 in flat-index order. ``quiet`` restarts at 0 in a world
    with a new ignition and grows by one otherwise; a world is out once ``quiet >= quiet_steps_out``
    and nothing burns there. Worlds already out have nothing burning, so nothing changes there.
    """
    batch, cells = state.batch, state.cells
    downwind = vector("downwind_rad", downwind_rad, batch)
    height = np.asarray(cell_height)
    if height.shape != state.trees.shape or not np.issubdtype(height.dtype, np.number):
        raise ValueError(f"cell_height must be a numeric {state.trees.shape} array, got {height.dtype} {height.shape}")
    new = spread(state, rng, spec, downwind, height.reshape(-1), conditions)
    age = state.age + np.int32(1)
    done = age >= spec.burn_steps
    trees = state.trees.reshape(-1)
    trees[state.burning[done]] = TreeState.BURNT
    trees[new] = TreeState.BURNING
    burning = np.concatenate([state.burning[~done], new])
    area = cells * cells
    ignited = np.bincount(new // area, minlength=batch).astype(np.int64)
    burnt_out = np.bincount(state.burning[done] // area, minlength=batch).astype(np.int64)
    alive = np.bincount(burning // area, minlength=batch)
    quiet = np.where(state.out, state.quiet, np.where(ignited > 0, 0, state.quiet + 1)).astype(np.int32)
    out = state.out | ((quiet >= spec.quiet_steps_out) & (alive == 0))
    return FireState(trees=state.trees, burning=burning, age=np.concatenate([age[~done], np.zeros(len(new), np.int32)]),
                     quiet=quiet, out=out, ignited=ignited, burnt_out=burnt_out)
