"""The wildfire island shared by Aerial Wildfire Suppression and Wildfire Resource Management.

One island per world at reset: terrain, village, forest, ignition and the ground palette, plus
the generator slots both environments declare. The generators are per world (a Python loop over
the worlds being reset, never in ``step``); everything they produce is resampled onto the forest
grid so the simulators work on arrays.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any, Callable, Literal

import numpy as np
from pydantic import Field

from ..compiler.registry import GeneratorSlot
from ..runtime.global_state import StateComponent
from ..sim.batching import pad_by_world, put_worlds, replace_worlds, select_worlds
from ..sim.fire import FireState, TreeState, fire_put_worlds, fire_reset
from ..sim.fire.summary import burning_share
from ..sim.procgen.forest import (ForestSpec, IgnitionSpec, cell_centre_xy, ignition_candidates, load_forest_preset,
                                  place_forest, rank_by_weather, ranked_ignition_mask)
from ..sim.procgen.terrain import TerrainSpec, generate_terrain, terrain_spec_for_level
from ..sim.procgen.weather import WeatherSpec, WeatherState, load_weather_preset, weather_fields
from ..sim.procgen.weather import weather_reset
from ..sim.procgen.wind import WindSpec, WindState, wind_reader, wind_reset


# The wind and fire facts of an island world's global state (hivex_dsl.runtime.global_state), first in both
# environments' world facts; fire_summary (hivex_dsl.sim.fire.summary) computes the fire's five.
ISLAND_STATE_COMPONENTS = (
    StateComponent("main wind", 2, -1.0, 1.0, "Direction the main wind blows to (cos, sin); fire spreads "
                   "downwind."),
    StateComponent("fire burning", 1, 0.0, 1.0, "Burning trees n on the C x C forest grid, log(1 + n) / "
                   "log(1 + C^2)."),
    StateComponent("fire front centre", 2, -1.0, 1.0, "Mean (x, y) of the burning trees / island half extent "
                   "(0 without fire)."),
    StateComponent("fire front spread", 1, 0.0, 1.0, "Root-mean-square distance of the burning trees from "
                   "their centre / (sqrt(2) x island half extent)."),
    StateComponent("fire out", 1, 0.0, 1.0, "1 once the island's fire is out, else 0."),
)

# Ground palette indices (uint8); tree states are drawn over them (see palette.py).
LAND_SHADES = 32
SEA = LAND_SHADES
VILLAGE = SEA + 1
SHADE_TOP_M = 220.0  # heights at or above this get the lightest land shade

FOREST_PRESET = load_forest_preset()
WEATHER_PRESET = load_weather_preset()

RedrawIsland = Literal["seed", "episode"]


def redraw_island_field() -> Any:
    """The ``redraw_island`` param of the island environments (AWS, WRM): one default, one meaning."""
    return Field("episode", description=(
        "[orig] When a world draws a new island (terrain, village, forest): 'episode' (the default) for every "
        "episode, each drawn from the split's seed stream, as the original's Aerial Wildfire Suppression release "
        "does (a new terrain seed and village spot from Unity's generator for every new world, which runs on from "
        "the run's one seed: the reward table's note 'New worlds in the release'; Wildfire Resource Management's "
        "build is not public and follows by analogy); 'seed' only when a seed starts a stream (the first reset, "
        "reset(seed=...), every episode of a per-episode seed list), keeping it for the episodes that continue the "
        "stream in either adapter (faster: an island costs about 60 ms to draw, a new fire on a kept one a few ms), "
        "an approximation the original did not make. Fire, weather and wind are new every episode either way."))


ISLAND_GENERATORS = {
    "terrain": GeneratorSlot(TerrainSpec, lambda level: terrain_spec_for_level(level),
                             "the island's height map (the level sets the height multiplier)"),
    "forest": GeneratorSlot(ForestSpec, lambda level: FOREST_PRESET.forest, "where trees grow on the island"),
    "ignition": GeneratorSlot(IgnitionSpec, lambda level: FOREST_PRESET.ignition, "where the fire starts"),
    "weather": GeneratorSlot(WeatherSpec, lambda level: WEATHER_PRESET.defaults,
                             "temperature, humidity and overcast fields drifting with the wind"),
}


def island_problems(compiled, island_half_extent_m: float) -> list[tuple[tuple, str]]:
    """The forest grid must be the island and lie inside the terrain map (compile-time check)."""
    forest, terrain = compiled.generators["forest"], compiled.generators["terrain"]
    problems = []
    if forest.half_extent_m != island_half_extent_m:
        problems.append((("generators", "forest", "half_extent_m"),
                         f"{forest.half_extent_m:g} m must equal the island's half extent "
                         f"({island_half_extent_m:g} m): the forest grid covers the island"))
    if terrain.extent_m / 2.0 < forest.half_extent_m:
        problems.append((("generators", "terrain", "extent_m"), f"{terrain.extent_m:g} m does not cover the forest "
                         f"(+/-{forest.half_extent_m:g} m)"))
    return problems + ignition_problems(compiled)


def ignition_problems(compiled) -> list[tuple[tuple, str]]:
    """Ignition settings under which no world could ever start a fire as specified."""
    forest, ignition, terrain = (compiled.generators[k] for k in ("forest", "ignition", "terrain"))
    problems = []
    # the farthest a candidate cell can be from the village: opposite corners of the village range and the grid
    farthest = np.sqrt(2.0) * (forest.half_extent_m + min(terrain.village_half_range_m, forest.half_extent_m))
    if ignition.min_village_distance_m >= farthest:
        problems.append((("generators", "ignition", "min_village_distance_m"),
                         f"{ignition.min_village_distance_m:g} m leaves no candidate cell: no cell of the forest lies "
                         f"farther than {farthest:.0f} m from any village position"))
    candidates = len(range(0, forest.cells, ignition.candidate_stride)) ** 2
    if ignition.min_burning >= candidates * ignition.block ** 2:
        problems.append((("generators", "ignition", "min_burning"),
                         f"{ignition.min_burning} trees can never burn at the start: {candidates} candidate blocks of "
                         f"{ignition.block}x{ignition.block} cells hold at most {candidates * ignition.block ** 2}"))
    return problems


@dataclass(frozen=True)
class Island:
    """One world's maps: height (C, C) float32, ground (C, C) uint8, village (2,), exists (C, C) bool, ignite (C, C) bool."""

    height: np.ndarray
    ground: np.ndarray
    village: np.ndarray
    exists: np.ndarray
    ignite: np.ndarray


@dataclass(frozen=True)
class IslandMaps:
    """What a world's generators drew, on the forest grid (C x C cells, row = y, col = x).

    height: (B, C, C) float32 terrain height at cell centres (uphill spread).
    ground: (B, C, C) uint8 palette index of the ground without trees (camera and render).
    village: (B, 2) float64 village centre in metres.
    exists: (B, C, C) bool where a tree grows at the start of an episode.
    terrain: (B, n, n) float32 the terrain generator's whole height map (its ``size`` nodes over ``extent_m``,
        :func:`hivex_dsl.sim.grids.terrain_grid`), which runs on under the water ring past the forest grid.
    """

    height: np.ndarray
    ground: np.ndarray
    village: np.ndarray
    exists: np.ndarray
    terrain: np.ndarray


@dataclass(frozen=True)
class IslandStart:
    """The island part of new episodes: maps, fire, wind, weather and the weather grid (B, G, G, 3), and the
    weather (B, N, 3) float32 at the N probe points :func:`start_islands` was asked for (None without)."""

    maps: IslandMaps
    fire: FireState
    wind: WindState
    weather: WeatherState
    conditions: np.ndarray
    probe_weather: np.ndarray | None = None


@dataclass(frozen=True)
class IslandSpecs:
    """The generator specs of one compiled scenario and the island's size."""

    terrain: TerrainSpec
    forest: ForestSpec
    ignition: IgnitionSpec
    weather: WeatherSpec
    wind: WindSpec
    half_extent_m: float
    weather_cells: int
    fire_start: str = "running"

    @classmethod
    def of(cls, compiled) -> "IslandSpecs":
        gens, p = compiled.generators, compiled.params
        return cls(gens["terrain"], gens["forest"], gens["ignition"], gens["weather"], p.wind_spec(),
                   p.island_half_extent_m, p.weather_grid_cells, p.fire_start)


def draw_maps(rng: np.random.Generator, count: int, specs: IslandSpecs) -> IslandMaps:
    """``count`` new islands (the generators run once per world: resets only)."""
    cells, nodes = specs.forest.cells, specs.terrain.size
    drawn = [draw_island(rng, specs.terrain, specs.forest) for _ in range(count)]
    if not drawn:
        return IslandMaps(np.zeros((0, cells, cells), np.float32), np.zeros((0, cells, cells), np.uint8),
                          np.zeros((0, 2)), np.zeros((0, cells, cells), bool), np.zeros((0, nodes, nodes), np.float32))
    return IslandMaps(*(np.stack(part) for part in zip(*drawn)))


def start_islands(rng: np.random.Generator, count: int, specs: IslandSpecs, maps: IslandMaps | None,
                  probes: np.ndarray | None = None) -> IslandStart:
    """New episodes for ``count`` worlds: wind, weather, then new islands (or the kept ``maps``), then the fire.

    ``probes`` (N, 2) metres: points whose weather is sampled with the weather grid's (one evaluation).
    """
    wind = wind_reset(rng, count, specs.wind)
    weather = weather_reset(rng, count, specs.weather)
    grid = weather_grid_points(specs.half_extent_m, specs.weather_cells)
    fields = sample_points(weather, specs.weather, grid if probes is None else np.concatenate([grid, probes]))
    conditions = fields[:, :len(grid)].reshape(count, specs.weather_cells, specs.weather_cells, 3)
    maps = draw_maps(rng, count, specs) if maps is None else maps
    ignite = ignite_worlds(maps.exists, maps.village, conditions, specs.forest, specs.ignition, specs.fire_start)
    return IslandStart(maps, fire_reset(maps.exists, ignite), wind, weather, conditions,
                       None if probes is None else fields[:, len(grid):])


def kept_maps(maps: IslandMaps, mask: np.ndarray, redraw: str) -> IslandMaps | None:
    """The islands of the masked worlds when they are kept for a new episode (redraw_island 'seed'), else None."""
    if redraw == "episode":
        return None
    return select_worlds(maps, mask)


def restart_islands(state: Any, mask: np.ndarray, fresh: Any, kept: IslandMaps | None) -> dict[str, Any]:
    """maps, fire, wind, weather (and conditions, if it keeps them) of ``state`` with the masked worlds from ``fresh``.

    The fire's tree grid is updated in place (see hivex_dsl.sim.fire), so ``state`` is used up.
    """
    fire = fire_put_worlds(state.fire, mask, fresh.fire)
    weather = replace(state.weather, offsets=put_worlds(state.weather.offsets, mask, fresh.weather.offsets),
                      perm=put_worlds(state.weather.perm, mask, fresh.weather.perm, axis=1),
                      grads=put_worlds(state.weather.grads, mask, fresh.weather.grads, axis=1))
    changes = {"maps": state.maps if kept is not None else replace_worlds(state.maps, mask, fresh.maps),
               "fire": fire, "wind": replace_worlds(state.wind, mask, fresh.wind), "weather": weather}
    if hasattr(state, "conditions"):  # simulators that keep the weather grid between fire steps
        changes["conditions"] = put_worlds(state.conditions, mask, fresh.conditions)
    return changes


def restart_where(state: Any, mask: np.ndarray, rng: np.random.Generator, redraw: str,
                  fresh_episodes: Callable[[np.random.Generator, int, IslandMaps | None], Any],
                  per_world: tuple[str, ...]) -> tuple[Any, dict[str, Any]]:
    """New episodes in the worlds where ``mask`` (B,) is true, for a simulator whose state has the
    island fields (maps, fire, wind, weather, and perhaps conditions) and the world-first arrays ``per_world``.

    ``fresh_episodes(rng, count, kept_maps_or_None)`` builds the new worlds' state. Returns that
    fresh state and the field values for ``dataclasses.replace(state, **changes)``.
    """
    kept = kept_maps(state.maps, mask, redraw)
    fresh = fresh_episodes(rng, int(np.count_nonzero(mask)), kept)
    changes = restart_islands(state, mask, fresh, kept)
    changes.update({name: put_worlds(getattr(state, name), mask, getattr(fresh, name)) for name in per_world})
    return fresh, changes


def conditions_reader(conditions: np.ndarray, lookup: np.ndarray) -> Callable:
    """The fire engine's weather callback: the nearest weather-grid cell of each forest cell."""

    def read(world: np.ndarray, rows: np.ndarray, cols: np.ndarray):
        values = conditions[world, lookup[rows], lookup[cols]]
        return values[:, 0], values[:, 1], values[:, 2]

    return read


def weather_reader(weather: WeatherState, spec: WeatherSpec, half_extent_m: float, cells: int,
                   lookup: np.ndarray) -> Callable:
    """The fire engine's weather callback, sampling the weather grid only at the cells it asks for.

    Reads what ``conditions_reader(sample_conditions(weather, ...), lookup)`` reads: a point's weather
    does not depend on the other points sampled with it. A fire step asks for the cells holding
    burning trees, a few dozen of the G x G per world, so this is several times less work.
    """

    def read(world: np.ndarray, rows: np.ndarray, cols: np.ndarray):
        if world.size == 0:
            return (np.zeros(0, np.float32),) * 3
        batch, area = weather.offsets.shape[0], cells * cells
        key = world * area + lookup[rows] * cells + lookup[cols]
        asked = np.zeros(batch * area, bool)
        asked[key] = True
        wanted = np.flatnonzero(asked)  # (K,) distinct world * area + cell, ascending
        owner, cell = np.divmod(wanted, area)
        slot, width = pad_by_world(owner, batch)
        centres = weather_grid_points(half_extent_m, cells)
        points = np.broadcast_to(centres[0], (batch, width, 2)).copy()  # unused slots: any point
        points[owner, slot] = centres[cell]
        values = weather_fields(weather, points, spec)[:, owner, slot].astype(np.float32)  # (3, K)
        at = (np.cumsum(asked) - 1)[key]  # position of each query's cell among the wanted ones
        values = values[:, at]
        return values[0], values[1], values[2]

    return read


def fire_wind(params: Any, wind: WindState, spec: WindSpec, half_extent_m: float, cell_m: float) -> Any:
    """What the fire engine reads as the wind under ``params.spread_wind``: the main wind (B,) radians, or
    ('local') a reader of the local wind at the burning trees (hivex_dsl.sim.fire.Winds)."""
    if params.spread_wind == "local":
        return wind_reader(wind, spec, half_extent_m, cell_m)
    return wind.main


def weather_grid_points(half_extent_m: float, cells: int) -> np.ndarray:
    """(cells * cells, 2) centres of the weather grid over the island, row-major (row = y)."""
    centres = -half_extent_m + (np.arange(cells) + 0.5) * (2.0 * half_extent_m / cells)
    x, y = np.meshgrid(centres, centres)
    return np.stack([x.ravel(), y.ravel()], axis=-1)


def sample_conditions(weather: WeatherState, spec: WeatherSpec, half_extent_m: float, cells: int) -> np.ndarray:
    """(B, G, G, 3) float32 temperature, humidity, overcast at the weather grid centres of every world."""
    return sample_points(weather, spec, weather_grid_points(half_extent_m, cells)).reshape(-1, cells, cells, 3)


def sample_points(weather: WeatherState, spec: WeatherSpec, points: np.ndarray) -> np.ndarray:
    """(B, N, 3) float32 temperature, humidity, overcast at the same finite ``points`` (N, 2) metres of every world."""
    batch = weather.offsets.shape[0]
    fields = weather_fields(weather, np.broadcast_to(points, (batch,) + points.shape), spec)  # (3, B, N) float64
    return fields.transpose(1, 2, 0).astype(np.float32, order="C")


def grid_lookup(cells_of_forest: int, weather_cells: int) -> np.ndarray:
    """(C,) index of the weather grid cell holding each forest row (or column)."""
    return (np.arange(cells_of_forest) * weather_cells) // cells_of_forest


def build_island(rng: np.random.Generator, terrain_spec: TerrainSpec, forest_spec: ForestSpec,
                 ignition_spec: IgnitionSpec, conditions: np.ndarray, fire_start: str = "running") -> Island:
    """Draw one world. ``conditions`` (G, G, 3) is the world's weather grid (ignition prefers dry, hot cells)."""
    height, ground, village, exists, _ = draw_island(rng, terrain_spec, forest_spec)
    ignite = ignition_of(exists, village, conditions, forest_spec, ignition_spec, fire_start)
    return Island(height=height, ground=ground, village=village, exists=exists, ignite=ignite)


def draw_island(rng: np.random.Generator, terrain_spec: TerrainSpec, forest_spec: ForestSpec
                ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The lasting part of a world: height (C, C) float32, ground (C, C) uint8, village (2,), trees (C, C) bool and
    the whole terrain (n, n) float32."""
    terrain = generate_terrain(rng, terrain_spec)
    centres = cell_centre_xy(forest_spec).reshape(-1, 2)
    cells = forest_spec.cells
    height = terrain.height_at(centres).reshape(cells, cells)
    forest = place_forest(rng, forest_spec, terrain.height_at, terrain.village)
    ground = ground_palette(height, centres.reshape(cells, cells, 2), terrain.village, terrain_spec)
    return (height.astype(np.float32), ground, np.asarray(terrain.village, float), forest.grid >= 0,
            terrain.heights.astype(np.float32))


def ignition_of(exists: np.ndarray, village: np.ndarray, conditions: np.ndarray, forest_spec: ForestSpec,
                ignition_spec: IgnitionSpec, fire_start: str = "running") -> np.ndarray:
    """(C, C) bool cells set burning on a forest ``exists`` (C, C) under the weather grid ``conditions`` (G, G, 3),
    by the params' ``fire_start`` rule (:func:`~hivex_dsl.sim.procgen.forest.ranked_ignition_mask`).

    :func:`~hivex_dsl.sim.procgen.forest.ignition_mask` with each forest cell's weather read from the weather
    cell holding it (the grid is not upsampled to the forest's: only the candidate cells are read).
    """
    cells = ignition_candidates(forest_spec, ignition_spec, village)
    lookup = grid_lookup(forest_spec.cells, conditions.shape[0])
    weather = conditions[lookup[cells[:, 0]], lookup[cells[:, 1]]]  # (M, 3)
    ranked = rank_by_weather(cells, weather[:, 0], weather[:, 1], weather[:, 2])
    return ranked_ignition_mask(exists, ignition_spec, ranked, fire_start)


def ignite_worlds(exists: np.ndarray, village: np.ndarray, conditions: np.ndarray, forest_spec: ForestSpec,
                  ignition_spec: IgnitionSpec, fire_start: str = "running") -> np.ndarray:
    """(M, C, C) bool ignition of M kept islands (exists (M, C, C), village (M, 2), conditions (M, G, G, 3))."""
    if len(exists) == 0:
        return np.zeros_like(exists)
    return np.stack([ignition_of(e, v, c, forest_spec, ignition_spec, fire_start)
                     for e, v, c in zip(exists, village, conditions)])


def ground_palette(height: np.ndarray, centres: np.ndarray, village: np.ndarray, spec: TerrainSpec) -> np.ndarray:
    """(C, C) uint8: land shade by height, SEA at or below sea level, VILLAGE on the flattened village site."""
    shade = np.clip(height / SHADE_TOP_M * (LAND_SHADES - 1), 0, LAND_SHADES - 1).astype(np.uint8)
    ground = np.where(height <= spec.sea_level_m, np.uint8(SEA), shade)
    offset = centres - village
    on_village = np.einsum("rcd,rcd->rc", offset, offset) <= spec.village_flat_radius_m ** 2
    return np.where(on_village, np.uint8(VILLAGE), ground).astype(np.uint8)


def stack_islands(islands: list[Island]) -> dict[str, np.ndarray]:
    """The islands' arrays stacked on a leading world axis (empty list -> zero worlds)."""
    names = ("height", "ground", "village", "exists", "ignite")
    return {name: np.stack([getattr(i, name) for i in islands]) for name in names}


def burning_cells_xy(state: Any, half: float) -> tuple[np.ndarray, np.ndarray]:
    """(x, y) metres of the centres of world 0's burning cells, read off the tree grid cell by cell."""
    trees = state.fire.trees[0]
    rows, cols = np.nonzero(trees == TreeState.BURNING)
    spacing = 2.0 * half / trees.shape[0]
    return (cols + 0.5) * spacing - half, (rows + 0.5) * spacing - half


def island_fire_facts(state: Any, half: float) -> dict[str, list[float]]:
    """World 0's fire facts of the global state, counted off the tree grid (the tests' check of fire_summary)."""
    x, y = burning_cells_xy(state, half)
    cells = state.fire.trees.shape[1]
    return {"fire burning": [float(burning_share(len(x), cells))],
            "fire front centre": [float(x.mean() / half), float(y.mean() / half)] if len(x) else [0.0, 0.0]}
