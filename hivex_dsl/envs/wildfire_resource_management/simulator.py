"""Wildfire Resource Management as a batched NumPy simulator (no Python loop over worlds or towers in step).

The island, forest, weather, wind and fire are those of Aerial Wildfire Suppression (hivex_dsl.envs.island
and hivex_dsl.sim.fire); nine watchtowers watch the fire burn and shift resources between each other. Trees
change only on fire steps (nothing douses them), so the towers' sighting is recomputed only then, and
only this step's ignitions need searching (see .sight). The weather factors of spread are counted once
per weather refresh on the coarse weather grid (hivex_dsl.sim.fire.FactorGrid).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
from gymnasium import spaces

from ...base.numeric import clamp
from ...runtime.batched import StepOutcome
from ...sim.batching import assemble, read_only, replace_worlds
from ...sim.fire import FactorGrid, count_factors, fire_step_unchecked, grid_cell_table
from ...sim.procgen.weather import weather_step
from ...sim.procgen.wind import wind_step
from ..island import (IslandMaps, IslandSpecs, fire_wind, grid_lookup, restart_where, sample_points, start_islands,
                      weather_grid_points)
from .global_state import state_components, world_state
from .params import WildfireResourceParams
from .resources import (MAX_SUPPORT_TENTHS, TARGETS_PER_AGENT, TENTHS, TOWERS, apply_actions, grid_offsets,
                        initial_resources, total_support)
from .sight import age_cohorts, key_cells, key_tables, nearest_by_age, nearest_keys, square_table
from .terms import performance_of
from .types import Sighting, WildfireResourceState

FRAME = 8  # values of one observation stack
STACKS = 2
EVENTS = {"fire_out": "the fire on the whole island went out (every tower of the world)"}
# Per-world arrays of the state (world axis first) that a partial reset replaces.
_PER_WORLD = ("fire_factors", "tower_ground", "tower_weather", "allocation", "budget", "support", "impossible",
              "impossible_total", "frame", "fire_went_out")


class WildfireResourceSimulator:
    """B worlds of one compiled Wildfire Resource Management scenario."""

    observation_labels = ("closest fire x", "closest fire y", "closest fire z", "temperature", "humidity",
                          "overcast", "total support", "fire detected")
    observation_stacks = STACKS
    stacked_fields = ("frame",)  # shifted every physics step; the runtime stacks them per decision
    action_meanings = ("one branch per target (self, neighbour 1, neighbour 2, neighbour 3): "
                       "0 do nothing, 1 add 0.1 from the budget, 2 subtract 0.1 back to the budget")
    render_fps = 30

    def __init__(self, compiled):
        p: WildfireResourceParams = compiled.params
        if compiled.agents != TOWERS:
            raise ValueError(f"Wildfire Resource Management has exactly {TOWERS} towers, got {compiled.agents} agents")
        self.params = p
        self.agents = compiled.agents
        if p.eighth_observation == "budget":
            self.observation_labels = (*type(self).observation_labels[:-1], "unallocated budget")
        self.island = IslandSpecs.of(compiled)
        self.forest_spec, self.weather_spec, self.wind_spec = self.island.forest, self.island.weather, self.island.wind
        self.observation_space = spaces.Box(-1.0, 1.0, (FRAME * STACKS,), np.float32)
        self.action_space = spaces.MultiDiscrete([3] * TARGETS_PER_AGENT)
        self.cell_m = self.forest_spec.spacing_m
        half, cells = p.island_half_extent_m, self.forest_spec.cells
        self.towers = grid_offsets() * p.tower_spacing_m  # (9, 2) metres
        self.tower_rows = (self.towers[:, 1] + half) / self.cell_m - 0.5  # fractional forest-cell coordinates
        self.tower_cols = (self.towers[:, 0] + half) / self.cell_m - 0.5
        box = p.detection_radius_m / self.cell_m  # half side of a tower's search square, in cells
        self.search_keys = key_tables(square_table(self.tower_rows, box, cells),
                                      square_table(self.tower_cols, box, cells))
        # (C * C + 1, 3) metres (x, y, 0) of every cell centre, then an infinitely far sentinel for cell -1, and
        # (A, 3) (x, y, 0) of the towers: offsets in one gather and one subtraction, as fire.cell_xy computes them
        centre = (np.arange(cells) + 0.5) * self.cell_m - half  # of a column (x) or a row (y)
        centres = np.stack(np.broadcast_arrays(centre, centre[:, None], 0.0), axis=-1).reshape(-1, 3)
        self.cell_xy0 = np.concatenate([centres, [[np.inf, np.inf, 0.0]]])
        self.tower_xy0 = np.concatenate([self.towers, np.zeros((TOWERS, 1))], axis=1).astype(np.float64)
        self.tower_cells = np.clip(np.floor((self.towers + half) / self.cell_m).astype(np.int64), 0, cells - 1)
        self.weather_cells = grid_cell_table(grid_lookup(cells, p.weather_grid_cells), p.weather_grid_cells)
        self._first_cell_cache: dict[int, np.ndarray] = {}
        self._nothing_cache: dict[int, tuple[np.ndarray, np.ndarray]] = {}
        self._last_grid: FactorGrid | None = None
        self.all_towers = np.ones((1, self.agents), bool)
        # the weather grid's centres, then the towers: every point the weather is sampled at on a refresh
        self.weather_points = np.concatenate([weather_grid_points(half, p.weather_grid_cells), self.towers])

    # ---- reset -------------------------------------------------------------------------

    def reset(self, rng: np.random.Generator, batch: int) -> WildfireResourceState:
        return self._fresh(rng, batch, None)

    def _fresh(self, rng: np.random.Generator, batch: int, maps: IslandMaps | None) -> WildfireResourceState:
        """``batch`` new episodes: on new islands, or on the given ``maps`` (kept islands) when not None."""
        p = self.params
        island = start_islands(rng, batch, self.island, maps, probes=self.towers)
        maps, fire, wind, weather, conditions = island.maps, island.fire, island.wind, island.weather, island.conditions
        tower_ground = maps.height[:, self.tower_cells[:, 1], self.tower_cells[:, 0]]
        tower_weather = island.probe_weather
        sighting = self._sight(fire, maps.height, tower_ground, None)
        allocation, budget = initial_resources(batch, self.agents, p.initial_self_tenths)
        support = total_support(allocation)
        zeros = np.zeros((batch, self.agents), np.int16)
        frame = self._frame(sighting, tower_weather, support, budget,
                            np.zeros((batch, self.agents, FRAME * STACKS), np.float32))
        return WildfireResourceState(
            maps=maps, fire=fire, wind=wind, weather=weather, conditions=conditions,
            fire_factors=count_factors(conditions, p), tick=0,
            tower_ground=tower_ground, tower_weather=tower_weather, sighting=sighting, allocation=allocation,
            budget=budget, support=support, impossible=zeros, impossible_total=zeros.astype(np.int32), frame=frame,
            fire_went_out=np.zeros(batch, bool))

    def reset_where(self, state: WildfireResourceState, mask: np.ndarray, rng: np.random.Generator
                    ) -> WildfireResourceState:
        """New episodes in the worlds where ``mask`` (B,) is true; they keep their islands unless
        params.redraw_island is "episode"."""
        if not mask.any():
            return state
        fresh, changes = restart_where(state, mask, rng, self.params.redraw_island, self._fresh, _PER_WORLD)
        return replace(state, sighting=replace_worlds(state.sighting, mask, fresh.sighting), **changes)

    # ---- step --------------------------------------------------------------------------

    def step(self, state: WildfireResourceState, actions: np.ndarray, rng: np.random.Generator):
        """actions (B, A, 4) in {0, 1, 2}: shift resources, then move the wind, weather and fire."""
        p = self.params
        held_back = TENTHS - p.allocatable_tenths  # tenths of the budget no add can take (see the param)
        allocation, free, impossible = apply_actions(state.allocation, state.budget - held_back, np.asarray(actions))
        budget = free + held_back
        support = total_support(allocation)
        wind = wind_step(state.wind, rng, self.wind_spec)
        weather = weather_step(state.weather, wind.main, self.weather_spec)
        tick = state.tick + 1
        conditions, factors, tower_weather = state.conditions, state.fire_factors, state.tower_weather
        if tick % p.weather_refresh_interval == 0:
            conditions, tower_weather = self._sample_weather(weather)
            factors = count_factors(conditions, p)
        fire, sighting, was_out = state.fire, state.sighting, state.fire.out
        if tick % p.fire_step_interval == 0:
            winds = fire_wind(p, wind, self.wind_spec, p.island_half_extent_m, self.cell_m)
            fire = fire_step_unchecked(fire, rng, p, winds, state.maps.height, self._factor_grid(factors), self.cell_m)
            sighting = self._sight(fire, state.maps.height, state.tower_ground, state.sighting)
        if fire.out is was_out:  # no world's fire changed state (the one-world fire step keeps the array)
            went_out, every_tower = self._nothing(len(budget))
        else:
            went_out = fire.out & ~was_out
            every_tower = went_out[:, None] & self.all_towers  # (B, A): the event concerns every tower of the world
        new = assemble(WildfireResourceState,
            maps=state.maps, fire=fire, wind=wind, weather=weather, conditions=conditions, fire_factors=factors,
            tick=tick, tower_ground=state.tower_ground, tower_weather=tower_weather, sighting=sighting,
            allocation=allocation, budget=budget, support=support, impossible=impossible,
            impossible_total=state.impossible_total + impossible,
            frame=self._frame(sighting, tower_weather, support, budget, state.frame), fire_went_out=went_out)
        return new, StepOutcome(terminated=self._nothing(len(budget))[1], events={"fire_out": every_tower})

    def step_info(self, state: WildfireResourceState) -> dict[str, np.ndarray]:
        """(B, A) counts of impossible adds or subtracts (no-ops): this step and so far this episode."""
        return {"impossible_actions": state.impossible, "impossible_actions_episode": state.impossible_total}

    def _factor_grid(self, factors: np.ndarray) -> FactorGrid:
        """The FactorGrid of the weather factors (B, G * G): rebuilt only for a new array (a refresh or a
        reset makes one); it holds the array itself, so it can never read other counts than ``factors``."""
        if self._last_grid is None or self._last_grid.counts is not factors:
            self._last_grid = FactorGrid(factors, self.weather_cells)
        return self._last_grid

    def _tower_weather(self, weather) -> np.ndarray:
        """(B, A, 3) float32 temperature, humidity, overcast at the towers."""
        return sample_points(weather, self.weather_spec, self.towers)

    def _sample_weather(self, weather) -> tuple[np.ndarray, np.ndarray]:
        """(conditions (B, G, G, 3), tower weather (B, A, 3)) float32, as island.sample_conditions and
        _tower_weather give them, from one weather evaluation (the fields are sampled point by point)."""
        batch, grid = weather.offsets.shape[0], self.params.weather_grid_cells
        fields = sample_points(weather, self.weather_spec, self.weather_points)
        return fields[:, :grid * grid].reshape(batch, grid, grid, 3), fields[:, grid * grid:]

    def _sight(self, fire, height: np.ndarray, tower_ground: np.ndarray, before: Sighting | None) -> Sighting:
        """Each tower's horizontally closest burning tree within the detection radius, its 3-D offset and
        distance, whether that distance shrank since ``before`` (the previous fire step; None at reset,
        when every cohort of the burning list is searched; else only this step's ignitions are, see .sight),
        and the towers' performance P."""
        batch, cells = fire.trees.shape[:2]
        if before is None or before.cohorts is None:  # a reset (or a hand-made sighting): search all
            cohorts = nearest_by_age(fire.burning, fire.age, self.params.burn_steps, batch, cells, *self.search_keys)
        else:
            count = int(fire.ignited[0]) if batch == 1 else int(np.add.reduce(fire.ignited))
            ignitions = fire.burning[len(fire.burning) - count:]  # they end the list
            cohorts = age_cohorts(before.cohorts, nearest_keys(ignitions, batch, cells, *self.search_keys))
        cell = key_cells(np.minimum.reduce(cohorts, axis=-1))
        # cell -1 (none) reads the sentinel row of cell_xy0, infinitely far; the ground under it is any cell's
        offset = self.cell_xy0.take(cell, axis=0)
        offset -= self.tower_xy0
        ground = height.take(cell if batch == 1 else self._first_cells(batch, cells) + cell)  # flat indices
        np.subtract(ground, tower_ground, out=offset[..., 2])
        seen = np.hypot(offset[..., 0], offset[..., 1]) <= self.params.detection_radius_m
        np.copyto(offset, 0.0, where=~seen[..., None])
        distance = np.where(seen, np.sqrt(np.add.reduce(offset * offset, axis=-1)), np.inf)
        # an unseen distance is inf, never below the last one
        approaching = np.zeros_like(seen) if before is None else distance < before.distance
        return assemble(Sighting, cell=cell, cells=cells, offset=offset, distance=distance, approaching=approaching,
                        cohorts=cohorts, performance=performance_of(distance, approaching, seen, self.params))

    def _nothing(self, batch: int) -> tuple[np.ndarray, np.ndarray]:
        """Read-only all-false (B,) and (B, A) bool arrays (constants per batch size): no world, no tower."""
        nothing = self._nothing_cache.get(batch)
        if nothing is None:
            nothing = self._nothing_cache[batch] = (np.zeros(batch, bool), np.zeros((batch, self.agents), bool))
            for array in nothing:
                array.flags.writeable = False
        return nothing

    def _first_cells(self, batch: int, cells: int) -> np.ndarray:
        """(B, 1) int64 flat index of the first cell of each world (a constant per batch size)."""
        first = self._first_cell_cache.get(batch)
        if first is None:
            first = self._first_cell_cache[batch] = np.arange(batch)[:, None] * (cells * cells)
            first.flags.writeable = False
        return first

    # ---- observation and picture --------------------------------------------------------

    def _frame(self, sighting: Sighting, tower_weather: np.ndarray, support: np.ndarray, budget: np.ndarray,
               previous: np.ndarray) -> np.ndarray:
        """(B, A, 16) float32: this step's frame, then the previous step's first frame."""
        # minimum(maximum()), not np.clip: the same values (no NaN here) without np.clip's Python overhead;
        # one concatenate casts every part to float32 as assigning it into a float32 frame would
        direction = clamp(sighting.offset / self.params.detection_radius_m, -1.0, 1.0)
        eighth = np.isfinite(sighting.distance) if self.params.eighth_observation == "fire_detected" else budget / TENTHS
        return np.concatenate([direction, tower_weather, support[..., None] / MAX_SUPPORT_TENTHS,
                               eighth[..., None], previous[..., :FRAME]], axis=-1, dtype=np.float32)

    def observe(self, state: WildfireResourceState) -> np.ndarray:
        """(B, A, 16) float32 built in ``step``: 2 stacks (newest first) of the 8 labelled values (read-only: the state keeps it)."""
        return read_only(state.frame)

    state_components = state_components  # the global state's world facts: see global_state.py
    world_state = world_state

    def render(self, state: WildfireResourceState, index: int) -> np.ndarray:
        from .render import draw_towers

        return draw_towers(state, index, self.params, self.towers)
