"""Aerial Wildfire Suppression: forest placement on terrain and fire ignition (ENVIRONMENTS.md).

The forest lives on a square grid of ``cells x cells`` cells of side ``spacing_m`` covering
``+/- half_extent_m``; each cell holds at most one tree, jittered inside it. Grid convention:
``grid[row, col]`` with ``row`` indexing y and ``col`` indexing x, so the centre of cell
``(row, col)`` is ``(centres[col], centres[row])`` with ``centres = cell_centres(spec)``.
Weather arrays handed to :func:`select_ignition` follow the same convention. Lengths are metres.
The terrain is any callable mapping (N, 2) points to (N,) heights, so this module does not
depend on a particular terrain model.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Literal, NamedTuple

import numpy as np
from pydantic import Field, model_validator

from ...lang.spec.common import SCHEMA_VERSION, StrictModel
from .presets import load_preset

HeightAt = Callable[[np.ndarray], np.ndarray]


def check_forest_grid(spec) -> None:
    """Raise ValueError unless a forest spec's grid (``cells`` x ``spacing_m``, ``jitter_m``) covers +/-
    ``half_extent_m`` exactly and keeps every tree inside its cell; every forest spec's validator calls it."""
    if not np.isclose(spec.cells * spec.spacing_m, 2.0 * spec.half_extent_m, rtol=1e-9, atol=0.0):
        raise ValueError(f"cells * spacing_m ({spec.cells} * {spec.spacing_m}) must equal 2 * half_extent_m "
                         f"({2.0 * spec.half_extent_m}) so the grid covers the forest exactly")
    if spec.jitter_m > spec.spacing_m / 2.0:
        raise ValueError(f"jitter_m ({spec.jitter_m}) must be at most spacing_m / 2 ({spec.spacing_m / 2.0}) "
                         "so every tree stays inside its cell")


class ForestSpec(StrictModel):
    """Where trees grow: the placement grid and the height rule."""

    cells: int = Field(400, ge=1, le=4000, description="[orig] Grid cells per side; at most one tree per cell.")
    spacing_m: float = Field(3.0, gt=0.0, le=100.0, description="[orig] Side of one grid cell in metres.")
    half_extent_m: float = Field(600.0, gt=0.0, le=10_000.0, description=(
        "[orig] The grid covers +/- this many metres in x and y; must equal cells * spacing_m / 2."))
    jitter_m: float = Field(1.5, ge=0.0, le=50.0, description=(
        "[orig] Each tree sits at its cell centre plus a uniform offset in +/- this in x and y (at most spacing_m / 2)."))
    min_height_m: float = Field(10.0, ge=-1000.0, le=10_000.0, description="[orig] No tree grows on terrain lower than this.")
    max_height_m: float = Field(100.0, ge=-1000.0, le=10_000.0, description="[orig] No tree grows on terrain higher than this.")
    ideal_height_m: float = Field(55.0, ge=-1000.0, le=10_000.0, description="[orig] Terrain height where the forest is densest.")
    density_falloff: float = Field(0.02, ge=0.0, le=10.0, description=(
        "[orig] Per metre: a tree exists where a uniform draw exceeds density_falloff * |ideal_height_m - height| (2/100)."))
    village_clear_radius_m: float = Field(100.0, ge=0.0, le=10_000.0, description=(
        "[orig] No tree within this distance of the village (trees exist only strictly farther away)."))

    @model_validator(mode="after")
    def _consistent(self) -> "ForestSpec":
        check_forest_grid(self)
        if not self.min_height_m <= self.ideal_height_m <= self.max_height_m:
            raise ValueError(f"need min_height_m <= ideal_height_m <= max_height_m, got "
                             f"{self.min_height_m}, {self.ideal_height_m}, {self.max_height_m}")
        return self


class IgnitionSpec(StrictModel):
    """Where the fire starts: the driest candidate cells and their blocks."""

    candidate_stride: int = Field(10, ge=1, le=1000, description=(
        "[orig] Candidate cells are every this-many-th cell in each axis (row and col indices 0, s, 2s, ...)."))
    min_village_distance_m: float = Field(300.0, ge=0.0, le=10_000.0, description=(
        "[orig] A candidate cell's centre must be strictly farther than this from the village."))
    block: int = Field(5, ge=1, le=99, description=(
        "[orig] A chosen candidate ignites the trees of the block x block cells centred on it (odd, <= candidate_stride)."))
    min_burning: int = Field(15, ge=0, le=100_000, description=(
        "[orig] Blocks are taken in rank order until strictly more than this many trees burn (params.fire_start "
        "'running'); under 'release' one block burns, the first candidate's if it holds this many trees or more, "
        "else the first holding more."))

    @model_validator(mode="after")
    def _consistent(self) -> "IgnitionSpec":
        if self.block % 2 != 1:
            raise ValueError(f"block ({self.block}) must be odd so it is centred on its candidate cell")
        if self.block > self.candidate_stride:
            raise ValueError(f"block ({self.block}) must be at most candidate_stride ({self.candidate_stride}) "
                             "so the blocks of different candidates never overlap")
        return self


class ForestPreset(StrictModel):
    """generators/forest.yaml: the forest and ignition defaults."""

    hivex: Literal[SCHEMA_VERSION]
    generator: Literal["forest"]
    forest: ForestSpec
    ignition: IgnitionSpec


PRESET_FILE = "forest.yaml"


def load_forest_preset() -> ForestPreset:
    """generators/forest.yaml validated as a :class:`ForestPreset` (located errors)."""
    return load_preset(PRESET_FILE, ForestPreset)


class Neighbours(NamedTuple):
    """Result of a grid neighbourhood query for M query points.

    ``ids`` (M, K) int64: tree ids of every cell in the (2k+1) x (2k+1) block of cells around
    each query (row-major), -1 for empty cells or cells off the grid. ``within`` (M, K) bool:
    true where ``ids`` is a tree no farther than the radius (and, for tree queries, not the tree
    itself). The block is wide enough that no tree within the radius is missed.
    """

    ids: np.ndarray
    within: np.ndarray


@dataclass(frozen=True)
class Forest:
    """Trees placed on a grid; ``N`` trees with ids 0..N-1 in row-major cell order.

    positions (N, 2) float64 metres; heights (N,) float64 terrain height at each tree in metres;
    cell_index (N, 2) int64 (row, col) of each tree's cell; grid (cells, cells) int32 tree id or -1.
    """

    positions: np.ndarray
    heights: np.ndarray
    cell_index: np.ndarray
    grid: np.ndarray
    spec: ForestSpec

    @property
    def count(self) -> int:
        """Number of trees N."""
        return int(self.positions.shape[0])

    def neighbours_within(self, tree_ids: np.ndarray, radius_m: float) -> Neighbours:
        """Other trees within ``radius_m`` metres of each of the trees ``tree_ids`` (M,) int."""
        ids = np.asarray(tree_ids)
        if ids.ndim != 1 or not (np.issubdtype(ids.dtype, np.integer) or ids.size == 0):
            raise ValueError(f"tree_ids must be a 1-D integer array, got shape {ids.shape} dtype {ids.dtype}")
        if ids.size and (ids.min() < 0 or ids.max() >= self.count):
            raise ValueError(f"tree_ids must lie in [0, {self.count}), got range [{ids.min()}, {ids.max()}]")
        ids = ids.astype(np.int64)
        reach = _radius(radius_m) + 2.0 * self.spec.jitter_m  # two trees' offsets from their centres
        found = self._query(self.cell_index[ids], self.positions[ids], radius_m, int(reach // self.spec.spacing_m))
        return Neighbours(found.ids, found.within & (found.ids != ids[:, None]))

    def trees_near(self, points: np.ndarray, radius_m: float) -> Neighbours:
        """Trees within ``radius_m`` metres of each of ``points`` (P, 2) metres (anywhere, even off the grid)."""
        pts = np.asarray(points, dtype=np.float64)
        if pts.ndim != 2 or pts.shape[1] != 2 or not np.all(np.isfinite(pts)):
            raise ValueError(f"points must be a finite (P, 2) array of metres, got shape {pts.shape}")
        s = self.spec
        cells = np.floor((pts[:, ::-1] + s.half_extent_m) / s.spacing_m).astype(np.int64)  # (row, col)
        # a point sits anywhere in its cell, a tree within jitter_m of its centre
        half = int(np.floor((_radius(radius_m) + s.jitter_m) / s.spacing_m + 0.5))
        return self._query(cells, pts, radius_m, half)

    def _query(self, cells: np.ndarray, points: np.ndarray, radius_m: float, half: int) -> Neighbours:
        """Trees in the (2 half + 1)^2 blocks around ``cells`` (M, 2), filtered by distance to ``points`` (M, 2)."""
        ids = block_ids(self.grid, cells, half)
        padded = np.concatenate([self.positions, np.full((1, 2), np.inf)])  # id -1 -> infinitely far
        gap = padded[ids] - points[:, None, :]
        return Neighbours(ids, np.einsum("mkd,mkd->mk", gap, gap) <= radius_m * radius_m)


def _radius(radius_m: float) -> float:
    if not (np.isfinite(radius_m) and radius_m >= 0.0):
        raise ValueError(f"radius_m must be a finite number >= 0, got {radius_m!r}")
    return float(radius_m)


def block_ids(grid: np.ndarray, cells: np.ndarray, half: int) -> np.ndarray:
    """Ids in the (2 half + 1)^2 blocks of ``grid`` (R, C) around ``cells`` (M, 2) (row, col).

    Returns (M, (2 half + 1)^2) int64 in row-major block order, -1 for empty or off-grid cells.
    """
    rows, cols, inside = _block_cells(grid.shape, cells, half)
    return np.where(inside, grid[rows, cols], -1).astype(np.int64)


def _block_cells(shape: tuple[int, int], cells: np.ndarray, half: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Rows and cols (M, (2 half + 1)^2), clipped onto a grid of ``shape``, of the blocks around ``cells``
    (M, 2) in row-major block order, and whether each lies on the grid before clipping."""
    offsets = np.arange(-half, half + 1)
    rows = cells[:, 0, None, None] + offsets[None, :, None]
    cols = cells[:, 1, None, None] + offsets[None, None, :]
    rows, cols = np.broadcast_arrays(rows, cols)
    inside = (rows >= 0) & (rows < shape[0]) & (cols >= 0) & (cols < shape[1])
    side = (2 * half + 1) ** 2
    return (np.clip(rows, 0, shape[0] - 1).reshape(-1, side), np.clip(cols, 0, shape[1] - 1).reshape(-1, side),
            inside.reshape(-1, side))


def cell_centres(spec: ForestSpec) -> np.ndarray:
    """(cells,) float64 metres: centre coordinate of each row (as y) or column (as x)."""
    return -spec.half_extent_m + spec.spacing_m * (np.arange(spec.cells) + 0.5)


def cell_centre_xy(spec: ForestSpec) -> np.ndarray:
    """(cells, cells, 2) float64 metres: the (x, y) centre of every cell ``[row, col]``."""
    centres = cell_centres(spec)
    x, y = np.meshgrid(centres, centres, indexing="xy")
    return np.stack([x, y], axis=-1)


def _village(village_xy: np.ndarray) -> np.ndarray:
    village = np.asarray(village_xy, dtype=np.float64)
    if village.shape != (2,) or not np.all(np.isfinite(village)):
        raise ValueError(f"village_xy must be a finite (2,) point in metres, got {village_xy!r}")
    return village


def _heights(height_at: HeightAt, xy: np.ndarray) -> np.ndarray:
    heights = np.asarray(height_at(xy), dtype=np.float64)
    if heights.shape != (len(xy),) or not np.all(np.isfinite(heights)):
        raise ValueError(f"height_at must map (N, 2) points to N finite heights; for N = {len(xy)} "
                         f"it returned shape {heights.shape}")
    return heights


def place_forest(rng: np.random.Generator, spec: ForestSpec, height_at: HeightAt, village_xy: np.ndarray) -> Forest:
    """Jitter one candidate tree per cell and keep those the height rule and the village allow.

    Draws, in order: jitter (cells, cells, 2) uniform in +/- jitter_m, then one uniform [0, 1)
    per cell. A tree exists where min_height_m <= height <= max_height_m, the draw exceeds
    density_falloff * |ideal_height_m - height|, and it is farther than village_clear_radius_m
    from ``village_xy`` (2,) metres. ``height_at`` maps (cells^2, 2) metres to (cells^2,) metres.
    """
    village = _village(village_xy)
    xy = cell_centre_xy(spec) + rng.uniform(-spec.jitter_m, spec.jitter_m, (spec.cells, spec.cells, 2))
    flat_xy = xy.reshape(-1, 2)
    heights = _heights(height_at, flat_xy)
    draw = rng.random(heights.shape)
    grows = (heights >= spec.min_height_m) & (heights <= spec.max_height_m)
    grows &= draw > spec.density_falloff * np.abs(spec.ideal_height_m - heights)
    grows &= np.hypot(*(flat_xy - village).T) > spec.village_clear_radius_m
    flat = np.flatnonzero(grows)
    grid = np.full(spec.cells * spec.cells, -1, dtype=np.int32)
    grid[flat] = np.arange(len(flat), dtype=np.int32)
    cell_index = np.stack(np.divmod(flat, spec.cells), axis=1).astype(np.int64)
    return Forest(positions=flat_xy[flat], heights=heights[flat], cell_index=cell_index,
                  grid=grid.reshape(spec.cells, spec.cells), spec=spec)


def rank_ignition_cells(forest: Forest, spec: IgnitionSpec, village_xy: np.ndarray, temperature: np.ndarray,
                        humidity: np.ndarray, overcast: np.ndarray) -> np.ndarray:
    """Candidate cells (C, 2) int64 (row, col), best (lowest score) first.

    Candidates are cells with row and col in 0, stride, 2 stride, ... whose centre is strictly
    farther than min_village_distance_m from ``village_xy`` (2,). Score = humidity +
    (1 - temperature) + overcast, read from the (cells, cells) weather arrays at the cell; ties
    keep row-major cell order (lower row, then lower col, first). Raises ValueError if none qualifies.
    """
    return _rank_cells(forest.spec, spec, village_xy, temperature, humidity, overcast)


def _rank_cells(forest_spec: ForestSpec, spec: IgnitionSpec, village_xy: np.ndarray, temperature: np.ndarray,
                humidity: np.ndarray, overcast: np.ndarray) -> np.ndarray:
    n = forest_spec.cells
    weather = {"temperature": temperature, "humidity": humidity, "overcast": overcast}
    for name, field in weather.items():
        if np.shape(field) != (n, n) or not np.all(np.isfinite(field)):
            raise ValueError(f"{name} must be a finite ({n}, {n}) array sampled at cell centres, got shape {np.shape(field)}")
    cells = ignition_candidates(forest_spec, spec, village_xy)
    if len(cells) == 0:
        raise ValueError(f"no ignition candidate: no cell of stride {spec.candidate_stride} lies more than "
                         f"{spec.min_village_distance_m} m from the village at {tuple(np.asarray(village_xy))}")
    r, c = cells[:, 0], cells[:, 1]
    return rank_by_weather(cells, np.asarray(temperature)[r, c], np.asarray(humidity)[r, c], np.asarray(overcast)[r, c])


def ignition_candidates(forest_spec: ForestSpec, spec: IgnitionSpec, village_xy: np.ndarray) -> np.ndarray:
    """(M, 2) int64 (row, col) cells on the candidate stride farther than min_village_distance_m from
    the village, in row-major order; possibly none."""
    picks = np.arange(0, forest_spec.cells, spec.candidate_stride)
    cells = np.stack(np.meshgrid(picks, picks, indexing="ij"), axis=-1).reshape(-1, 2)
    centres = cell_centres(forest_spec)
    offset = np.stack([centres[cells[:, 1]], centres[cells[:, 0]]], axis=1) - _village(village_xy)
    return cells[np.hypot(offset[:, 0], offset[:, 1]) > spec.min_village_distance_m]


def rank_by_weather(cells: np.ndarray, temperature: np.ndarray, humidity: np.ndarray, overcast: np.ndarray
                    ) -> np.ndarray:
    """``cells`` (M, 2) best first by score = humidity + (1 - temperature) + overcast, each (M,) read at
    the cells; ties keep the given order."""
    score = humidity + (1.0 - temperature) + overcast
    return cells[np.argsort(score, kind="stable")]


def select_ignition(forest: Forest, spec: IgnitionSpec, village_xy: np.ndarray, temperature: np.ndarray,
                    humidity: np.ndarray, overcast: np.ndarray) -> np.ndarray:
    """Ids (K,) int64 of the trees set burning, K > min_burning.

    Takes the blocks of the ranked candidates (:func:`rank_ignition_cells`) in order until the
    running tree count exceeds min_burning (a cumulative sum; blocks never overlap). Ids come
    block by block in rank order, row-major within a block. Raises ValueError if every
    candidate block together holds at most min_burning trees.
    """
    ranked = _rank_cells(forest.spec, spec, village_xy, temperature, humidity, overcast)
    half = spec.block // 2
    taken, total = _first_blocks(lambda cells: block_ids(forest.grid, cells, half) >= 0, ranked, spec)
    if total[-1] <= spec.min_burning:
        raise ValueError(f"cannot ignite more than {spec.min_burning} trees: the {len(ranked)} candidate blocks "
                         f"far enough from the village hold only {int(total[-1])} trees")
    ids = block_ids(forest.grid, ranked[:taken], half)
    return ids[ids >= 0]


def ignition_mask(exists: np.ndarray, forest_spec: ForestSpec, spec: IgnitionSpec, village_xy: np.ndarray,
                  temperature: np.ndarray, humidity: np.ndarray, overcast: np.ndarray) -> np.ndarray:
    """(cells, cells) bool: the cells :func:`select_ignition` sets burning, from the tree grid alone.

    For a forest kept between episodes as its ``exists`` (cells, cells) bool grid: the same
    choice as select_ignition on the Forest it came from. Where select_ignition would raise (no
    candidate, or too few trees in all candidate blocks), this lights every tree the candidate
    blocks hold, possibly none: a simulator's world then starts without fire instead of failing at reset.
    """
    try:
        ranked = _rank_cells(forest_spec, spec, village_xy, temperature, humidity, overcast)
    except ValueError:
        ranked = np.zeros((0, 2), np.int64)
    return ranked_ignition_mask(exists, spec, ranked)


def ranked_ignition_mask(exists: np.ndarray, spec: IgnitionSpec, ranked: np.ndarray, rule: str = "running"
                         ) -> np.ndarray:
    """(cells, cells) bool: the trees of ``exists`` in the blocks of the ``ranked`` (M, 2) candidates the ``rule``
    takes. 'running': in order until more than min_burning trees burn (every candidate's if they never do), so
    the fire may start in several places. 'release' (:func:`release_ignition_block`): one block."""
    mask = np.zeros(exists.shape, bool)
    if rule == "release":
        ranked = ranked[exists[ranked[:, 0], ranked[:, 1]]] if len(ranked) else ranked
    if len(ranked) == 0:
        return mask
    half = spec.block // 2

    def trees_in_blocks(cells: np.ndarray) -> np.ndarray:  # (K, block^2) bool
        rows, cols, inside = _block_cells(exists.shape, cells, half)
        return inside & exists[rows, cols]

    if rule == "release":
        chosen = release_ignition_block(np.count_nonzero(trees_in_blocks(ranked), axis=1), spec.min_burning)
        taken = ranked[chosen:chosen + 1]
    else:
        taken = ranked[:_first_blocks(trees_in_blocks, ranked, spec)[0]]
    rows, cols, inside = _block_cells(exists.shape, taken, half)
    burning = inside & exists[rows, cols]
    mask[rows[burning], cols[burning]] = True
    return mask


def release_ignition_block(counts: np.ndarray, min_burning: int) -> int:
    """Which candidate's block the release's InitiateFireEnvProbability sets burning, from the trees ``counts``
    (M >= 1,) of the ranked candidates' blocks (candidates with a tree on their own cell): the first's if it holds
    at least ``min_burning`` trees; else the first in rank order holding more than ``min_burning``; else the
    last's (its loop replaces the list with each candidate's block and stops past ``min_burning``)."""
    if counts[0] >= min_burning:
        return 0
    more = np.flatnonzero(counts > min_burning)
    return int(more[0]) if more.size else len(counts) - 1


def _first_blocks(trees_in_blocks: Callable[[np.ndarray], np.ndarray], ranked: np.ndarray, spec: IgnitionSpec
                  ) -> tuple[int, np.ndarray]:
    """How many of the ``ranked`` (M >= 1, 2) candidates to take: the first whose blocks' running tree count
    exceeds min_burning (all M if none does), and the running counts of the blocks looked at.

    ``trees_in_blocks(cells)`` (K, block^2) bool marks the trees of the blocks around ``cells`` (K, 2). It is
    asked for a growing prefix of the candidates, since the first few blocks nearly always suffice.
    """
    looked = min(len(ranked), 16)
    while True:
        total = np.cumsum(np.count_nonzero(trees_in_blocks(ranked[:looked]), axis=1))
        if total[-1] > spec.min_burning or looked == len(ranked):
            return min(int(np.searchsorted(total, spec.min_burning, side="right")) + 1, looked), total
        looked = min(len(ranked), looked * 4)
