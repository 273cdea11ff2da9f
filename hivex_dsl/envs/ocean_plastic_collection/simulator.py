"""Ocean Plastic Collection as a batched NumPy simulator (no Python loop over worlds or vessels in step).

Per step: vessels that crashed on the previous step respawn (``crash_outcome: respawn``); every
active vessel turns and accelerates; crossings of the border and vessel-vessel collisions are
detected; the collectors sweep up pebbles; cameras and nearby counts are read at the new
positions. With ``crash_outcome: end`` a crashed vessel is terminated and frozen where it crashed; with
``end_world`` (the default) so is it, and the event ``crash_ended_world`` fires for every vessel of its world,
which every task's ``ends_on`` names: the world's episode ends for all its vessels.
"""

from __future__ import annotations

from dataclasses import replace
from functools import lru_cache
from typing import NamedTuple

import numpy as np
from gymnasium import spaces

from ...base.numeric import all_true, clamp
from ...runtime.batched import StepOutcome
from ...sim.batching import assemble, read_only, replace_worlds
from ...sim.procgen.pollution import PollutionSpec, SpawnSpec, pollution_map, sample_pebbles, spawn_vessels
from ...sim.procgen.wind import wrap_angle
from .camera import CAMERA_CELLS, Geometry, Sensing, as_pairs, build_field, heat_camera, sense
from .global_state import state_components, world_state
from .neighbours import neighbour_distances
from .params import OceanPlasticCollectionParams
from .respawn import respawn_where
from .types import OceanState

# steer action -> heading change sign: 0 do nothing, 1 turn right (clockwise), 2 turn left
STEER_SIGN = np.array([0.0, -1.0, 1.0])
FRAME = 6  # vector components of one stack
STACKS = 2  # [paper] two stacks of both observations


class Motion(NamedTuple):
    """The motion constants of a scenario, tabulated by action."""

    turn: np.ndarray  # (3,) heading change (radians) per steer action
    thrust: np.ndarray  # (2,) speed added (metres per step) per throttle action
    keep: float  # fraction of its speed a vessel keeps each step
    cap: float | None = None  # the speed no vessel exceeds (params.max_speed_m), None without a cap
    noise: float = 0.0  # standard deviation (radians) of the sea's random turn each step (params.heading_noise_deg)

    @classmethod
    def of(cls, params: OceanPlasticCollectionParams) -> "Motion":
        return cls(turn=np.radians(params.turn_rate_deg) * STEER_SIGN,
                   thrust=params.acceleration * np.array([0.0, 1.0]), keep=1.0 - params.drag,
                   cap=params.max_speed_m, noise=np.radians(params.heading_noise_deg))


@lru_cache(maxsize=16)
def _worlds(batch: int) -> np.ndarray:
    """(B, 1) read-only world indices, to pick one agent per world with an index array (B, A)."""
    worlds = np.arange(batch)[:, None]
    worlds.setflags(write=False)
    return worlds


def crossed_border(position: np.ndarray, active: np.ndarray, half_extent: float) -> np.ndarray:
    """(B, A) the paper's test: p_x or p_y beyond +/- the half extent (strictly)."""
    return active & np.logical_or.reduce(np.abs(position) > half_extent, axis=-1)


def move(position: np.ndarray, heading: np.ndarray, speed: np.ndarray, actions: np.ndarray, active: np.ndarray,
         motion: Motion) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Turn, then speed <- speed * (1 - drag) + acceleration * throttle (at most the cap, where the scenario
    sets one), then advance along the new heading.

    actions (B, A, 2): throttle {0, 1}, steer {0 noop, 1 right, 2 left}. Inactive vessels stay put.
    Returns position, heading, speed and ``facing`` = exp(i heading) (B, A) complex, the unit heading.
    """
    turned = wrap_angle(heading + motion.turn[actions[..., 1]])
    speed = speed * motion.keep + motion.thrust[actions[..., 0]]
    if motion.cap is not None:
        speed = np.minimum(speed, motion.cap)
    if all_true(active):
        heading = turned
    else:
        heading = np.where(active, turned, heading)
        speed = np.where(active, speed, 0.0)
    facing = np.exp(1j * heading)
    return position + as_pairs(speed * facing), heading, speed, facing


def drift_heading(heading: np.ndarray, active: np.ndarray, noise: float, rng: np.random.Generator) -> np.ndarray:
    """(B, A) headings each active vessel's turned by a normal draw of standard deviation ``noise`` (radians)."""
    return wrap_angle(heading + np.where(active, rng.normal(0.0, noise, heading.shape), 0.0))


class OceanPlasticSimulator:
    """B worlds of one compiled Ocean Plastic Collection scenario."""

    action_meanings = "throttle {0 do nothing, 1 accelerate}, steer {0 do nothing, 1 turn right, 2 turn left}"
    observation_labels = ("local position x", "local position y", "direction x", "direction y",
                          "closest neighbouring vessel x", "closest neighbouring vessel y")
    observation_stacks = STACKS
    stacked_fields = ("vector", "visual")  # shifted every physics step; the runtime stacks them per decision
    render_fps = 30

    def __init__(self, compiled):
        params: OceanPlasticCollectionParams = compiled.params
        self.params = params
        self.agents = compiled.agents
        self.pollution: PollutionSpec = compiled.generators["pollution"]
        self.spawn: SpawnSpec = compiled.generators["spawn"]
        self.half_extent = self.pollution.half_extent_m
        self.geometry = Geometry(half_extent=self.half_extent, collector_reach=params.collector_reach_m,
                                 collector_half_width=params.collector_half_width_m,
                                 nearby_radius=params.nearby_radius_m, top_speed=params.top_speed_m)
        self.observation_space = spaces.Dict({
            "vector": spaces.Box(-1.0, 1.0, (FRAME * STACKS,), np.float32),
            "visual": spaces.Box(0.0, 1.0, (CAMERA_CELLS, CAMERA_CELLS, STACKS), np.float32),
        })
        self.action_space = spaces.MultiDiscrete([2, 3])
        self.motion = Motion.of(params)
        self.period = compiled.decision_period
        self.cap = params.collect_per_decision  # 0: no cap
        self.sight = np.inf if params.neighbour_sight_m is None else params.neighbour_sight_m

    # -- reset ------------------------------------------------------------------------------------

    def reset(self, rng: np.random.Generator, batch: int) -> OceanState:
        """Heat maps, vessel spawns, then pebbles (in that order of draws, as the pollution preview)."""
        heat = pollution_map(rng, self.pollution, batch)
        position, heading = spawn_vessels(rng, self.spawn, batch, self.agents)
        pebbles = sample_pebbles(rng, heat, self.pollution.pebble_count, self.half_extent)
        field = build_field(pebbles, self.geometry)
        shape = (batch, self.agents)
        speed, active, no = np.zeros(shape), np.ones(shape, bool), np.zeros(shape, bool)
        facing = np.exp(1j * heading)
        sensing = sense(field, position, facing, speed, active, self.geometry, sweeping=None)
        distances = neighbour_distances(position, active)
        closest = distances.min(axis=-1)
        vector = self._vector(position, facing, distances, closest, np.zeros(shape + (FRAME * STACKS,), np.float32))
        visual = self._visual(sensing, heat, position, facing, active,
                              np.zeros(shape + (CAMERA_CELLS, CAMERA_CELLS, STACKS), np.float32))
        zeros = np.zeros(shape, np.int64)
        return OceanState(position=position, heading=heading, speed=speed, active=active, crashed=no,
                          crossed_border=no, collided_vessel=no, closest=closest,
                          collected=zeros, collected_total=zeros, decision_collected=zeros,
                          tick=np.zeros(batch, np.int64), nearby=zeros, nearby_best=zeros, pebbles=field, heat=heat,
                          vector=vector, visual=visual)

    def reset_where(self, state: OceanState, mask: np.ndarray, rng: np.random.Generator) -> OceanState:
        count = int(np.count_nonzero(mask))
        if count == 0:
            return state
        return replace_worlds(state, mask, self.reset(rng, count))

    respawn_where = respawn_where  # single vessels in running worlds: see respawn.py

    # -- step -------------------------------------------------------------------------------------

    def step(self, state: OceanState, actions: np.ndarray, rng: np.random.Generator) -> tuple[OceanState, StepOutcome]:
        p = self.params
        position, heading, speed = state.position, state.heading, state.speed
        if p.crash_outcome == "respawn" and np.count_nonzero(state.crashed):
            position, heading, speed = self._respawn(position, heading, speed, state.crashed, rng)
        active = state.active
        if self.motion.noise > 0:
            heading = drift_heading(heading, active, self.motion.noise, rng)
        before = heading  # a vessel the sea turned at rest sweeps nothing
        position, heading, speed, facing = move(position, heading, speed, np.asarray(actions), active, self.motion)
        border = crossed_border(position, active, self.half_extent)
        distances = neighbour_distances(position, active)
        closest = np.minimum.reduce(distances, axis=-1)
        collided = closest < p.collision_distance_m
        crashed = border | collided
        sweeping = active & ((speed > 0) | (heading != before))  # a collector at rest sweeps nothing
        so_far, allowance = self._allowance(state)
        sensing = sense(state.pebbles, position, facing, speed, active, self.geometry, sweeping, allowance)
        terminated = np.zeros(crashed.shape, bool)
        ends = p.crash_outcome != "respawn"
        if ends and np.count_nonzero(crashed):
            terminated = crashed
            active = active & ~crashed
            speed = np.where(crashed, 0.0, speed)
            distances = neighbour_distances(position, active)
            closest = np.minimum.reduce(distances, axis=-1)
        pebbles = state.pebbles
        if sensing.alive is not pebbles.alive:
            pebbles = replace(pebbles, alive=sensing.alive)
        new = assemble(OceanState,
            position=position, heading=heading, speed=speed, active=active, crashed=crashed,
            crossed_border=border, collided_vessel=collided, closest=closest, collected=sensing.collected,
            collected_total=state.collected_total + sensing.collected,
            decision_collected=so_far + sensing.collected if self.cap else so_far, tick=state.tick + 1,
            nearby=sensing.nearby,
            nearby_best=np.maximum(state.nearby_best, sensing.nearby), pebbles=pebbles,
            heat=state.heat, vector=self._vector(position, facing, distances, closest, state.vector),
            visual=self._visual(sensing, state.heat, position, facing, active, state.visual))
        events = {"crossed_border": border, "collided_with_other_vessel": collided,
                  "collided_with_trash": sensing.collected > 0, "crash_ended_world": self._world_crash(crashed)}
        return new, StepOutcome(terminated=terminated, events=events)

    def _allowance(self, state: OceanState) -> tuple[np.ndarray, np.ndarray | None]:
        """The pebbles each vessel collected earlier in this step's decision (B, A), and how many more it may
        collect this step under params.collect_per_decision (slots,), None without a cap."""
        if not self.cap:
            return state.decision_collected, None
        starts = (state.tick % self.period == 0)[:, None]  # this step begins a decision
        so_far = np.where(starts, 0, state.decision_collected)
        return so_far, np.maximum(self.cap - so_far, 0).reshape(-1)

    def _world_crash(self, crashed: np.ndarray) -> np.ndarray:
        """(B, A) bool: under ``crash_outcome: end_world``, every vessel of a world in which one crashed this step
        (a world event: the tasks' ``ends_on`` ends the world's episode on it); never under the other outcomes."""
        if self.params.crash_outcome != "end_world":
            return np.zeros(crashed.shape, bool)
        return np.repeat(crashed.any(axis=1, keepdims=True), crashed.shape[1], axis=1)

    def _respawn(self, position, heading, speed, crashed, rng):
        """Crashed vessels restart at rest with a random heading at the best of a few random spawn
        points: the one farthest from every other vessel."""
        agents = self.agents
        slots = np.flatnonzero(crashed.reshape(-1))
        world, agent = np.divmod(slots, agents)
        reach = self.spawn.half_extent_m - self.spawn.border_margin_m
        trials = rng.uniform(-reach, reach, (slots.size, self.params.respawn_candidates, 2))
        others = position[world]  # (n, A, 2)
        gap = np.hypot(*np.moveaxis(trials[:, :, None, :] - others[:, None, :, :], -1, 0))  # (n, K, A)
        gap = np.where((np.arange(agents) == agent[:, None])[:, None, :], np.inf, gap)
        best = np.argmax(gap.min(axis=2), axis=1)
        position, heading, speed = position.copy(), heading.copy(), speed.copy()
        position[world, agent] = trials[np.arange(slots.size), best]
        heading[world, agent] = rng.uniform(-np.pi, np.pi, slots.size)
        speed[world, agent] = 0.0
        return position, heading, speed

    # -- observations ------------------------------------------------------------------------------

    def _vector(self, position: np.ndarray, facing: np.ndarray, distances: np.ndarray, closest: np.ndarray,
                previous: np.ndarray) -> np.ndarray:
        """(B, A, 12) float32: this step's frame (position / H, (cos, sin) heading, closest active
        vessel's position / H, or (0, 0) without one or past params.neighbour_sight_m), then the previous physics
        step's frame (at a decision period above 1 the runtime puts the previous decision's there:
        :mod:`hivex_dsl.sim.stacking`). ``distances`` (B, A, A) from :func:`neighbour_distances`, ``closest`` (B, A)
        their minimum over the last axis."""
        local = clamp(position * (1.0 / self.half_extent), -1.0, 1.0)
        neighbour = local[_worlds(len(position)), distances.argmin(axis=-1)]
        out = np.empty(previous.shape, np.float32)
        out[..., 0:2] = local
        out[..., 2:4] = as_pairs(facing)
        out[..., 4:6] = neighbour * (np.isfinite(closest) & (closest <= self.sight))[..., None]
        out[..., FRAME:] = previous[..., :FRAME]
        return out

    def _visual(self, sensing: Sensing, heat: np.ndarray, position: np.ndarray, facing: np.ndarray,
                active: np.ndarray, previous: np.ndarray) -> np.ndarray:
        """(B, A, 25, 25, 2) float32: trash density, newest first (stacked as :meth:`_vector`'s frames are):
        min(1, count / camera_full_count) of the pebbles, or the heat map's (:func:`heat_camera`), as
        params.camera_source says."""
        if self.params.camera_source == "heat_map":
            density = heat_camera(heat, position, facing, active, self.half_extent)
        elif self.params.camera_source == "blank":
            density = np.zeros(previous.shape[:-1], np.float32)
        else:
            full = self.params.camera_full_count
            density = sensing.camera.astype(np.float32)
            np.minimum(density, full, out=density)
            density *= np.float32(1.0 / full)
        out = np.empty(previous.shape, np.float32)
        out[..., 0] = density
        out[..., 1] = previous[..., 0]
        return out

    def observe(self, state: OceanState) -> dict[str, np.ndarray]:
        """The state's own observation arrays (built once per step in ``step``), read-only: an in-place edit
        would change the older stack of the next observation, so it raises instead."""
        return {"vector": read_only(state.vector), "visual": read_only(state.visual)}

    state_components = state_components  # the global state's world facts: see global_state.py
    world_state = world_state

    def render(self, state: OceanState, index: int) -> np.ndarray:
        from .render import draw_ocean

        return draw_ocean(state, index, self.params, self.half_extent)
