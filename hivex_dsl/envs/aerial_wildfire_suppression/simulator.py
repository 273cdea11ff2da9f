"""Aerial Wildfire Suppression as a batched NumPy simulator (no Python loop over worlds or planes in step)."""

from __future__ import annotations

from dataclasses import replace
from functools import partial
from typing import NamedTuple

import numpy as np
from gymnasium import spaces

from ...base.numeric import and_not, clamp, constant
from ...runtime.batched import StepOutcome
from ...sim.batching import assemble, read_only, replace_worlds
from ...sim.cameras import blank_images
from ...sim.grids import terrain_grid
from ...sim.spaces import toggle_mask
from ...sim.fire import any_burning, douse, fire_step_unchecked
from ...sim.fire.search import closest_burning_at
from ...sim.procgen.weather import weather_step
from ...sim.procgen.wind import frame_ends, wind_step, wrap_angle
from ..island import (IslandMaps, IslandSpecs, fire_wind, grid_lookup, restart_where, start_islands,
                      weather_reader)
from .burn_clock import of_worlds, step_worlds, stepping_worlds
from .camera import pixel_offsets
from .global_state import state_components, world_state
from .params import CAMERA_PIXELS, AerialWildfireParams
from .ground import MASK_TERRAIN_M, near_village, over_land, over_terrain
from .respawn import continue_worlds, respawn_where, world_goes_on
from .spawn import spawn, spawn_out_of_sight
from .waiting import count_finishes
from .types import AerialWildfireState, Sighting
from .view import (build_look, drawn_border_m, frame_template, is_tiled, plane_cameras, redraw_cells,
                   redraw_fire_step, view_frame, window_cells)

PICKUP_EVENT = "picked_up_water"
# Events of one plane; a task that ends on one of them takes that plane out of the game (see _sense).
FINDING_EVENTS = ("found_fire", "found_village")
PLANE_EVENTS = (PICKUP_EVENT, "dropped_water") + FINDING_EVENTS
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
        self.wait = p.finished_planes == "wait"
        self.held_events = self.plane_endings if self.wait else ()  # finished planes wait: contract.HoldsEndings
        mode = p.spawn_holding_water
        self.spawn_water = mode == "always" or (mode == "auto" and PICKUP_EVENT not in compiled.ends_on)
        finding = any(event in FINDING_EVENTS for event in compiled.ends_on)
        self.handles_water = p.water_in_find_tasks or not finding  # the release's Find tasks neither refill nor drop
        self.camera_offsets = pixel_offsets(CAMERA_PIXELS, p.camera_pixel_m)
        # a plane stays inside the border, or stops one step beyond it
        self.frame = view_frame(self.camera_offsets, self.forest_spec.cells, p.island_half_extent_m,
                                drawn_border_m(p, CAMERA_PIXELS), p.border_half_extent_m + p.plane_speed_m)
        self.frame_template = frame_template(self.frame)
        along = np.arange(p.drop_points) * p.drop_point_spacing_m
        self.drop_along = along  # (P,) metres ahead of the plane
        self.cell_m = self.forest_spec.spacing_m
        self.weather_lookup = grid_lookup(self.forest_spec.cells, p.weather_grid_cells)
        self.operands = _Operands.of(p, self.cell_m)
        self.frame_casts = p.terrain_cast == "frame"
        self.release_mask = p.drop_mask == "release"
        self.drops_past_island = p.drop_ground == "terrain"
        self.terrain_grid = terrain_grid(self.island.terrain)
        self.sea_level_m = self.island.terrain.sea_level_m  # the ground grid's SEA: height at or below it
        self._query_shapes: dict[tuple[int, int], tuple[np.ndarray, np.ndarray]] = {}

    # ---- reset -------------------------------------------------------------------------

    _spawn = spawn  # where planes start, out of the fire's sight: see spawn.py
    _spawn_out_of_sight = spawn_out_of_sight

    def reset(self, rng: np.random.Generator, batch: int) -> AerialWildfireState:
        return self._fresh(rng, batch, None)

    def _fresh(self, rng: np.random.Generator, batch: int, maps: IslandMaps | None,
               tiled: bool | None = None) -> AerialWildfireState:
        """``batch`` new episodes: on new islands, or on the given ``maps`` (kept islands) when not None.
        Their look is ``tiled`` or not (see view.build_look; by default as suits ``batch`` worlds)."""
        island = start_islands(rng, batch, self.island, maps)
        shape, no = (batch, self.agents), np.zeros((batch, self.agents), bool)
        flying = np.ones(shape, bool)
        position, heading, water = self._spawn_out_of_sight(rng, island.fire, island.maps.village)
        look = build_look(island.fire.trees, island.maps.ground, self.frame_template, self.frame, tiled)
        return AerialWildfireState(
            maps=island.maps, fire=island.fire, wind=island.wind, weather=island.weather, tick=0,
            position=position, heading=heading, water=water, flying=flying, cast_at=position,
            sighting=self._sight_of(island.fire, island.maps.village, position, flying),
            seen_fire=no, seen_village=no, village_hit=np.zeros(batch, bool), village_reached=np.zeros(batch, bool),
            crossed=no, picked_up=no, dropped=no, found_fire=no, found_village=no,
            extinguished=np.zeros(shape, np.int32), prepared=np.zeros(shape, np.int32),
            fire_went_out=np.zeros(batch, bool), village_threatened=np.zeros(batch, bool),
            burning=any_burning(island.fire), finishes=np.zeros(batch, np.int64), look=look,
            burn_running=np.zeros(batch, bool), burn_waiting=np.zeros(batch, bool),
            visual=self._cameras(position, heading, look, island.fire.trees, island.maps.ground))

    def reset_where(self, state: AerialWildfireState, mask: np.ndarray, rng: np.random.Generator) -> AerialWildfireState:
        """New episodes in the worlds where ``mask`` (B,) is true; they keep their islands unless
        params.redraw_island is "episode", and under params.episodes_continue a world that the time limit cut goes
        on whole (respawn.continue_worlds). ``state`` is used up: its fire and look are rewritten in place."""
        if self.params.episodes_continue:
            going_on = mask & world_goes_on(state, self.agents)
            state, mask = continue_worlds(self, state, going_on, rng), mask & ~going_on
        if not mask.any():
            return state
        fresh_episodes = partial(self._fresh, tiled=is_tiled(state.look))  # the new worlds' look in the batch's layout
        fresh, changes = restart_where(state, mask, rng, self.params.redraw_island, fresh_episodes, _PER_WORLD)
        state.look[mask] = fresh.look
        # the other worlds keep the sighting of their step: what a plane sees never depends on another world
        sighting = replace_worlds(state.sighting, mask, fresh.sighting)
        return replace(state, sighting=sighting, **changes)

    def derive(self, state: AerialWildfireState) -> AerialWildfireState:
        """``state`` with what it derives from its maps, fire and planes rebuilt (sighting, look, visual):
        for states edited by hand."""
        look = build_look(state.fire.trees, state.maps.ground, self.frame_template, self.frame, is_tiled(state.look))
        return replace(state, look=look, sighting=self._sight(state),
                       visual=self._cameras(state.position, state.heading, look, state.fire.trees, state.maps.ground))

    def _cameras(self, position: np.ndarray, heading: np.ndarray, look: np.ndarray, trees: np.ndarray,
                 ground: np.ndarray, facing: np.ndarray | None = None) -> np.ndarray:
        if not self.params.cameras_render:
            return blank_images(heading.shape + (CAMERA_PIXELS, CAMERA_PIXELS, 3))
        return plane_cameras(position, heading, look, trees, ground, self.frame, self.camera_offsets, facing)

    respawn_where = respawn_where  # single planes in running worlds: see respawn.py

    # ---- step --------------------------------------------------------------------------

    def step(self, state: AerialWildfireState, actions: dict, rng: np.random.Generator):
        """actions: continuous (B, A, 1) steer, discrete (B, A, 1) drop flag. ``state`` is used up: its fire
        and look are written in place."""
        p = self.params
        flight = self._fly(state, actions)
        fire, extinguished, prepared = self._drop(state.fire, state.look, flight.position, flight.facing,
                                                  flight.dropping)
        wind = wind_step(state.wind, rng, self.wind_spec)
        weather = weather_step(state.weather, wind.main, self.weather_spec)
        worlds, running, waiting = stepping_worlds(p, state.tick, fire.out, state.burn_running, state.burn_waiting)
        if worlds is None or worlds.any():
            burning = fire.burning
            conditions = weather_reader(weather, self.weather_spec, p.island_half_extent_m, p.weather_grid_cells,
                                        self.weather_lookup)
            winds = fire_wind(p, wind, self.wind_spec, p.island_half_extent_m, self.cell_m)
            fire = step_worlds(fire, worlds, lambda some, index: fire_step_unchecked(
                some, rng, p, of_worlds(winds, index), of_worlds(state.maps.height, index),
                of_worlds(conditions, index), self.cell_m))
            redraw_fire_step(state.look, burning, fire, self.frame)
        moved = {"fire": fire, "wind": wind, "weather": weather, "tick": state.tick + 1, "extinguished": extinguished,
                 "prepared": prepared, "burn_running": running, "burn_waiting": waiting}
        return self._sense(state, moved, flight)

    def _sense(self, prev: AerialWildfireState, moved: dict, flight: Flight):
        """The state after the step and its outcome: sightings, one-off events, planes whose task ended, cameras.
        ``moved`` holds the step's new fire, wind, weather, tick and drop counts (state fields)."""
        fire = moved["fire"]
        # a waiting plane still observes (the release collects a frozen agent's observations)
        sighting = self._sight_of(fire, prev.maps.village, flight.position, self._playing(flight.flying))
        found_fire = and_not(sighting.plane_found & flight.flying, prev.seen_fire)  # found by flying to it
        near = self._near_village(prev.maps, flight.position, flight.cast_at, flight.flying)
        found_village = and_not(near, prev.seen_village)
        reached = prev.village_reached | sighting.village_threat
        threatened = and_not(reached, prev.village_hit)  # once an episode, again in a continued world's next
        went_out = and_not(fire.out, prev.fire.out)
        events = {PICKUP_EVENT: flight.picked, "dropped_water": flight.dropping, "found_fire": found_fire,
                  "found_village": found_village, "fire_out": np.repeat(went_out[:, None], found_fire.shape[1], axis=1)}
        flying = flight.flying
        if self.plane_endings:  # a plane whose episode ends on its own event stops flying, dropping and refilling
            flying = and_not(flying, np.logical_or.reduce([events[e] for e in self.plane_endings]))
        finishes, world_ended = prev.finishes, None
        if self.wait:
            finishes, world_ended = count_finishes(prev, flying, events, self.plane_endings)
            found_fire, found_village = events["found_fire"], events["found_village"]
        visual = self._cameras_after(prev, flight, fire.trees)
        new = assemble(AerialWildfireState, maps=prev.maps, **moved, position=flight.position, heading=flight.heading,
                       water=flight.water, flying=flying, cast_at=flight.cast_at, sighting=sighting,
                       seen_fire=prev.seen_fire | found_fire, seen_village=prev.seen_village | found_village,
                       village_hit=prev.village_hit | threatened, village_reached=reached,
                       crossed=flight.crossed, picked_up=flight.picked, dropped=flight.dropping, found_fire=found_fire,
                       found_village=found_village, fire_went_out=went_out, village_threatened=threatened,
                       burning=any_burning(fire), finishes=finishes, look=prev.look, visual=visual)
        if not self.wait:
            return new, StepOutcome(terminated=flight.crossed.copy(), events=events)
        return new, StepOutcome(np.zeros(flying.shape, bool), events, world_ended=world_ended)

    def _playing(self, flying: np.ndarray) -> np.ndarray:
        """(B, A) bool: the planes that observe, the flying ones, and under ``finished_planes: wait`` all."""
        return np.ones_like(flying) if self.wait else flying

    def _cameras_after(self, prev: AerialWildfireState, flight: Flight, trees: np.ndarray) -> np.ndarray:
        """(B, A, P, P, 3) cameras after the step. In a one-world batch, a plane that was out of the game
        before the step and is beyond the island's sight keeps its picture: it has not moved, and the
        water ring and outside it sees never change (a reset draws its world's pictures afresh)."""
        parked = and_not(flight.outside > self.frame.blind_m, prev.flying)
        if len(parked) != 1 or not np.count_nonzero(parked):
            return self._cameras(flight.position, flight.heading, prev.look, trees, prev.maps.ground, flight.facing)
        parked, watched = parked[0], ~parked[0]
        visual = np.empty_like(prev.visual)
        visual[0, parked] = prev.visual[0, parked]
        if np.count_nonzero(watched):
            visual[0, watched] = self._cameras(flight.position[:, watched], flight.heading[:, watched], prev.look,
                                               trees, prev.maps.ground, flight.facing[:, watched])[0]
        return visual

    def _fly(self, state: AerialWildfireState, actions: dict) -> Flight:
        """Turn and move the flying planes; border crossings, refills and who drops water this step."""
        k = self.operands
        flying, water = state.flying, state.water
        steer = clamp(actions["continuous"][..., 0].astype(np.float64), k.minus_one, k.one)
        if self.params.turn_rule == "full":
            steer = np.sign(steer)
        heading = np.where(flying, wrap_angle(state.heading + k.turn_rad * steer), state.heading)
        facing = np.empty(heading.shape + (2,))
        np.cos(heading, out=facing[..., 0])
        np.sin(heading, out=facing[..., 1])
        position = np.where(flying[..., None], state.position + k.speed * facing, state.position)
        reach = np.abs(position)
        outside = np.maximum(reach[..., 0], reach[..., 1])
        crossed = flying & (outside > k.border)
        still = flying ^ crossed  # flying & ~crossed
        handles = self.handles_water
        picked = and_not(still & (outside > k.island_half) & handles, water)
        # only water held when the plane decided drops: the release's mask closed the drop to a plane without water,
        # though its OnActionReceived fills it (PickupWater) before DropWater reads the action
        dropping = still & water & (actions["discrete"][..., 0] == 1) & handles
        water = water | picked
        cast_at = position
        if self.frame_casts:  # the drop reads the last frame's cast; this step's move is cast if it ends a frame
            dropping_over = state.cast_at
            if not frame_ends(state.tick, self.params.wind_frame_steps):
                cast_at = state.cast_at
        else:
            dropping_over = position
        if np.count_nonzero(dropping):
            dropping &= self._over_land(state.maps, dropping_over)
        return Flight(heading, facing, position, outside, still, crossed, picked, and_not(water, dropping), dropping,
                      cast_at)

    _over_land = over_land  # the ground under the planes: see ground.py
    _over_terrain = over_terrain
    _near_village = near_village

    def _drop(self, fire, look: np.ndarray, position: np.ndarray, direction: np.ndarray, dropping: np.ndarray):
        """Wet the swath of every dropping plane and redraw it in ``look``.

        Returns (fire, extinguished (B, A), prepared (B, A))."""
        batch, agents = dropping.shape
        if not np.count_nonzero(dropping):
            zero = np.zeros((batch, agents), np.int32)
            return fire, zero, zero
        owners = np.flatnonzero(dropping.reshape(-1))
        pos = position.reshape(-1, 2)[owners]
        dirs = direction.reshape(-1, 2)[owners]
        rows, cols = self.swath_cells(pos, dirs)
        owner = np.repeat(owners, rows.shape[1])
        radius = self.params.drop_radius_m / self.cell_m
        fire, out, wet = douse(fire, owner // agents, rows.ravel(), cols.ravel(), radius, owner, batch * agents,
                               self.params.extinguished_spread)
        redraw_cells(look, fire.trees, window_cells(owner // agents, rows.ravel(), cols.ravel(), radius,
                                                    self.forest_spec.cells), self.frame)
        return fire, out.reshape(batch, agents).astype(np.int32), wet.reshape(batch, agents).astype(np.int32)

    def swath_cells(self, position: np.ndarray, direction: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Fractional (row, col) forest-cell coordinates (D, P) of the swath's points ahead of D planes at
        ``position`` (D, 2) metres facing the unit ``direction`` (D, 2); each wets drop_radius_m around it."""
        points = position[:, None, :] + self.drop_along[None, :, None] * direction[:, None, :]  # (D, P, 2)
        half = self.params.island_half_extent_m
        return (points[..., 1] + half) / self.cell_m - 0.5, (points[..., 0] + half) / self.cell_m - 0.5

    def _sight(self, state: AerialWildfireState) -> Sighting:
        """Closest burning tree in each plane's view square, and fire near each village, in one query."""
        return self._sight_of(state.fire, state.maps.village, state.position, state.flying)

    def _sight_of(self, fire, village: np.ndarray, position: np.ndarray, flying: np.ndarray) -> Sighting:
        p, k = self.params, self.operands
        batch, agents = flying.shape
        world, half = self._queries(batch, agents)
        points = np.concatenate([position.reshape(-1, 2), village], axis=0)
        cell_points = (points + k.island_half) / k.cell_m - k.half  # (col, row) per point
        found, hit_rows, hit_cols = closest_burning_at(fire, world, cell_points, half)
        if not np.count_nonzero(found):  # most steps: no plane and no village sees fire
            return assemble(Sighting, plane_found=np.zeros((batch, agents), bool),
                            plane_xy=np.zeros((batch, agents, 2)), village_threat=np.zeros(batch, bool))
        xy = np.empty((len(found), 2))  # (x, y) = (col, row) cell centres in metres, 0 where nothing was found
        xy[:, 0], xy[:, 1] = hit_cols, hit_rows
        xy += 0.5
        xy *= self.cell_m
        xy -= p.island_half_extent_m
        xy = np.where(found[:, None], xy, 0.0)
        planes = batch * agents
        village_gap = xy[planes:] - village
        threat = found[planes:]  # a burning tree in the village's square (the query's box)
        if p.village_zone == "circle":
            threat = threat & (np.hypot(village_gap[:, 0], village_gap[:, 1]) <= k.village_radius)
        return assemble(Sighting, plane_found=found[:planes].reshape(batch, agents) & flying,
                        plane_xy=xy[:planes].reshape(batch, agents, 2), village_threat=threat)

    def _queries(self, batch: int, agents: int) -> tuple[np.ndarray, np.ndarray]:
        """World (B * A + B,) and half box in cells of the sighting queries: every plane, then every village."""
        if (batch, agents) not in self._query_shapes:
            p = self.params
            world = np.concatenate([np.repeat(np.arange(batch), agents), np.arange(batch)])
            half = np.concatenate([np.full(batch * agents, p.fire_view_half_m), np.full(batch, p.village_radius_m)])
            half_cells = half / self.cell_m
            for array in (world, half_cells):
                array.flags.writeable = False
            self._query_shapes = {(batch, agents): (world, half_cells)}  # one shape at a time
        return self._query_shapes[batch, agents]

    # ---- observation and picture --------------------------------------------------------

    def observe(self, state: AerialWildfireState) -> dict[str, np.ndarray]:
        """vector (B, A, 8) float32 in [-1, 1], visual (B, A, 42, 42, 3) float32 in [0, 1]."""
        k = self.operands
        sighting = state.sighting
        vector = np.empty(state.heading.shape + (8,), np.float32)  # float64 values, rounded once on assignment
        vector[..., 0:2] = clamp(state.position / k.border, k.minus_one, k.one)
        vector[..., 2] = np.cos(state.heading)
        vector[..., 3] = np.sin(state.heading)
        vector[..., 4] = state.water
        vector[..., 5:7] = clamp(sighting.plane_xy / k.border, k.minus_one, k.one)
        vector[..., 7] = sighting.plane_found
        # the state's own camera array (drawn in step): read-only, so an in-place edit raises
        return {"vector": vector, "visual": read_only(state.visual)}

    def action_mask(self, state: AerialWildfireState) -> np.ndarray:
        """(B, A, 2) bool: the drop is open to a flying plane that holds water over terrain at least MASK_TERRAIN_M
        high, as the release's WriteDiscreteActionMask opens it, though its DropWater drops only over higher ground
        (here: above the sea level SEA_LEVEL_M), so over a low shore the branch is open and a drop does nothing. The
        mask knows no task: the Find tasks' planes, which neither drop nor refill (params.water_in_find_tasks), keep
        their first water and the branch open wherever they fly over the island (the reward table's note 'What the
        cameras see past the border, and the drop's action mask'). Under params.drop_mask 'release' it opens to
        waiting planes too and over the water ring's seabed, where a drop does nothing below the sea level (above it,
        on a headland past the island, it lands under params.drop_ground 'terrain')."""
        open_ = state.water.copy() if self.release_mask else state.flying & state.water  # narrowed in place below
        if np.count_nonzero(open_):
            open_ &= self._over_terrain(state.maps, state.cast_at if self.frame_casts else state.position)
        return toggle_mask(open_)

    state_components = state_components  # the global state's world facts: see global_state.py
    world_state = world_state

    def render(self, state: AerialWildfireState, index: int) -> np.ndarray:
        from .render import draw_island

        return draw_island(state, index, self.params)


class _Operands(NamedTuple):
    """The float64 constants of the step as 0-d arrays: cheaper operands than Python floats on the few
    values of a one-world step (NumPy resolves a Python scalar's type on every call), with the same
    results on float64, int and bool arrays."""

    one: np.ndarray
    minus_one: np.ndarray
    half: np.ndarray
    turn_rad: np.ndarray
    speed: np.ndarray
    border: np.ndarray  # the border's half extent; observed positions are metres / border
    village_radius: np.ndarray
    island_half: np.ndarray  # the island's half extent
    cell_m: np.ndarray

    @classmethod
    def of(cls, p: AerialWildfireParams, cell_m: float) -> "_Operands":
        values = (1.0, -1.0, 0.5, np.radians(p.turn_rate_deg), p.plane_speed_m, p.border_half_extent_m,
                  p.village_radius_m, p.island_half_extent_m, cell_m)
        return cls(*(constant(value) for value in values))


class Flight(NamedTuple):
    """The planes after their move: heading (B, A), facing (B, A, 2) its (cos, sin), position (B, A, 2),
    outside (B, A) max(|x|, |y|) of the position, and (B, A) bool flying, crossed the border, picked up water,
    holding water, dropping water, and where each plane last read the ground (B, A, 2) (params.terrain_cast)."""

    heading: np.ndarray
    facing: np.ndarray
    position: np.ndarray
    outside: np.ndarray
    flying: np.ndarray
    crossed: np.ndarray
    picked: np.ndarray
    water: np.ndarray
    dropping: np.ndarray
    cast_at: np.ndarray


# Per-world arrays of the state (world axis first) that a partial reset replaces.
_PER_WORLD = ("position", "heading", "water", "flying", "cast_at", "seen_fire", "seen_village", "village_hit",
              "village_reached", "crossed", "picked_up", "dropped", "found_fire", "found_village", "extinguished",
              "prepared", "fire_went_out", "village_threatened", "burning", "finishes", "visual",
              "burn_running")  # not burn_waiting: a waiting BurnNext outlives its world (burn_clock.py)
