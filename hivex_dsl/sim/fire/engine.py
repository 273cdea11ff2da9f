"""The fire engine's state, constants, resets and coordinate helpers (ENVIRONMENTS.md, AWS).

Grid: the forest grid of :mod:`hivex_dsl.sim.procgen.forest`, ``trees[b, row, col]`` with ``row``
indexing y and ``col`` indexing x. Cell coordinates are fractional (row, col) with the centre of
cell ``(row, col)`` at exactly ``(row, col)``; a point (x, y) in metres lies at
``row = (y + half_extent_m) / spacing_m - 0.5``, ``col = (x + half_extent_m) / spacing_m - 0.5``
(:func:`cell_coords`). Water drops and the closest-fire search measure distances between such
points and cell *centres*: a tree's +/-1.5 m jitter is ignored, because the 30 m drop radius and
the 150 m view square are 20 to 100 times larger, so at most a rim of trees shifts in or out.

A flat index ``i`` addresses ``trees.reshape(-1)``: world ``i // C**2``, row ``i % C**2 // C``,
col ``i % C``. ``burning`` lists the flat indices of every burning tree of every world.

Ownership: ``fire_step``, ``douse`` and ``fire_reset_where`` write ``trees`` in place and return a
new :class:`FireState` sharing it (copying a (256, 400, 400) grid costs more than a whole step);
the state passed in is consumed: read nothing from it afterwards. :func:`fire_copy` snapshots.
Editing ``trees`` by hand must not turn a cell back into an existing tree while its world burns
(``FireState.spent`` relies on that): reset the world instead.
"""

from __future__ import annotations

import enum
from dataclasses import dataclass
from typing import Any, ClassVar, Literal

import numpy as np
from pydantic import Field

from ...lang.spec.common import AS_DEFAULT, StrictModel
from ..batching import put_worlds
from ..procgen.forest import ForestSpec


class TreeState(enum.IntEnum):
    """Content of one forest cell (uint8 in ``FireState.trees``)."""

    NONE = 0
    EXISTING = 1
    BURNING = 2
    BURNT = 3
    WET = 4


class FireSpec(StrictModel):
    """Constants of fire spread, burn-out and the end of the fire, and the rule of its start."""

    spread_radius_cells: int = Field(2, ge=1, le=10, description=(
        "[orig] A burning tree tries the trees of the (2r+1) x (2r+1) cells around it (r = 2: within 10 m on a 3 m grid)."))
    spread_chance_per_factor: float = Field(0.2, ge=0.0, le=1.0, description=(
        "[orig] Ignition chance of one try per true factor (downwind, uphill, hot, dry, low overcast), capped at 1."))
    downwind_cone_deg: float = Field(45.0, ge=0.0, le=180.0, description=(
        "[orig] A target counts as downwind when its direction from the source is within this angle of the "
        "direction the wind blows to (inclusive)."))
    hot_temperature: float = Field(0.5, ge=0.0, le=1.0, description=(
        "[orig] Temperature at the burning tree above this counts as a factor."))
    dry_humidity: float = Field(0.5, ge=0.0, le=1.0, description=(
        "[orig] Humidity at the burning tree below this counts as a factor."))
    low_overcast: float = Field(0.5, ge=0.0, le=1.0, description=(
        "[ours] Overcast at the burning tree below this counts as a factor (the original says only 'overcast low')."))
    burn_steps: int = Field(10, ge=1, le=1000, description=(
        "[orig] Fire steps a tree burns (about 10 in the original) before it is burnt; it tries its neighbours in each."))
    quiet_steps_out: int = Field(10, ge=1, le=10_000, description=(
        "[orig] The fire of a world is out once nothing burns and this many fire steps passed without a new ignition."))
    spread_weather_at: Literal["burning", "neighbour"] = Field("burning", description=(
        "[ours] Where a try reads hot, dry and low overcast: 'burning' at the burning tree; 'neighbour' [orig] at "
        "the tree it tries, as the release's ForestDataGenerator.BurnNNeighbourIndexes reads them."))
    spread_max_distance_m: float = Field(0.0, ge=0.0, le=100.0, description=(
        "[ours] 0: a burning tree tries every tree of its block. Above 0, only the trees within this many metres "
        "in 3-D, cell centre to cell centre with their ground heights; the release tries only neighbours within "
        "10 m (Vector3.Distance of the trees' positions, heights included)."))
    spread_wind: Literal["main", "local"] = Field("main", description=(
        "[ours] The wind the downwind factor reads: 'main' the world's main wind; 'local' [orig] the wind at the "
        "burning tree, the main wind turned by the wind's noise field, as the release's Wind.GetWindAtLocation."))

    downwind_angle: Literal["horizontal", "3d"] = Field("horizontal", description=(
        "[ours] 'horizontal': a target counts as downwind by its direction on the map. '3d' [orig]: by the angle in "
        "3-D between its offset from the burning tree, heights included, and the level wind, as the release's "
        "BurnNNeighbourIndexes reads it (Vector3.Angle of the trees' positions' difference and "
        "Wind.GetWindAtLocation), so on a slope fewer targets count as downwind. Needs cell_m."))

    burn_list: Literal["age", "release"] = Field("age", description=(
        "[ours] 'age': a tree tries its neighbours for burn_steps fire steps, and the fire is out once nothing "
        "tries and quiet_steps_out steps passed without an ignition. "
        "'release' [orig]: the release's ForestDataGenerator.BurnNext keeps its burning list as a queue that drops "
        "from its front, each step, as many trees as caught fire 10 steps before, a count that never held the "
        "fire's first trees; so the list always keeps, past their burn_steps, as many of the youngest trees as the "
        "fire started with, burnt but still trying; each step it shows its oldest fifth burnt (seen by no plane "
        "or village, wetted by no drop), still trying; and the fire is out once quiet_steps_out steps pass "
        "without an ignition, whatever the list holds (hivex_dsl.sim.fire.queue)."))

    fire_start: Literal["running", "release"] = Field("running", description=(
        "[ours] 'running': the ignition generator's ranked candidates' blocks burn in rank order until their "
        "running count of trees exceeds its min_burning, so a fire often starts in two places or more. "
        "'release' [orig]: the release's ForestDataGenerator.InitiateFireEnvProbability: only candidates with a "
        "tree on their own cell, and one block, the first candidate's if it holds min_burning trees or more, else "
        "the first in rank order holding more alone, else the last candidate's (its loop replaces the list with "
        "each candidate's block): the fire starts in one place."))

    ADDED_FIELDS: ClassVar[dict[str, Any]] = dict.fromkeys(
        ("spread_weather_at", "spread_max_distance_m", "spread_wind", "burn_list", "fire_start", "downwind_angle"),
        AS_DEFAULT)


# The tree states as NumPy scalars: comparing a uint8 grid with an IntEnum member casts the whole grid
# to int64 first (about 14 times slower on a 400 x 400 grid); assigning one costs a conversion each time.
EXISTING, BURNING, BURNT, WET = (np.uint8(value) for value in
                                 (TreeState.EXISTING, TreeState.BURNING, TreeState.BURNT, TreeState.WET))


NO_CELLS = np.zeros(0, np.int64)  # an empty doused list (read-only: states share it)
NO_AGES = np.zeros(0, np.int32)
NO_CELLS.flags.writeable = NO_AGES.flags.writeable = False


@dataclass(frozen=True)
class FireState:
    """Fires of ``B`` worlds on a ``C x C`` grid with ``K`` burning trees in all.

    trees (B, C, C) uint8 :class:`TreeState`; burning (K,) int64 flat indices of the burning cells in
    ignition order; age (K,) int32 fire steps each has burnt; quiet (B,) int32 fire steps since the last
    new ignition; out (B,) bool the fire is out (stays so until reset); ignited, burnt_out (B,) int64
    trees set burning / burnt by the last fire step of the world (or by its reset). ``douse`` leaves
    these two counters alone: it returns its own counts.

    spent (K,) uint8: 0, or a radius r such that the (2r+1) x (2r+1) block of the burning tree held no
    existing tree at a fire step; it cannot hold one later (no cell turns back into an existing tree
    while its world burns), so spread skips the tree for any radius <= r. Optional (None: all 0).

    doused (D,) int64 flat cells and doused_age (D,) int32: trees that still try their neighbours but no longer
    burn in ``trees``, in no search for burning trees: those water reached while they burnt, as the release's fire
    does (``douse(..., spreading=True)``), wet, and under ``FireSpec.burn_list`` 'release' the burnt trees its
    queue keeps. They age with the list and leave it at ``burn_steps`` (the kept ones as the queue says).
    Optional (None: none).

    carry (B,) int32: how many trees past their burn the release's queue keeps in each world, as many as its
    fire started with (:func:`fire_reset`); read only under ``burn_list`` 'release'. Optional (None: 0).
    """

    trees: np.ndarray
    burning: np.ndarray
    age: np.ndarray
    quiet: np.ndarray
    out: np.ndarray
    ignited: np.ndarray
    burnt_out: np.ndarray
    spent: np.ndarray | None = None
    doused: np.ndarray | None = None
    doused_age: np.ndarray | None = None
    carry: np.ndarray | None = None

    def __post_init__(self) -> None:
        if self.doused is None and self.doused_age is None:
            object.__setattr__(self, "doused", NO_CELLS)
            object.__setattr__(self, "doused_age", NO_AGES)
        elif self.doused is None or self.doused_age is None or self.doused.shape != self.doused_age.shape \
                or self.doused.ndim != 1:
            raise ValueError("doused and doused_age must be given together as equal-length 1-D arrays")
        if self.spent is None:
            object.__setattr__(self, "spent", np.zeros(self.burning.shape, np.uint8))
        elif self.spent.shape != self.burning.shape or self.spent.dtype != np.uint8:
            raise ValueError(f"spent must be a uint8 array shaped like burning {self.burning.shape}, "
                             f"got {self.spent.dtype} {self.spent.shape}")
        trees = self.trees
        if trees.dtype != np.uint8 or trees.ndim != 3 or trees.shape[1] != trees.shape[2]:
            raise ValueError(f"trees must be a uint8 (B, C, C) array, got {trees.dtype} {trees.shape}")
        if not trees.flags.c_contiguous:
            raise ValueError("trees must be C-contiguous: the engine writes it in place through a flat view")
        if self.burning.shape != self.age.shape or self.burning.ndim != 1:
            raise ValueError(f"burning and age must be equal-length 1-D arrays, got {self.burning.shape} and {self.age.shape}")
        if self.carry is None:
            object.__setattr__(self, "carry", np.zeros(trees.shape[0], np.int32))
        for name in ("quiet", "out", "ignited", "burnt_out", "carry"):
            if getattr(self, name).shape != trees.shape[:1]:
                raise ValueError(f"{name} must have shape ({trees.shape[0]},), got {getattr(self, name).shape}")

    @property
    def batch(self) -> int:
        """Number of worlds B."""
        return int(self.trees.shape[0])

    @property
    def cells(self) -> int:
        """Cells per grid side C."""
        return int(self.trees.shape[1])


def split_flat(flat: np.ndarray, cells: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(world, row, col) of flat indices ``flat`` (N,) on a ``cells x cells`` grid, in ``flat``'s dtype."""
    world, inside = np.divmod(flat, cells * cells)
    row, col = np.divmod(inside, cells)
    return world, row, col


def vector(name: str, array: object, length: int | None = None, integer: bool = False) -> np.ndarray:
    """``array`` as a 1-D int64 (``integer``) or finite float64 array, of ``length`` when given."""
    vec = np.asarray(array)
    if vec.ndim != 1 or (length is not None and len(vec) != length):
        wanted = "N" if length is None else str(length)
        raise ValueError(f"{name} must have shape ({wanted},), got {vec.shape}")
    kind = vec.dtype.kind  # dtype kinds, not np.issubdtype: this runs on every step
    if integer:
        if not (kind in "iu" or vec.size == 0):
            raise ValueError(f"{name} must hold integers, got dtype {vec.dtype}")
        return vec.astype(np.int64, copy=False)
    if kind not in "iuf" or not np.isfinite(vec).all():
        raise ValueError(f"{name} must hold finite numbers, got dtype {vec.dtype}")
    return vec.astype(np.float64, copy=False)


def in_range(name: str, values: np.ndarray, stop: int) -> None:
    """Raise unless every integer of ``values`` lies in [0, stop)."""
    if values.size and (values.min() < 0 or values.max() >= stop):
        raise ValueError(f"{name} must lie in [0, {stop}), got range [{values.min()}, {values.max()}]")


def _grids(name: str, array: object, shape: tuple[int, ...] | None = None) -> np.ndarray:
    """``array`` as a bool (N, C, C) array (of ``shape`` when given)."""
    grid = np.asarray(array)
    if grid.dtype != np.bool_ or grid.ndim != 3 or grid.shape[1] != grid.shape[2]:
        raise ValueError(f"{name} must be a bool (worlds, C, C) array, got {grid.dtype} {grid.shape}")
    if shape is not None and grid.shape != shape:
        raise ValueError(f"{name} must have shape {shape}, got {grid.shape}")
    return grid


def _fresh_trees(exists: np.ndarray, ignite: np.ndarray) -> np.ndarray:
    """(N, C, C) uint8 trees: EXISTING where ``exists``, BURNING where ``ignite`` (a subset of ``exists``)."""
    exists = _grids("exists", exists)
    ignite = _grids("ignite", ignite, exists.shape)
    stray = ignite & ~exists
    if stray.any():
        world, row, col = (int(v[0]) for v in np.nonzero(stray))
        raise ValueError(f"ignite marks {int(stray.sum())} cell(s) without a tree, first world {world} "
                         f"row {row} col {col}: only trees can burn")
    trees = exists.astype(np.uint8) * EXISTING
    trees[ignite] = BURNING
    return trees


def fire_reset(exists: np.ndarray, ignite: np.ndarray) -> FireState:
    """New fires: trees where ``exists`` (B, C, C) bool, burning where ``ignite`` (B, C, C) bool.

    The burning list is in flat-index order; every age, quiet counter and burnt_out count is 0; ``carry`` is
    each world's count of first trees.
    """
    trees = _fresh_trees(exists, ignite)
    batch = trees.shape[0]
    burning = np.flatnonzero(trees == BURNING).astype(np.int64)
    ignited = np.bincount(burning // (trees.shape[1] * trees.shape[2]), minlength=batch).astype(np.int64)
    return FireState(trees=trees, burning=burning, age=np.zeros(len(burning), np.int32),
                     quiet=np.zeros(batch, np.int32), out=np.zeros(batch, bool), ignited=ignited,
                     burnt_out=np.zeros(batch, np.int64), carry=ignited.astype(np.int32))


def fire_reset_where(state: FireState, mask: np.ndarray, exists: np.ndarray, ignite: np.ndarray) -> FireState:
    """Replace the worlds where ``mask`` (B,) bool holds; ``exists``/``ignite`` (M, C, C) bool for those M worlds.

    Writes ``state.trees`` in place. The other worlds keep everything, their burning trees keep their
    order; the reset worlds' ignitions follow them in flat-index order.
    """
    worlds = int(np.count_nonzero(_checked_mask(state, mask)))
    cells = state.cells
    fresh = fire_reset(exists, ignite)
    if fresh.trees.shape != (worlds, cells, cells):
        raise ValueError(f"exists and ignite must have shape ({worlds}, {cells}, {cells}) for the "
                         f"{worlds} masked worlds, got {fresh.trees.shape}")
    return fire_put_worlds(state, mask, fresh)


def _checked_mask(state: FireState, mask: np.ndarray) -> np.ndarray:
    """``mask`` as a (B,) bool array, or ValueError."""
    mask = np.asarray(mask)
    if mask.dtype != np.bool_ or mask.shape != (state.batch,):
        raise ValueError(f"mask must be a bool array of shape ({state.batch},), got {mask.dtype} {mask.shape}")
    return mask


def fire_put_worlds(state: FireState, mask: np.ndarray, fresh: FireState) -> FireState:
    """``state`` with the worlds where ``mask`` (B,) bool holds taken from ``fresh`` (their M fires, in order).

    Writes ``state.trees`` in place. The other worlds keep everything, their burning trees keep their
    order; the fresh worlds' burning trees follow them in ``fresh``'s order. :func:`fire_reset_where` is
    this with ``fresh = fire_reset(exists, ignite)``; a caller that has that reset already passes it here.
    """
    mask = _checked_mask(state, mask)
    worlds = np.flatnonzero(mask)
    if fresh.trees.shape != (len(worlds),) + state.trees.shape[1:]:
        raise ValueError(f"fresh must hold the {len(worlds)} masked worlds of shape {state.trees.shape[1:]}, "
                         f"got trees {fresh.trees.shape}")
    area = state.cells * state.cells
    state.trees[worlds] = fresh.trees
    keep, burning = _put_cells(state.burning, fresh.burning, mask, worlds, area)
    kept, doused = _put_cells(state.doused, fresh.doused, mask, worlds, area)
    return FireState(trees=state.trees, burning=burning,
                     age=np.concatenate([state.age[keep], fresh.age]), quiet=put_worlds(state.quiet, mask, fresh.quiet),
                     out=put_worlds(state.out, mask, fresh.out), ignited=put_worlds(state.ignited, mask, fresh.ignited),
                     burnt_out=put_worlds(state.burnt_out, mask, fresh.burnt_out),
                     spent=np.concatenate([state.spent[keep], fresh.spent]), doused=doused,
                     doused_age=np.concatenate([state.doused_age[kept], fresh.doused_age]),
                     carry=put_worlds(state.carry, mask, fresh.carry))


def fire_take_worlds(state: FireState, mask: np.ndarray) -> FireState:
    """The worlds where ``mask`` (B,) bool holds, as a fire of their own (M worlds, in order; every array a copy):
    what a caller steps alone and puts back with :func:`fire_put_worlds`. Each world's lists keep their order."""
    mask = _checked_mask(state, mask)
    worlds = np.flatnonzero(mask)
    area = state.cells * state.cells
    renumber = np.cumsum(mask) - 1  # a kept world's index among the M

    def take(cells: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        world, cell = np.divmod(cells, area)
        keep = mask[world]
        return keep, renumber[world[keep]] * area + cell[keep]

    keep, burning = take(state.burning)
    kept, doused = take(state.doused)
    return FireState(trees=state.trees[worlds], burning=burning, age=state.age[keep], quiet=state.quiet[worlds],
                     out=state.out[worlds], ignited=state.ignited[worlds], burnt_out=state.burnt_out[worlds],
                     spent=state.spent[keep], doused=doused, doused_age=state.doused_age[kept],
                     carry=state.carry[worlds])


def _put_cells(cells: np.ndarray, fresh: np.ndarray, mask: np.ndarray, worlds: np.ndarray, area: int
               ) -> tuple[np.ndarray, np.ndarray]:
    """(keep (K,) bool: the flat ``cells`` of the worlds not in ``mask``, the list with them first, then the
    ``fresh`` list's cells moved into the masked ``worlds``)."""
    keep = ~mask[cells // area]
    fresh_world, cell = np.divmod(fresh, area)
    return keep, np.concatenate([cells[keep], worlds[fresh_world] * area + cell])


def fire_copy(state: FireState) -> FireState:
    """An independent snapshot of ``state`` (every array copied)."""
    return FireState(**{name: getattr(state, name).copy() for name in state.__dataclass_fields__})


def burning_count(state: FireState) -> np.ndarray:
    """(B,) int64 burning trees per world."""
    cells = state.cells
    return np.bincount(state.burning // (cells * cells), minlength=state.batch).astype(np.int64)


def any_burning(state: FireState) -> np.ndarray:
    """(B,) bool: the world's fire goes on, some tree burns or a doused one still spreads (one world: no count
    needed)."""
    if state.batch == 1:
        return np.array([state.burning.size + state.doused.size > 0])
    if state.doused.size:
        return (burning_count(state) + np.bincount(state.doused // (state.cells ** 2), minlength=state.batch)) > 0
    return burning_count(state) > 0


def cell_coords(spec: ForestSpec, x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Fractional (row, col) float64 cell coordinates of points ``x``, ``y`` metres (any shape).

    The centre of cell (row, col) maps to exactly (row, col); points off the grid give values
    outside [-0.5, C - 0.5).
    """
    row = (np.asarray(y, dtype=np.float64) + spec.half_extent_m) / spec.spacing_m - 0.5
    col = (np.asarray(x, dtype=np.float64) + spec.half_extent_m) / spec.spacing_m - 0.5
    return row, col


def cell_xy(spec: ForestSpec, row: np.ndarray, col: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Metres (x, y) of cell coordinates ``row``, ``col`` (any shape): the inverse of :func:`cell_coords`."""
    x = (np.asarray(col, dtype=np.float64) + 0.5) * spec.spacing_m - spec.half_extent_m
    y = (np.asarray(row, dtype=np.float64) + 0.5) * spec.spacing_m - spec.half_extent_m
    return x, y


def length_in_cells(spec: ForestSpec, metres: float) -> float:
    """A distance of ``metres`` in cell units (e.g. a 30 m drop radius is 10 cells on a 3 m grid)."""
    return float(metres) / spec.spacing_m
