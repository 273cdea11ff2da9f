"""One fire step of every world: spread from the burning trees, burn-out, the end of the fire.

Every burning tree tries each existing tree of the (2r+1) x (2r+1) cells around it (not itself,
inside the grid) once, an independent draw per (burning, target) pair, with probability
``min(1, spread_chance_per_factor * n)``; ``n`` counts the target within ``downwind_cone_deg``
of the wind direction seen from the source, the target higher than the source, and at the
source temperature > hot, humidity < dry, overcast < low. A target tried by several burning trees
thus ignites with probability ``1 - prod(1 - p)``. The release's rules are the spec's options:
the weather read at the target (``spread_weather_at``), the wind at the source rather than the
world's main wind (``spread_wind``, a :data:`Winds` callable), and only targets within
``spread_max_distance_m`` in 3-D (a try beyond it draws its number and never ignites). The work
is proportional to the front: K burning trees x (2r+1)^2 cells, gathered from flat indices;
nothing scans the grid. A burning tree whose block held no existing tree is marked
(``FireState.spent``) and skipped from then on: most of a fire's burning trees are behind its
front, with nothing left to ignite.
"""

from __future__ import annotations

from functools import lru_cache
from typing import Callable

import numpy as np

from ...base import portable
from ..batching import assemble
from ..procgen.wind import TWO_PI
from .engine import BURNING, BURNT, EXISTING, NO_CELLS, FireSpec, FireState, vector
from .factors import FactorGrid, factor_count
from .queue import keep_youngest, list_lengths, settle

# conditions(world (N,), row (N,), col (N,)) int64 -> (temperature (N,), humidity (N,), overcast (N,)) in [0, 1]
Conditions = Callable[[np.ndarray, np.ndarray, np.ndarray], tuple[np.ndarray, np.ndarray, np.ndarray]]
# winds(world (N,), row (N,), col (N,)) int64 -> (N,) float64 direction the wind blows to at those cells (radians)
Winds = Callable[[np.ndarray, np.ndarray, np.ndarray], np.ndarray]
FACTORS = 5
CONE_TOLERANCE_RAD = 1e-9  # "within" is inclusive: a diagonal exactly 45 degrees off the wind counts
FLOAT64, INT32, BOOL = np.dtype(np.float64), np.dtype(np.int32), np.dtype(np.bool_)
SHORT_LIST = 4096  # burning trees up to which spread works in int64 (see spread)


@lru_cache(maxsize=16)
def block_offsets(radius: int) -> tuple[np.ndarray, np.ndarray]:
    """(N,) int64 row and col offsets of the (2r+1)^2 block around a cell, without the cell, row-major."""
    span = np.arange(-radius, radius + 1)
    rows, cols = (a.ravel() for a in np.meshgrid(span, span, indexing="ij"))
    keep = (rows != 0) | (cols != 0)
    rows, cols = rows[keep], cols[keep]
    rows.flags.writeable = cols.flags.writeable = False
    return rows, cols


@lru_cache(maxsize=16)
def _block_of(radius: int, cells: int, index: type) -> tuple[np.ndarray, np.ndarray]:
    """Flat offsets (N,) ``index`` of the block's cells from its centre, and (C * C,) bool: a cell lies
    within ``radius`` of the grid edge (its block may reach off the grid)."""
    d_row, d_col = block_offsets(radius)
    offsets = (d_row * cells + d_col).astype(index)
    band = np.arange(cells)
    near = (band < radius) | (band >= cells - radius)
    edge = (near[:, None] | near[None, :]).reshape(-1)
    offsets.flags.writeable = edge.flags.writeable = False
    return offsets, edge


@lru_cache(maxsize=16)
def _offset_directions(radius: int) -> np.ndarray:
    """(N,) float64 direction atan2(d_row, d_col) of each block offset."""
    d_row, d_col = block_offsets(radius)
    angle = portable.arctan2(d_row, d_col)
    angle.flags.writeable = False
    return angle


@lru_cache(maxsize=16)
def _offset_reach2(radius: int) -> np.ndarray:
    """(N,) float64 squared length d_row^2 + d_col^2 of each block offset, in cells."""
    d_row, d_col = block_offsets(radius)
    reach = (d_row * d_row + d_col * d_col).astype(np.float64)
    reach.flags.writeable = False
    return reach


@lru_cache(maxsize=64)
def _cone_limit(cone_deg: float) -> float:
    return np.radians(cone_deg) + CONE_TOLERANCE_RAD


@lru_cache(maxsize=64)
def _chances(chance_per_factor: float) -> np.ndarray:
    """(FACTORS + 1,) float32 ignition chance of one try by its number of true factors."""
    chance = np.minimum(1.0, chance_per_factor * np.arange(FACTORS + 1)).astype(np.float32)
    chance.flags.writeable = False
    return chance


def _downwind(downwind_rad: np.ndarray, direction: np.ndarray, cone_deg: float) -> np.ndarray:
    """(B, N) bool: the offsets' directions (N,) lie within ``cone_deg`` of each world's downwind direction
    ``downwind_rad`` (B,); :func:`hivex_dsl.sim.procgen.wind.wrap_angle`'s operations, done in place."""
    gap = direction - downwind_rad[:, None]
    gap += np.pi
    gap %= TWO_PI
    gap -= np.pi
    return np.abs(gap, out=gap) <= _cone_limit(cone_deg)


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
    return factor_count(temperature, humidity, overcast, spec)


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
    """Sorted distinct values of ``values`` (N,), which it sorts in place (pass a fresh array). np.unique is
    far slower; the values come in ascending runs (one per burning tree and block row), which timsort
    (kind="stable") exploits."""
    ordered = values
    ordered.sort(kind="stable")
    keep = np.empty(len(ordered), bool)
    keep[:1] = True
    np.not_equal(ordered[1:], ordered[:-1], out=keep[1:])
    return ordered[keep]


def _tries(state: FireState, radius: int, index: type) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The burning trees that may still ignite something and what each may try.

    Returns (live (L,) positions in the burning list of the trees not known to be spent for ``radius``,
    src (L,) ``index`` their flat cells, target (L, N) ``index`` the flat cells of their blocks, tried
    (L, N) bool: the target is an existing tree on the grid).
    """
    cells = state.trees.shape[1]
    offsets, edge_cell = _block_of(radius, cells, index)
    live = (state.spent < radius).nonzero()[0]
    src = state.burning.take(live)
    if index is not np.int64:
        src = src.astype(index)
    target = src[:, None] + offsets
    tried = state.trees.take(target, mode="clip") == EXISTING  # clip: off-grid targets are masked below
    local = src if state.trees.shape[0] == 1 else src % (cells * cells)
    edge = edge_cell.take(local).nonzero()[0]
    if edge.size:  # only sources near the border have blocks reaching off the grid
        d_row, d_col = block_offsets(radius)
        row, col = np.divmod(local[edge], cells)
        tried[edge] &= _inside(row, col, d_row, d_col, radius, cells)
    return live, src, target, tried


def _spent(state: FireState, radius: int, live: np.ndarray, tries: np.ndarray) -> np.ndarray:
    """(K,) uint8 ``state.spent`` with ``radius`` for the live trees (L,) but those at positions ``tries``
    (P,) among them, which found something to try."""
    spent = state.spent.copy()
    spent[live[np.bincount(tries, minlength=len(live)) == 0]] = radius
    return spent


def _per_source(ask: Callable, k: np.ndarray, source: np.ndarray, area: int, cells: int) -> np.ndarray:
    """(P,) ``ask(world, row, col)`` at the source of each pair, asked once per distinct source: the source's
    position k (P,) among the live trees, ascending, and its flat cell (P,)."""
    first = np.ones(len(k), bool)  # k ascends: runs of one source each
    np.not_equal(k[1:], k[:-1], out=first[1:])
    world, local = np.divmod(source[first], area)  # only the burning trees that try something are asked
    row, col = np.divmod(local, cells)
    return ask(world.astype(np.int64), row.astype(np.int64), col.astype(np.int64))[np.cumsum(first) - 1]


def _per_target(ask: Callable, target: np.ndarray, area: int, cells: int) -> np.ndarray:
    """(P,) ``ask(world, row, col)`` at each pair's target cell (P,), asked once per distinct target."""
    cell, which = np.unique(target, return_inverse=True)
    world, local = np.divmod(cell.astype(np.int64), area)
    row, col = np.divmod(local, cells)
    return ask(world, row, col)[which]


def _pair_weather(spec: FireSpec, conditions: Conditions | FactorGrid, k: np.ndarray, source: np.ndarray,
                  target: np.ndarray, area: int, cells: int) -> np.ndarray:
    """(P,) int8 weather factors of each pair, read where ``spec.spread_weather_at`` says: at its source (its
    position k (P,) among the live trees, ascending, and its flat cell (P,)) or at its target cell (P,)."""
    at_target = spec.spread_weather_at == "neighbour"
    if isinstance(conditions, FactorGrid):
        return conditions.at(target if at_target else source, area)

    def ask(world: np.ndarray, row: np.ndarray, col: np.ndarray) -> np.ndarray:
        return weather_factors(spec, conditions, world, row, col)

    return _per_target(ask, target, area, cells) if at_target else _per_source(ask, k, source, area, cells)


def _pair_downwind(spec: FireSpec, downwind: np.ndarray | Winds, k: np.ndarray, o: np.ndarray, source: np.ndarray,
                   area: int, cells: int, radius: int) -> np.ndarray:
    """(P,) bool: each pair's target lies within the downwind cone of the wind at its source, the world's main wind
    ``downwind`` (B,) radians or a :data:`Winds` callable asked once per distinct source."""
    directions = _offset_directions(radius)
    if callable(downwind):
        return _downwind(_source_wind(downwind, k, source, area, cells), directions.take(o)[:, None],
                         spec.downwind_cone_deg)[:, 0]
    table = _downwind(downwind, directions, spec.downwind_cone_deg)
    return table.take(o if len(downwind) == 1 else (source // area) * table.shape[1] + o)


def _source_wind(downwind: np.ndarray | Winds, k: np.ndarray, source: np.ndarray, area: int, cells: int) -> np.ndarray:
    """(P,) float64 radians: the wind at each pair's source, from the world's main wind ``downwind`` (B,) or a
    :data:`Winds` callable asked once per distinct source (k (P,) ascending, source (P,) flat cells)."""
    if callable(downwind):
        return np.asarray(_per_source(downwind, k, source, area, cells), dtype=np.float64)
    return downwind.take(0 if len(downwind) == 1 else source // area)


def _downwind_in_3d(spec: FireSpec, downwind: np.ndarray | Winds, down: np.ndarray, k: np.ndarray, o: np.ndarray,
                    source: np.ndarray, climb: np.ndarray, area: int, cells: int, radius: int, cell_m: float | None
                    ) -> np.ndarray:
    """(P,) bool: the pairs of ``down`` (within the cone on the map) whose target also lies within it in 3-D, its
    offset of r metres on the map and ``climb`` (P,) metres up: the angle's cosine to the level wind is the map
    angle's times r / sqrt(r^2 + climb^2), so a target as far up or down as away is never downwind."""
    if cell_m is None:
        raise ValueError("downwind_angle '3d' is set: pass cell_m, the forest grid's cell side in metres")
    pick = np.flatnonzero(down & (climb != 0))  # level targets keep the map's reading
    if not pick.size:
        return down
    wind = _source_wind(downwind, k.take(pick), source.take(pick), area, cells)
    along = np.cos(_offset_directions(radius).take(o.take(pick)) - wind)
    run2 = _offset_reach2(radius).take(o.take(pick)) * (cell_m * cell_m)
    rise = climb.take(pick).astype(np.float64)
    limit = np.cos(np.radians(spec.downwind_cone_deg))
    inside = (along > 0.0) & (along * along * run2 >= limit * limit * (run2 + rise * rise))
    down = down.copy()
    down[pick] = inside
    return down


def _within_reach(spec: FireSpec, o: np.ndarray, climb: np.ndarray, radius: int, cell_m: float | None) -> np.ndarray:
    """(P,) bool: each pair's target lies within ``spec.spread_max_distance_m`` of its source in 3-D, from its block
    offset o (P,) on cells of ``cell_m`` metres and the height difference ``climb`` (P,) in metres."""
    if cell_m is None:
        raise ValueError("spread_max_distance_m is set: pass cell_m, the forest grid's cell side in metres")
    reach = _offset_reach2(radius).take(o) * (cell_m * cell_m)
    reach += np.square(climb, dtype=np.float64)
    return reach <= spec.spread_max_distance_m ** 2


def spread(state: FireState, rng: np.random.Generator, spec: FireSpec, downwind_rad: np.ndarray | Winds,
           height: np.ndarray, conditions: Conditions | FactorGrid, cell_m: float | None = None
           ) -> tuple[np.ndarray, np.ndarray]:
    """Sorted flat indices (I,) int64 of the existing trees the burning trees set alight this step, and
    the burning trees' ``spent`` (K,) uint8 updated with the blocks found without existing trees.

    ``height`` holds the cell heights, (B, C, C) or flat, read by flat index; ``downwind_rad`` the main wind
    (B,) or, under ``spread_wind`` 'local', a :data:`Winds` callable; ``cell_m`` the cell side in metres (needed
    only under ``spread_max_distance_m``). Draws one float32 uniform per (burning tree, existing target) pair, in
    burning-list order, then row-major block order, whatever the options. Trees known to be spent have no such
    pair, so skipping them changes no draw.
    """
    cells = state.trees.shape[1]
    radius = spec.spread_radius_cells
    area = cells * cells
    reach = radius * (cells + 1)  # the farthest a target's flat index lies from its source's
    # int32 halves the memory traffic of many pairs; a short list skips the conversions instead
    index = np.int32 if len(state.burning) > SHORT_LIST and state.trees.size + reach < 2**31 else np.int64
    live, src, target, tried = _tries(state, radius, index)
    pick = tried.reshape(-1).nonzero()[0]
    if index is not np.int64:
        pick = pick.astype(index)
    k, o = np.divmod(pick, tried.shape[1])  # a Python int keeps the dtype of pick (NEP 50)
    spent = _spent(state, radius, live, k)
    if pick.size == 0:
        return np.zeros(0, np.int64), spent
    t = target.take(pick)
    source = src.take(k)
    factors = _pair_weather(spec, conditions, k, source, t, area, cells)
    down = _pair_downwind(spec, downwind_rad, k, o, source, area, cells, radius)
    target_height, source_height = height.take(t), height.take(source)
    if spec.downwind_angle == "3d":
        down = _downwind_in_3d(spec, downwind_rad, down, k, o, source, target_height - source_height, area, cells,
                               radius, cell_m)
    factors += down
    factors += target_height > source_height
    hit = rng.random(len(pick), dtype=np.float32) < _chances(spec.spread_chance_per_factor).take(factors)
    if spec.spread_max_distance_m > 0.0:
        hit &= _within_reach(spec, o, target_height - source_height, radius, cell_m)
    new = _unique(t[hit])
    return (new if index is np.int64 else new.astype(np.int64)), spent


def _checked_height(cell_height: np.ndarray, shape: tuple[int, ...]) -> np.ndarray:
    """``cell_height`` as a flat (B * C * C,) numeric array, after checking its shape (B, C, C)."""
    height = np.asarray(cell_height)
    if height.shape != shape or height.dtype.kind not in "iufc":
        raise ValueError(f"cell_height must be a numeric {shape} array, got {height.dtype} {height.shape}")
    return height.reshape(-1)


def _checked_wind(downwind_rad: np.ndarray | Winds, batch: int) -> np.ndarray | Winds:
    """``downwind_rad`` as a finite (B,) float64 array: :func:`.engine.vector`'s checks, with two ufunc calls
    for the array the simulators pass (anything else takes the general checks and conversion); a :data:`Winds`
    callable as it is."""
    wind = downwind_rad
    if callable(wind):
        return wind
    if (type(wind) is np.ndarray and wind.dtype is FLOAT64 and wind.shape == (batch,)
            and np.logical_and.reduce(np.isfinite(wind))):
        return wind
    return vector("downwind_rad", wind, batch)


def fire_step(state: FireState, rng: np.random.Generator, spec: FireSpec, downwind_rad: np.ndarray | Winds,
              cell_height: np.ndarray, conditions: Conditions | FactorGrid, cell_m: float | None = None) -> FireState:
    """Advance every world by one fire step; writes ``state.trees`` in place (``state`` is consumed).

    downwind_rad (B,) direction the wind blows to per world (radians from +x towards +y), or a :data:`Winds`
    callable giving it at the burning trees' cells; cell_m the forest cell's side in metres, needed only
    under ``spec.spread_max_distance_m``;
    cell_height (B, C, C) terrain height at cell centres (C-contiguous, else copied each call);
    ``conditions`` (see :data:`Conditions`) is called at most once, with the burning trees that have
    an existing tree in their block (or a :class:`.factors.FactorGrid` of the same weather, read per
    pair). Spread (:func:`spread`) uses the trees burning at the start, then the doused trees that still spread
    (``FireState.doused``, which age alike and leave at ``burn_steps``, staying wet);
    then their ages grow by one, those reaching ``burn_steps`` become BURNT and leave the list, and
    the new ignitions join it with age 0 in flat-index order. ``quiet`` restarts at 0 in a world
    with a new ignition and grows by one otherwise; a world is out once ``quiet >= quiet_steps_out``
    and nothing burns there. Worlds already out have nothing burning, so nothing changes there.
    Under ``spec.burn_list`` 'release' the youngest ``state.carry`` trees past their burn go on trying from the
    doused list, and a world is out once ``quiet >= quiet_steps_out``, both its lists then emptied (:mod:`.queue`).
    """
    trees = state.trees
    downwind = _checked_wind(downwind_rad, trees.shape[0])
    return fire_step_unchecked(state, rng, spec, downwind, _checked_height(cell_height, trees.shape), conditions,
                               cell_m)


def fire_step_unchecked(state: FireState, rng: np.random.Generator, spec: FireSpec, downwind_rad: np.ndarray | Winds,
                        cell_height: np.ndarray, conditions: Conditions | FactorGrid,
                        cell_m: float | None = None) -> FireState:
    """:func:`fire_step` without its argument checks, for a simulator whose arguments are valid by
    construction: ``downwind_rad`` a finite (B,) float64 array, ``cell_height`` a numeric (B, C, C) array
    (C-contiguous, else copied each call) of the fire's shape. Other arguments are undefined behaviour."""
    trees = state.trees
    queue = spec.burn_list == "release"
    before = list_lengths(state) if queue else None
    if state.doused.size:
        new, spent, doused, doused_age = _spread_with_doused(state, rng, spec, downwind_rad, cell_height, conditions,
                                                             cell_m, keep_aged=queue)
    else:
        new, spent = spread(state, rng, spec, downwind_rad, cell_height, conditions, cell_m)
        doused, doused_age = state.doused, state.doused_age
    ended, burning, age, spent = _burn_out(state, spent, spec.burn_steps)
    if queue:
        doused, doused_age = keep_youngest(ended, doused, doused_age, state.carry, spec.burn_steps, trees[0].size)
    flat = trees.reshape(-1)
    flat[ended] = BURNT
    flat[new] = BURNING
    burning = np.concatenate([burning, new])
    age = np.concatenate([age, np.zeros(len(new), np.int32)])
    spent = np.concatenate([spent, np.zeros(len(new), np.uint8)])
    tally = _tally_one if trees.shape[0] == 1 else _tally
    alive = NO_CELLS if queue else burning if not doused.size else np.concatenate([burning, doused])
    quiet, out, ignited, burnt_out = tally(state, len(new), len(ended), alive, spec.quiet_steps_out, new, ended)
    if queue:
        lists = settle(trees, before, out > state.out, (burning, age, spent, doused, doused_age))
        burning, age, spent, doused, doused_age, burnt = lists
        burnt_out = burnt_out + burnt
    return assemble(FireState, trees=trees, burning=burning, age=age, quiet=quiet, out=out, ignited=ignited,
                    burnt_out=burnt_out, spent=spent, doused=doused, doused_age=doused_age, carry=state.carry)


def _spread_with_doused(state: FireState, rng: np.random.Generator, spec: FireSpec, downwind_rad: np.ndarray | Winds,
                        cell_height: np.ndarray, conditions: Conditions | FactorGrid, cell_m: float | None,
                        keep_aged: bool = False) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """:func:`spread` from the burning trees and then the doused ones, which try their neighbours as burning trees
    do (the release's BurnNext reads its burning list, which water never touches); -> (new ignitions, the burning
    trees' ``spent``, then the doused trees (D',) and their ages (D',) after they aged a step, those reaching
    ``burn_steps`` gone unless ``keep_aged`` (the release's queue then picks: :mod:`.queue`): they stay as they
    are in ``trees``)."""
    burnt = len(state.burning)
    sources = FireState(trees=state.trees, burning=np.concatenate([state.burning, state.doused]),
                        age=np.concatenate([state.age, state.doused_age]), quiet=state.quiet, out=state.out,
                        ignited=state.ignited, burnt_out=state.burnt_out,
                        spent=np.concatenate([state.spent, np.zeros(len(state.doused), np.uint8)]))
    new, spent = spread(sources, rng, spec, downwind_rad, cell_height, conditions, cell_m)
    age = state.doused_age + 1
    if keep_aged:
        return new, spent[:burnt], state.doused, age
    going = age < spec.burn_steps
    return new, spent[:burnt], state.doused[going], age[going]


def _tally(state: FireState, ignitions: int, burnt: int, burning: np.ndarray, quiet_steps_out: int,
           new: np.ndarray, ended: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(quiet (B,) int32, out (B,) bool, ignited (B,) int64, burnt_out (B,) int64) after a fire step that
    set the flat cells ``new`` alight and burnt out ``ended`` (``ignitions`` and ``burnt`` of them), with
    ``burning`` (K,) the list afterwards."""
    batch, area = state.trees.shape[0], state.trees.shape[1] ** 2
    ignited = np.bincount(new // area, minlength=batch).astype(np.int64)
    alive = np.bincount(burning // area, minlength=batch)
    quiet = np.where(state.out, state.quiet, (state.quiet + 1) * (ignited == 0)).astype(np.int32, copy=False)
    out = state.out | ((quiet >= quiet_steps_out) & (alive == 0))
    return quiet, out, ignited, np.bincount(ended // area, minlength=batch).astype(np.int64)


def _tally_one(state: FireState, ignitions: int, burnt: int, burning: np.ndarray, quiet_steps_out: int,
               new: np.ndarray, ended: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """:func:`_tally` of one world, in Python numbers (tests/fire/test_fire_fast_paths.py compares them)."""
    was_out, was_quiet = bool(state.out[0]), int(state.quiet[0])
    quiet = was_quiet if was_out else 0 if ignitions else was_quiet + 1
    out = was_out or (quiet >= quiet_steps_out and len(burning) == 0)
    # an unchanged counter or flag keeps its array (the state passed in is consumed)
    return (state.quiet if quiet == was_quiet and state.quiet.dtype == INT32 else np.array([quiet], np.int32),
            state.out if out == was_out and state.out.dtype == BOOL else np.array([out]),
            np.array([ignitions], np.int64),
            np.array([burnt], np.int64))


def _burn_out(state: FireState, spent: np.ndarray, burn_steps: int
              ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(ended (D,) flat cells of the trees whose age reaches ``burn_steps``, then burning, age (grown by
    one) and ``spent`` (K,) of the others, in list order)."""
    age = state.age + 1  # int32: NEP 50
    done = age >= burn_steps
    count = np.count_nonzero(done)
    if np.count_nonzero(done[:count]) == count:  # the oldest lead a list kept in ignition order: slices, no gathers
        return state.burning[:count], state.burning[count:], age[count:], spent[count:]
    keep = ~done
    return state.burning[done], state.burning[keep], age[keep], spent[keep]
