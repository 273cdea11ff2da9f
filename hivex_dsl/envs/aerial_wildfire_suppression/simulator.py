"""Aerial Wildfire Suppression as a batched NumPy simulator (no Python loop over worlds or planes in step)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
from gymnasium import spaces

from ...fire import burning_count, closest_burning, douse, fire_step
from ...procgen.weather import weather_step
from ...procgen.wind import wind_step, wrap_angle
from ...runtime import StepOutcome
from .camera import cameras, pixel_offsets
from .params import CAMERA_PIXELS, AerialWildfireParams
from .types import AerialWildfireState, Sighting
from ..island import (SEA, IslandMaps, IslandSpecs, conditions_reader, grid_lookup, restart_where, sample_conditions,
                      start_islands)

PICKUP_EVENT = "picked_up_water"
# Events of one plane; a task that ends on one of them takes that plane out of the game (see _sense).
PLANE_EVENTS = (PICKUP_EVENT, "dropped_water", "found_fire", "found_village")
EVENTS = {
    PICKUP_EVENT: "a plane without water entered the water ring and filled up",
    "dropped_water": "a plane dropped its water over land",
    "found_fire": "a plane observed a burning tree for the first time this episode",
    "found_village": "a plane came within village_radius_m of the village for the first time this episode",
    "fire_out": "the fire on the whole island went out (every plane of the world)",
}


class AerialWildfireSimulator:
    """B worlds of one compiled Aerial Wildfire Suppression scenario."""

    observation_labels = ("local position x", "local position y", "direction x", "direction y", "holding water",
                          "closest burning tree x", "closest burning tree y", "closest tree burning")
    action_meanings = "continuous: steer in [-1, 1] (turn rate x steer per step); discrete: 0 do nothing, 1 drop water"
    render_fps = 30

    def __init__(self, compiled):
        p: AerialWildfireParams = compiled.params
        self.params = p
        self.agents = compiled.agents
        self.island = IslandSpecs.of(compiled)
        self.forest_spec, self.weather_spec, self.wind_spec = self.island.forest, self.island.weather, self.island.wind
        self.observation_space = spaces.Dict({
            "vector": spaces.Box(-1.0, 1.0, (8,), np.float32),
            "visual": spaces.Box(0.0, 1.0, (CAMERA_PIXELS, CAMERA_PIXELS, 3), np.float32)})
        self.action_space = spaces.Dict({
            "continuous": spaces.Box(-1.0, 1.0, (1,), np.float32),
            "discrete": spaces.MultiDiscrete([2])})
        self.plane_endings = tuple(e for e in compiled.ends_on if e in PLANE_EVENTS)
        mode = p.spawn_holding_water
        self.spawn_water = mode == "always" or (mode == "auto" and PICKUP_EVENT not in compiled.ends_on)
        self.camera_offsets = pixel_offsets(CAMERA_PIXELS, p.camera_pixel_m)
        along = np.arange(p.drop_points) * p.drop_point_spacing_m
        self.drop_along = along  # (P,) metres ahead of the plane
        self.cell_m = self.forest_spec.spacing_m
        self.weather_lookup = grid_lookup(self.forest_spec.cells, p.weather_grid_cells)

    # ---- reset -------------------------------------------------------------------------

    def _spawn(self, rng: np.random.Generator, count: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Positions (count, A, 2) uniform in the spawn disk clipped to the border, headings, water."""
        p, shape = self.params, (count, self.agents)
        radius = p.spawn_radius_m * np.sqrt(rng.random(shape))
        angle = rng.uniform(-np.pi, np.pi, shape)
        position = np.stack([radius * np.cos(angle), radius * np.sin(angle)], axis=-1)
        position = np.clip(position, -p.border_half_extent_m, p.border_half_extent_m)
        heading = rng.uniform(-np.pi, np.pi, shape)
        return position, heading, np.full(shape, self.spawn_water)

    def reset(self, rng: np.random.Generator, batch: int) -> AerialWildfireState:
        return self._fresh(rng, batch, None)

    def _fresh(self, rng: np.random.Generator, batch: int, maps: IslandMaps | None) -> AerialWildfireState:
        """``batch`` new episodes: on new islands, or on the given ``maps`` (kept islands) when not None."""
        island = start_islands(rng, batch, self.island, maps)
        position, heading, water = self._spawn(rng, batch)
        shape, no = (batch, self.agents), np.zeros((batch, self.agents), bool)
        state = AerialWildfireState(
            maps=island.maps, fire=island.fire, wind=island.wind, weather=island.weather,
            conditions=island.conditions, tick=0,
            position=position, heading=heading, water=water, flying=np.ones(shape, bool),
            sighting=Sighting(no, np.zeros(shape + (2,)), np.zeros(batch, bool)),
            seen_fire=no, seen_village=no, village_hit=np.zeros(batch, bool),
            crossed=no, picked_up=no, dropped=no, found_fire=no, found_village=no,
            extinguished=np.zeros(shape, np.int32), prepared=np.zeros(shape, np.int32),
            fire_went_out=np.zeros(batch, bool), village_threatened=np.zeros(batch, bool),
            burning=burning_count(island.fire) > 0)
        return replace(state, sighting=self._sight(state))

    def reset_where(self, state: AerialWildfireState, mask: np.ndarray, rng: np.random.Generator) -> AerialWildfireState:
        """New episodes in the worlds where ``mask`` (B,) is true; they keep their islands unless
        params.redraw_island is "episode"."""
        if not mask.any():
            return state
        _, changes = restart_where(state, mask, rng, self.params.redraw_island, self._fresh, _PER_WORLD)
        new = replace(state, **changes)
        return replace(new, sighting=self._sight(new))

    # ---- step --------------------------------------------------------------------------

    def step(self, state: AerialWildfireState, actions: dict, rng: np.random.Generator):
        """actions: continuous (B, A, 1) steer, discrete (B, A, 1) drop flag."""
        p = self.params
        flying = state.flying
        steer = np.clip(actions["continuous"][..., 0].astype(np.float64), -1.0, 1.0)
        heading = np.where(flying, wrap_angle(state.heading + np.radians(p.turn_rate_deg) * steer), state.heading)
        direction = np.stack([np.cos(heading), np.sin(heading)], axis=-1)
        position = np.where(flying[..., None], state.position + p.plane_speed_m * direction, state.position)
        outside = np.abs(position).max(axis=-1)
        crossed = flying & (outside > p.border_half_extent_m)
        flying = flying & ~crossed
        picked = flying & (outside > p.island_half_extent_m) & ~state.water
        water = state.water | picked
        dropping = flying & water & (actions["discrete"][..., 0] == 1) & self._over_land(state, position)
        fire, extinguished, prepared = self._drop(state.fire, position, direction, dropping)
        water = water & ~dropping

        wind = wind_step(state.wind, rng, self.wind_spec)
        weather = weather_step(state.weather, wind.main, self.weather_spec)
        tick = state.tick + 1
        conditions = state.conditions
        if tick % p.fire_step_interval == 0:
            conditions = sample_conditions(weather, self.weather_spec, p.island_half_extent_m, p.weather_grid_cells)
            fire = fire_step(fire, rng, p, wind.main, state.maps.height, conditions_reader(conditions, self.weather_lookup))
        new = replace(state, fire=fire, wind=wind, weather=weather, conditions=conditions, tick=tick,
                      position=position, heading=heading, water=water, flying=flying, crossed=crossed,
                      picked_up=picked, dropped=dropping, extinguished=extinguished, prepared=prepared)
        return self._sense(state, new)

    def _over_land(self, state: AerialWildfireState, position: np.ndarray) -> np.ndarray:
        """(B, A) bool: the ground under each plane is island land (not sea, not the water ring)."""
        half, cells = self.params.island_half_extent_m, self.forest_spec.cells
        col = np.floor((position[..., 0] + half) / self.cell_m).astype(np.int64)
        row = np.floor((position[..., 1] + half) / self.cell_m).astype(np.int64)
        inside = (row >= 0) & (row < cells) & (col >= 0) & (col < cells)
        world = np.arange(position.shape[0])[:, None]
        ground = state.maps.ground[world, np.clip(row, 0, cells - 1), np.clip(col, 0, cells - 1)]
        return inside & (ground != SEA)

    def _drop(self, fire, position: np.ndarray, direction: np.ndarray, dropping: np.ndarray):
        """Wet the swath of every dropping plane; (fire, extinguished (B, A), prepared (B, A))."""
        batch, agents = dropping.shape
        owners = np.flatnonzero(dropping.reshape(-1))
        zero = np.zeros((batch, agents), np.int32)
        if owners.size == 0:
            return fire, zero, zero
        pos = position.reshape(-1, 2)[owners]
        dirs = direction.reshape(-1, 2)[owners]
        points = pos[:, None, :] + self.drop_along[None, :, None] * dirs[:, None, :]  # (D, P, 2)
        rows, cols = self._cells(points)
        owner = np.repeat(owners, points.shape[1])
        fire, out, wet = douse(fire, owner // agents, rows.ravel(), cols.ravel(), self.params.drop_radius_m / self.cell_m,
                               owner, batch * agents)
        return fire, out.reshape(batch, agents).astype(np.int32), wet.reshape(batch, agents).astype(np.int32)

    def _cells(self, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Fractional (row, col) forest-cell coordinates of points (..., 2) metres."""
        half = self.params.island_half_extent_m
        return (points[..., 1] + half) / self.cell_m - 0.5, (points[..., 0] + half) / self.cell_m - 0.5

    def _sight(self, state: AerialWildfireState) -> Sighting:
        """Closest burning tree in each plane's view square, and fire near each village, in one query."""
        p = self.params
        batch, agents = state.heading.shape
        points = np.concatenate([state.position.reshape(-1, 2), state.maps.village], axis=0)
        world = np.concatenate([np.repeat(np.arange(batch), agents), np.arange(batch)])
        rows, cols = self._cells(points)
        half = np.concatenate([np.full(batch * agents, p.fire_view_half_m), np.full(batch, p.village_radius_m)])
        found, hit_rows, hit_cols = closest_burning(state.fire, world, rows, cols, half / self.cell_m)
        xy = np.stack([(hit_cols + 0.5) * self.cell_m - p.island_half_extent_m,
                       (hit_rows + 0.5) * self.cell_m - p.island_half_extent_m], axis=-1)
        xy = np.where(found[:, None], xy, 0.0)
        planes = slice(0, batch * agents)
        village_gap = xy[batch * agents:] - state.maps.village
        threat = found[batch * agents:] & (np.hypot(village_gap[:, 0], village_gap[:, 1]) <= p.village_radius_m)
        return Sighting(plane_found=found[planes].reshape(batch, agents) & state.flying,
                        plane_xy=xy[planes].reshape(batch, agents, 2), village_threat=threat)

    def _sense(self, prev: AerialWildfireState, new: AerialWildfireState):
        p = self.params
        sighting = self._sight(new)
        found_fire = sighting.plane_found & ~prev.seen_fire
        gap = new.position - new.maps.village[:, None, :]
        near_village = new.flying & (np.hypot(gap[..., 0], gap[..., 1]) <= p.village_radius_m)
        found_village = near_village & ~prev.seen_village
        threatened = sighting.village_threat & ~prev.village_hit
        went_out = new.fire.out & ~prev.fire.out
        new = replace(new, sighting=sighting, seen_fire=prev.seen_fire | found_fire, found_fire=found_fire,
                      seen_village=prev.seen_village | found_village, found_village=found_village,
                      village_hit=prev.village_hit | threatened, village_threatened=threatened,
                      fire_went_out=went_out, burning=burning_count(new.fire) > 0)
        events = {PICKUP_EVENT: new.picked_up, "dropped_water": new.dropped, "found_fire": found_fire,
                  "found_village": found_village,
                  "fire_out": np.broadcast_to(went_out[:, None], new.flying.shape).copy()}
        if self.plane_endings:  # a plane whose episode ends on its own event stops flying, dropping and refilling
            finished = np.logical_or.reduce([events[e] for e in self.plane_endings])
            new = replace(new, flying=new.flying & ~finished)
        return new, StepOutcome(terminated=new.crossed.copy(), events=events)

    # ---- observation and picture --------------------------------------------------------

    def observe(self, state: AerialWildfireState) -> dict[str, np.ndarray]:
        """vector (B, A, 8) float32 in [-1, 1], visual (B, A, 42, 42, 3) float32 in [0, 1]."""
        p = self.params
        scale = p.border_half_extent_m
        sighting = state.sighting
        vector = np.concatenate([
            np.clip(state.position / scale, -1.0, 1.0),
            np.stack([np.cos(state.heading), np.sin(state.heading)], axis=-1),
            state.water[..., None].astype(np.float64),
            np.clip(sighting.plane_xy / scale, -1.0, 1.0),
            sighting.plane_found[..., None].astype(np.float64),
        ], axis=-1).astype(np.float32)
        visual = cameras(state.position, state.heading, state.fire.trees, state.maps.ground, self.camera_offsets,
                         p.island_half_extent_m, p.border_half_extent_m)
        return {"vector": vector, "visual": visual}

    def render(self, state: AerialWildfireState, index: int) -> np.ndarray:
        from .render import draw_island

        return draw_island(state, index, self.params)


# Per-world arrays of the state (world axis first) that a partial reset replaces.
_PER_WORLD = ("position", "heading", "water", "flying", "seen_fire", "seen_village", "village_hit", "crossed",
              "picked_up", "dropped", "found_fire", "found_village", "extinguished", "prepared", "fire_went_out",
              "village_threatened", "burning")
