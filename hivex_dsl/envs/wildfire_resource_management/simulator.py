"""Wildfire Resource Management as a batched NumPy simulator (no Python loop over worlds or towers in step).

The island, forest, weather, wind and fire are those of Aerial Wildfire Suppression (hivex_dsl.envs.island
and hivex_dsl.fire); nine watchtowers watch the fire burn and shift resources between each other. Trees
change only on fire steps (nothing douses them), so the towers' sighting is recomputed only then.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
from gymnasium import spaces

from ...fire import TreeState, closest_burning, fire_step
from ...procgen.weather import weather_at, weather_step
from ...procgen.wind import wind_step
from ...runtime import StepOutcome
from ...batching import read_only, replace_worlds
from ..island import (IslandMaps, IslandSpecs, conditions_reader, grid_lookup, restart_where,
                      sample_conditions, start_islands)
from .params import WildfireResourceParams
from .resources import (MAX_SUPPORT_TENTHS, TARGETS_PER_AGENT, TENTHS, TOWERS, apply_actions, grid_offsets,
                        initial_resources, total_support)
from .types import Sighting, WildfireResourceState

FRAME = 8  # values of one observation stack
STACKS = 2
EVENTS = {"fire_out": "the fire on the whole island went out (every tower of the world)"}
# Per-world arrays of the state (world axis first) that a partial reset replaces.
_PER_WORLD = ("tower_ground", "tower_weather", "allocation", "budget", "support", "impossible",
              "impossible_total", "frame", "fire_went_out")


class WildfireResourceSimulator:
    """B worlds of one compiled Wildfire Resource Management scenario."""

    observation_labels = ("closest fire x", "closest fire y", "closest fire z", "temperature", "humidity",
                          "overcast", "total support", "unallocated budget")
    observation_stacks = STACKS
    action_meanings = ("one branch per target (self, neighbour 1, neighbour 2, neighbour 3): "
                       "0 do nothing, 1 add 0.1 from the budget, 2 subtract 0.1 back to the budget")
    render_fps = 30

    def __init__(self, compiled):
        p: WildfireResourceParams = compiled.params
        if compiled.agents != TOWERS:
            raise ValueError(f"Wildfire Resource Management has exactly {TOWERS} towers, got {compiled.agents} agents")
        self.params = p
        self.agents = compiled.agents
        self.island = IslandSpecs.of(compiled)
        self.forest_spec, self.weather_spec, self.wind_spec = self.island.forest, self.island.weather, self.island.wind
        self.observation_space = spaces.Box(-1.0, 1.0, (FRAME * STACKS,), np.float32)
        self.action_space = spaces.MultiDiscrete([3] * TARGETS_PER_AGENT)
        self.cell_m = self.forest_spec.spacing_m
        half = p.island_half_extent_m
        self.towers = grid_offsets() * p.tower_spacing_m  # (9, 2) metres
        self.tower_rows = (self.towers[:, 1] + half) / self.cell_m - 0.5  # fractional forest-cell coordinates
        self.tower_cols = (self.towers[:, 0] + half) / self.cell_m - 0.5
        cells = self.forest_spec.cells
        self.tower_cells = np.clip(np.floor((self.towers + half) / self.cell_m).astype(np.int64), 0, cells - 1)
        self.weather_lookup = grid_lookup(cells, p.weather_grid_cells)

    # ---- reset -------------------------------------------------------------------------

    def reset(self, rng: np.random.Generator, batch: int) -> WildfireResourceState:
        return self._fresh(rng, batch, None)

    def _fresh(self, rng: np.random.Generator, batch: int, maps: IslandMaps | None) -> WildfireResourceState:
        """``batch`` new episodes: on new islands, or on the given ``maps`` (kept islands) when not None."""
        p = self.params
        island = start_islands(rng, batch, self.island, maps)
        maps, fire, wind, weather, conditions = island.maps, island.fire, island.wind, island.weather, island.conditions
        tower_ground = maps.height[:, self.tower_cells[:, 1], self.tower_cells[:, 0]]
        tower_weather = self._tower_weather(weather)
        sighting = self._sight(fire, maps.height, tower_ground, None)
        allocation, budget = initial_resources(batch, self.agents, p.initial_self_tenths)
        support = total_support(allocation)
        zeros = np.zeros((batch, self.agents), np.int16)
        frame = self._frame(sighting, tower_weather, support, budget,
                            np.zeros((batch, self.agents, FRAME * STACKS), np.float32))
        return WildfireResourceState(
            maps=maps, fire=fire, wind=wind, weather=weather, conditions=conditions, tick=0,
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
        allocation, budget, impossible = apply_actions(state.allocation, state.budget, np.asarray(actions))
        support = total_support(allocation)
        wind = wind_step(state.wind, rng, self.wind_spec)
        weather = weather_step(state.weather, wind.main, self.weather_spec)
        tick = state.tick + 1
        conditions, tower_weather = state.conditions, state.tower_weather
        if tick % p.weather_refresh_interval == 0:
            conditions = sample_conditions(weather, self.weather_spec, p.island_half_extent_m, p.weather_grid_cells)
            tower_weather = self._tower_weather(weather)
        fire, sighting, was_out = state.fire, state.sighting, state.fire.out
        if tick % p.fire_step_interval == 0:
            fire = fire_step(fire, rng, p, wind.main, state.maps.height, conditions_reader(conditions, self.weather_lookup))
            sighting = self._sight(fire, state.maps.height, state.tower_ground, state.sighting)
        went_out = fire.out & ~was_out
        new = replace(state, fire=fire, wind=wind, weather=weather, conditions=conditions, tick=tick,
                      tower_weather=tower_weather, sighting=sighting, allocation=allocation, budget=budget,
                      support=support, impossible=impossible, impossible_total=state.impossible_total + impossible,
                      frame=self._frame(sighting, tower_weather, support, budget, state.frame), fire_went_out=went_out)
        shape = budget.shape
        events = {"fire_out": np.broadcast_to(went_out[:, None], shape).copy()}
        return new, StepOutcome(terminated=np.zeros(shape, bool), events=events)

    def step_info(self, state: WildfireResourceState) -> dict[str, np.ndarray]:
        """(B, A) counts of impossible adds or subtracts (no-ops): this step and so far this episode."""
        return {"impossible_actions": state.impossible, "impossible_actions_episode": state.impossible_total}

    def _tower_weather(self, weather) -> np.ndarray:
        """(B, A, 3) float32 temperature, humidity, overcast at the towers."""
        batch = weather.offsets.shape[0]
        at = weather_at(weather, np.broadcast_to(self.towers, (batch,) + self.towers.shape), self.weather_spec)
        return np.stack([at["temperature"], at["humidity"], at["overcast"]], axis=-1).astype(np.float32)

    def _sight(self, fire, height: np.ndarray, tower_ground: np.ndarray, before: Sighting | None) -> Sighting:
        """Each tower's horizontally closest burning tree within the detection radius, its 3-D offset and
        distance, and whether that distance shrank since ``before`` (the previous fire step; None at reset,
        when every tower searches the whole burning list)."""
        p = self.params
        batch, agents = tower_ground.shape
        world = np.repeat(np.arange(batch), agents)
        if before is None:
            found, rows, cols = self._search(fire, world, np.tile(np.arange(agents), batch))
            rows, cols = np.where(found, rows, -1), np.where(found, cols, -1)
        else:
            rows, cols = self._track(fire, world, before.row.reshape(-1), before.col.reshape(-1))
        half = p.island_half_extent_m
        dx = (cols + 0.5) * self.cell_m - half - np.tile(self.towers[:, 0], batch)
        dy = (rows + 0.5) * self.cell_m - half - np.tile(self.towers[:, 1], batch)
        dz = height[world, np.maximum(rows, 0), np.maximum(cols, 0)] - tower_ground.reshape(-1)
        seen = ((rows >= 0) & (np.hypot(dx, dy) <= p.detection_radius_m)).reshape(batch, agents)
        offset = np.where(seen[..., None], np.stack([dx, dy, dz], axis=-1).reshape(batch, agents, 3), 0.0)
        distance = np.where(seen, np.sqrt((offset * offset).sum(axis=-1)), np.inf)
        approaching = np.zeros_like(seen) if before is None else seen & (distance < before.distance)
        return Sighting(row=rows.reshape(batch, agents), col=cols.reshape(batch, agents), offset=offset,
                        distance=distance, approaching=approaching)

    def _search(self, fire, world: np.ndarray, tower: np.ndarray):
        """closest_burning for towers ``tower`` (Q,) of worlds ``world`` (Q,) in their search squares."""
        return closest_burning(fire, world, self.tower_rows[tower], self.tower_cols[tower],
                               self.params.detection_radius_m / self.cell_m)

    def _track(self, fire, world: np.ndarray, rows: np.ndarray, cols: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The closest burning cells (Q,) after one fire step, from the previous ones ``rows``/``cols`` (Q,).

        Exactly closest_burning's answer at a fraction of its work: the trees burning now are the previous
        ones still burning plus this step's ignitions (the tail of the burning list), so the answer is the
        nearer of the previous closest (if it still burns) and the closest new ignition, ties to the lower
        cell index as closest_burning breaks them. Only towers whose closest burnt out search the whole list.
        """
        agents, cells = self.agents, fire.cells
        tower = np.tile(np.arange(agents), len(world) // agents)
        had = rows >= 0
        flat = (world * cells + rows) * cells + cols
        still = had & (fire.trees.reshape(-1)[np.where(had, flat, 0)] == TreeState.BURNING)
        fresh = len(fire.burning) - int(fire.ignited.sum())
        if fresh < len(fire.burning):
            ignitions = replace(fire, burning=fire.burning[fresh:], age=fire.age[fresh:])
            new_found, new_rows, new_cols = self._search(ignitions, world, tower)
        else:
            new_found, new_rows, new_cols = np.zeros(len(world), bool), np.full(len(world), -1), np.full(len(world), -1)
        q_rows, q_cols = self.tower_rows[tower], self.tower_cols[tower]

        def squared(r: np.ndarray, c: np.ndarray) -> np.ndarray:  # closest_burning's distance, same float ops
            return (r - q_rows) * (r - q_rows) + (c - q_cols) * (c - q_cols)

        d_old = np.where(still, squared(rows, cols), np.inf)
        d_new = np.where(new_found, squared(new_rows, new_cols), np.inf)
        new_flat = (world * cells + new_rows) * cells + new_cols
        take_new = new_found & ((d_new < d_old) | ((d_new == d_old) & (new_flat < flat)))
        rows = np.where(take_new, new_rows, np.where(still, rows, -1))
        cols = np.where(take_new, new_cols, np.where(still, cols, -1))
        lost = np.flatnonzero(had & ~still)  # an older tree may now be the closest: search them all
        if lost.size:
            found, r, c = self._search(fire, world[lost], tower[lost])
            rows[lost], cols[lost] = np.where(found, r, -1), np.where(found, c, -1)
        return rows, cols

    # ---- observation and picture --------------------------------------------------------

    def _frame(self, sighting: Sighting, tower_weather: np.ndarray, support: np.ndarray, budget: np.ndarray,
               previous: np.ndarray) -> np.ndarray:
        """(B, A, 16) float32: this step's frame, then the previous step's first frame."""
        out = np.empty(previous.shape, np.float32)
        out[..., 0:3] = np.clip(sighting.offset / self.params.detection_radius_m, -1.0, 1.0)
        out[..., 3:6] = tower_weather
        out[..., 6] = support / MAX_SUPPORT_TENTHS
        out[..., 7] = budget / TENTHS
        out[..., FRAME:] = previous[..., :FRAME]
        return out

    def observe(self, state: WildfireResourceState) -> np.ndarray:
        """(B, A, 16) float32 built in ``step``: 2 stacks (newest first) of the 8 labelled values (read-only: the state keeps it)."""
        return read_only(state.frame)

    def render(self, state: WildfireResourceState, index: int) -> np.ndarray:
        from .render import draw_towers

        return draw_towers(state, index, self.params, self.towers)
