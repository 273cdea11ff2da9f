"""Drone-Based Reforestation as a batched NumPy simulator (no Python loop over worlds or drones in step).

Each world: a terrain (procgen terrain, scaled to the 400 m world), an existing forest (procgen
forest), the drone station at the centre on flattened ground, and the rasters derived from them
at reset: distances to the forest (the hidden fertility field) and the camera's grayscale map.
"""

from __future__ import annotations

import math

import numpy as np
from gymnasium import spaces

from ...base.numeric import all_true, clamp
from ...runtime.batched import StepOutcome
from ...sim.batching import evolve, read_only, replace_worlds
from ...sim.cameras import blank_images
from ...sim.procgen.terrain import TerrainSpec, generate_terrain
from ...sim.procgen.wind import wrap_angle
from ...sim.spaces import toggle_mask
from .camera import STATION_GRAY, TREE_GRAY, Raster, camera_images, ground_shade, stamp_disks, to_byte
from ...sim.grids import GridSet, interpolation_matrix, sample_bilinear, terrain_grid
from .fertility import FAR_M, fertility, forest_grid, nearest_new_tree_distance, tree_distance_raster
from .global_state import state_components, world_state
from .forest import ReforestationForestSpec, place_reforestation_forest
from .params import DroneBasedReforestationParams
from .planting import alive_only, plant, running_back, running_back_fields, wanted_drops
from .respawn import respawn_where
from .types import STATION_PAD_M, VECTOR_SIZE, DroneState, Flight

# [ours] Group Up's drones start scattered (drones that start together would be grouped from the first step). [orig]
# Pick-up Seed's start at the station, as Explore Furthest's, against the paper's text ("the initial position of
# drones is random"): the first training points of the two tasks' pages are identical in every statistic (issue 52;
# the reward table's note "Pick-up Seed's start and the returns that reload"). Drop Seed's start at the station too.
RANDOM_SPAWN_TASKS = ("group_up",)
# [orig] The tasks whose station is inert for the Recharge Energy Count: their pages log 0 at every summary point and
# level, the untrained policy's first included, whose drones start on the pad (the main task's first point: 41
# docked steps a drone-episode); elsewhere the count runs from the first step (the reward table's notes).
INERT_STATION_TASKS = ("find_closest_tree", "find_high_potential_area", "find_high_terrain")
# [orig] Pick-up Seed's drones start without a seed (they come back for one: the original's page logs no drop), and
# so do those of Find Closest Tree and the three best-so-far tasks: their pages log no drop at any point, the
# untrained policy's first included (which drops 0.81 seeds a drone-episode in the main task), and their returns
# are their statistics less one seedless battery (the reward table's note "Episode endings and the battery's
# race"); [ours] Group Up's too
SEEDLESS_START_TASKS = ("pick_up_seed", "group_up", "find_closest_tree", "find_high_potential_area",
                        "find_high_terrain", "explore_furthest")


def returns_reload(task_name: str) -> bool:
    """[orig] Whether a return hands over a seed and a full battery: only where the drones start with a seed.
    Pick-up Seed's and Explore Furthest's drones return many times yet their pages log no drop at any point and run
    out in about 2/3 of drone-episodes, the last-step run-out of one seedless battery never refilled (the same note).
    """
    return task_name not in SEEDLESS_START_TASKS


class DroneReforestationSimulator:
    """B worlds of one compiled Drone-Based Reforestation scenario."""

    action_meanings = ("continuous: [0] throttle (0 or less hover .. 1 forward; -1 backward with params.throttle "
                       "'signed'), [1] steer (-1 right .. 1 left), "
                       "[2] up/down (-1 down .. 1 up); discrete: [0] drop seed {0 do nothing, 1 drop seed}")
    observation_labels = ("distance to ground", "local position x", "local position y", "local position z",
                          "direction x", "direction y", "direction z", "drone station height", "holding seed",
                          "energy level")
    observation_stacks = 2
    stacked_fields = ("frames",)  # shifted every physics step; the runtime stacks them per decision
    render_fps = 20

    def __init__(self, compiled):
        p: DroneBasedReforestationParams = compiled.params
        self.params = p
        self.agents = compiled.agents
        self.time_limit = compiled.episode_length  # physics steps
        self.terrain_spec: TerrainSpec = compiled.generators["terrain"]
        self.forest_spec: ReforestationForestSpec = compiled.generators["forest"]
        self.random_spawn = compiled.task_name in RANDOM_SPAWN_TASKS
        self.start_with_seed = compiled.task_name not in SEEDLESS_START_TASKS
        self.return_reloads = returns_reload(compiled.task_name)
        self.station_logs_docking = compiled.task_name not in INERT_STATION_TASKS
        t, f = self.terrain_spec, self.forest_spec
        self.half = t.extent_m / 2.0
        self.terrain_grid = terrain_grid(t)
        self.forest_grid = forest_grid(f)
        self._below = GridSet((self.terrain_grid, self.forest_grid))  # sampled under every drone each step
        self.raster = Raster.covering(self.half, p.camera_cell_m)
        self._to_raster = interpolation_matrix(self.raster.centres(), self.terrain_grid)
        self.tree_reach_m = max(p.max_tree_distance_m, p.close_tree_radius_m)
        self._turn = np.radians(p.turn_rate_deg)
        self._control_scale = np.array([p.drone_speed_m, self._turn, p.climb_speed_m])  # per unit of each control
        self._frame_scale = np.array([self.half, self.half, p.height_bound_m])
        # battery share a step costs, indexed by holding a seed (0 no, 1 yes)
        self._depletion = np.array([1.0 / p.energy_steps_without_seed, 1.0 / p.energy_steps_with_seed])
        # steps a docking lasts: the time to charge an empty battery, whatever this one held
        self.charging_cycle = int(np.ceil(1.0 / p.charge_per_step - 1e-9))
        self._view = math.tan(math.radians(p.camera_fov_deg) / 2.0)
        gain = p.vector_observation_gain
        vector = spaces.Box(-gain, gain, (VECTOR_SIZE * self.observation_stacks,), np.float32)
        visual = spaces.Box(0.0, 1.0, (16, 16, 1), np.float32)
        self.observation_space = spaces.Dict({"vector": vector, "visual": visual})
        self.action_space = spaces.Dict({"continuous": spaces.Box(-1.0, 1.0, (3,), np.float32),
                                         "discrete": spaces.MultiDiscrete([2])})

    # ------------------------------------------------------------------ reset
    def _world(self, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """One world's terrain heights (n, n), existing trees per forest cell (m, m, 2) and station (3,)."""
        terrain = generate_terrain(rng, self.terrain_spec)
        forest = place_reforestation_forest(rng, self.forest_spec, terrain)
        m = self.forest_spec.cells
        trees = np.full((m, m, 2), FAR_M, np.float32)
        trees[forest.cell_index[:, 0], forest.cell_index[:, 1]] = forest.positions
        station = np.append(terrain.village, terrain.height_at(terrain.village))
        return terrain.heights, trees, station

    def _cameras(self, heights: np.ndarray, trees: np.ndarray, station: np.ndarray) -> np.ndarray:
        """(B, R, R) uint8 camera rasters: shaded ground, existing trees, station pad."""
        batch, raster = len(heights), self.raster
        ground = self._to_raster @ heights @ self._to_raster.T  # bilinear terrain height at every cell centre
        rasters = to_byte(ground_shade(ground, self.params.height_bound_m))
        world, row, col = np.nonzero(trees[..., 0] < FAR_M)
        stamp_disks(rasters, raster, world, trees[world, row, col].astype(np.float64), self.params.tree_crown_radius_m,
                    TREE_GRAY)
        stamp_disks(rasters, raster, np.arange(batch), station[:, :2], STATION_PAD_M, STATION_GRAY)
        return rasters

    def _spawn(self, rng: np.random.Generator, heights: np.ndarray, station: np.ndarray):
        """Positions (B, A, 3), headings (B, A) and whether the drones start with a seed."""
        p, batch, count = self.params, len(heights), self.agents
        if self.random_spawn:
            margin = 0.9 * self.half
            xy = rng.uniform(-margin, margin, (batch, count, 2))
            offset = xy - station[:, None, :2]
            radius = np.hypot(offset[..., 0], offset[..., 1])
            push = np.maximum(p.random_spawn_min_distance_m, radius) / np.maximum(radius, 1e-9)
            xy = np.clip(station[:, None, :2] + offset * push[..., None], -margin, margin)
            low = sample_bilinear(heights, self.terrain_grid, xy) + p.min_clearance_m
            z = low + rng.random((batch, count)) * (p.height_bound_m - low)
        else:
            angles = rng.uniform(0.0, 2.0 * np.pi, (batch, 1)) + 2.0 * np.pi * np.arange(count) / count
            xy = station[:, None, :2] + spawn_ring_radius(p, count) * np.stack([np.cos(angles), np.sin(angles)], axis=-1)
            z = np.broadcast_to(station[:, None, 2] + p.spawn_altitude_m, (batch, count))
        ground = sample_bilinear(heights, self.terrain_grid, xy)
        z = np.clip(z, ground + p.min_clearance_m, p.height_bound_m)
        heading = rng.uniform(-np.pi, np.pi, (batch, count))
        return np.concatenate([xy, z[..., None]], axis=-1), heading, ground, self.start_with_seed

    def reset(self, rng: np.random.Generator, batch: int) -> DroneState:
        n, m = self.terrain_grid.n, self.forest_grid.n
        worlds = [self._world(rng) for _ in range(batch)]
        heights, trees, station = (np.stack(parts) for parts in zip(*worlds)) if batch else (
            np.zeros((0, n, n)), np.zeros((0, m, m, 2), np.float32), np.zeros((0, 3)))
        occupied = trees[..., 0] < FAR_M
        position, heading, ground, holding = self._spawn(rng, heights, station)
        shape = (batch, self.agents)
        zeros, false = np.zeros(shape), np.zeros(shape, bool)
        distance, reach = self._station_distances(position, station)
        tree_distance = tree_distance_raster(occupied, self.forest_grid.cell, self.tree_reach_m)
        _, det = self._below.sample((heights, tree_distance), position[..., :2])
        p = self.params
        state = DroneState(
            heights=heights, tree_distance=tree_distance,
            tree_xy=trees, station=station, camera=self._cameras(heights, trees, station),
            new_trees=np.full((batch, self.params.new_tree_capacity, 2), FAR_M, np.float32),
            new_quality=np.zeros((batch, self.params.new_tree_capacity), np.float32),
            new_count=np.zeros(batch, np.int64), steps_left=np.full(batch, self.time_limit, np.int64),
            position=position, heading=heading, ground=ground,
            energy=np.ones(shape), holding=np.full(shape, holding), alive=np.ones(shape, bool),
            inside=distance <= p.charge_radius_m, logs_docking=np.full(distance.shape, self.station_logs_docking),
            docked_steps=np.zeros(shape, np.int64), away=(distance >= p.return_min_distance_m) & self.random_spawn,
            # best-so-far potential and distance from the spawn state: the first step pays only for what it finds;
            # the height's from 0, as the paper's h_old (the reward table's notes: the original's records read so)
            best_fertility=fertility(det, p.min_tree_distance_m, p.max_tree_distance_m),
            best_height=zeros.copy(), best_distance=np.minimum(reach, self.half), back_active=false,
            back_init=zeros, back_best=np.zeros(shape, np.int64), back_multiplier=zeros,
            flown=zeros, dropped=false, seed_reward=zeros, distance_reward=zeros, drop_tree_distance=zeros,
            returned=false,
            found_tree=false, running_back=zeros, frames=np.zeros(shape + (2 * VECTOR_SIZE,), np.float32))
        flight = Flight(position, position[..., :2], position[..., 2], heading,
                        np.stack([np.cos(heading), np.sin(heading)], axis=-1), ground, None)
        # the older stack starts as zeros, as ML-Agents' StackingSensor starts (and ResetSensors resets) its buffer
        return evolve(state, frames=self._frames(state.frames, flight, station, state.holding, state.energy))

    def reset_where(self, state: DroneState, mask: np.ndarray, rng: np.random.Generator) -> DroneState:
        return replace_worlds(state, mask, self.reset(rng, int(np.count_nonzero(mask))))

    respawn_where = respawn_where  # single drones in running worlds: see respawn.py

    # ------------------------------------------------------------------ step
    @staticmethod
    def _station_distances(position: np.ndarray, station: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(B, A) distance of each drone from its station in 3D, and horizontally."""
        gap = position - station[:, None, :]
        square = gap * gap  # the 3D sum stays einsum's (its order of summation); two squares sum alike in any order
        return np.sqrt(np.einsum("bad,bad->ba", gap, gap)), np.sqrt(square[..., 0] + square[..., 1])

    def _frames(self, previous: np.ndarray, flight: Flight, station: np.ndarray, holding: np.ndarray,
                energy: np.ndarray) -> np.ndarray:
        """(B, A, 20) float32: this step's normalised vector observation, then the previous physics step's (at a
        decision period above 1 the runtime puts the previous decision's there: :mod:`hivex_dsl.sim.stacking`)."""
        bound = self.params.height_bound_m
        frames = np.empty(previous.shape, np.float32)
        frames[..., VECTOR_SIZE:] = previous[..., :VECTOR_SIZE]
        frames[..., 0] = (flight.z - flight.ground) / bound  # in (0, 1]: between the ground and the bound
        frames[..., 1:4] = flight.position / self._frame_scale  # x / half, y / half, z / bound
        frames[..., 4:6] = flight.direction
        frames[..., 6] = 0.0  # a level drone's forward vector has no vertical part
        frames[..., 7] = station[:, None, 2] / bound
        frames[..., 8] = holding
        frames[..., 9] = energy
        return frames

    def _fly(self, state: DroneState, actions, alive: np.ndarray | None) -> Flight:
        """Where the drones are after this step's controls. Frozen drones (``alive`` (B, A) false; None: all
        alive) stay put; a drone never goes below min_clearance_m above the ground or above the bound."""
        p = self.params
        controls = np.asarray(actions["continuous"], np.float64)
        if alive is not None:
            controls = controls * alive[..., None]
        moves = controls * self._control_scale  # (B, A, 3) metres forward, radians turned, metres climbed
        if p.throttle == "forward":
            np.maximum(moves[..., 0], 0.0, out=moves[..., 0])
        heading = wrap_angle(state.heading + moves[..., 1])
        direction = np.empty(heading.shape + (2,))
        direction[..., 0] = np.cos(heading)
        direction[..., 1] = np.sin(heading)
        xy = clamp(state.position[..., :2] + moves[..., :1] * direction, -self.half, self.half)
        ground, det = self._below.sample((state.heights, state.tree_distance), xy)
        z = clamp(state.position[..., 2] + moves[..., 2], ground + p.min_clearance_m, p.height_bound_m)
        position = np.empty(state.position.shape)
        position[..., :2] = xy
        position[..., 2] = z
        return Flight(position, xy, z, heading, direction, ground, det)

    _wanted_drops = wanted_drops  # the seed's drop and the running back after it: see planting.py
    _plant = plant
    _running_back = running_back

    def _energy(self, state: DroneState, docked: np.ndarray, alive: np.ndarray | None) -> np.ndarray:
        """(B, A) battery after this step: ``charge_per_step`` more (at most full) when charging (``docked``, alive
        within the charge radius, on a return: away since its last one), else less the step's cost (with or without
        a seed) for a living drone; 0 once (nearly) empty. A drone on the pad it started on, or lingering at the
        station after its return, is not charging: its battery drains there as anywhere (the reward table's notes,
        "Episode endings and the battery's race"), as does every docked drone of a task whose returns do not reload
        (``return_reloads`` false: its drones start seedless)."""
        cost = self._depletion[state.holding.astype(np.intp)]
        energy = state.energy - (cost if alive is None else cost * alive)
        if self.return_reloads:
            np.putmask(energy, docked & state.away, np.minimum(state.energy + self.params.charge_per_step, 1.0))
        np.putmask(energy, energy <= 1e-9, 0.0)
        return energy

    def step(self, state: DroneState, actions, rng: np.random.Generator) -> tuple[DroneState, StepOutcome]:
        """actions: continuous (B, A, 3) throttle, steer, up/down; discrete (B, A, 1) drop seed."""
        p, shape = self.params, state.alive.shape
        alive = None if all_true(state.alive) else state.alive  # None: all (most steps)
        flight = self._fly(state, actions, alive)
        distance, reach = self._station_distances(flight.position, state.station)
        inside = distance <= p.charge_radius_m
        outside = ~inside
        drops = self._wanted_drops(state, actions, distance, alive)
        dropping = np.count_nonzero(drops) > 0
        if dropping:
            drops, r_s, r_d, det, new_count = self._plant(state, drops, flight.position)
        else:
            r_s, r_d, det, new_count = np.zeros(shape), np.zeros(shape), np.zeros(shape), state.new_count
        back, paid_back = {}, np.zeros(shape)
        if dropping or np.count_nonzero(state.back_active):
            increment = (distance * (1.0 / p.running_back_step_m)).astype(np.int64)  # floor: distances are >= 0
            paid_back = self._running_back(state, increment, alive)
            back = running_back_fields(state, drops, distance, increment, outside, r_s, r_d, dropping)

        docked = alive_only(inside, alive)
        docked_steps = np.where(docked, state.docked_steps + 1, 0)
        energy = self._energy(state, docked, alive)
        # back, and docked a whole charging cycle: the seed is taken then, the battery full whatever it held
        returned = docked & state.away & (docked_steps >= self.charging_cycle)
        returning = np.count_nonzero(returned) > 0  # rare: most steps skip the ops with it
        reloading = returning and self.return_reloads
        if reloading:
            np.putmask(energy, returned, 1.0)
        holding = (state.holding & ~drops) if dropping else state.holding
        holding = holding | returned if reloading else holding
        away = state.away | (distance >= p.return_min_distance_m)
        # the path since the last seed taken, this step's leg included (a drop reads it); a return starts it anew
        flown = state.flown + _zero_unless_alive(np.linalg.norm(flight.position - state.position, axis=-1), alive)
        new = evolve(
            state, new_count=new_count, steps_left=state.steps_left - 1, position=flight.position,
            heading=flight.heading, ground=flight.ground,
            energy=energy, holding=holding, alive=energy > 0.0, inside=inside,
            docked_steps=docked_steps, away=away & ~returned if returning else away,
            flown=np.where(returned, 0.0, flown) if returning else flown,
            best_fertility=self._best_fertility(state, flight.xy, flight.tree_distance, alive),
            best_height=np.maximum(state.best_height, _zero_unless_alive(flight.z, alive)),
            best_distance=np.maximum(state.best_distance, _zero_unless_alive(np.minimum(reach, self.half), alive)),
            dropped=drops, seed_reward=r_s, distance_reward=r_d, drop_tree_distance=det, returned=returned,
            found_tree=alive_only(flight.tree_distance <= p.close_tree_radius_m, alive), running_back=paid_back,
            frames=self._frames(state.frames, flight, state.station, holding, energy), **back)
        events = {"returned_to_station": returned, "found_close_tree": new.found_tree, "planted_tree": drops}
        return new, StepOutcome(terminated=~new.alive, events=events)

    def _best_fertility(self, state: DroneState, xy: np.ndarray, det: np.ndarray, alive: np.ndarray | None
                        ) -> np.ndarray:
        """pot_old after this step: the fertility here counts if it beats the best so far and no planted tree
        is within dot_min."""
        p = self.params
        here = fertility(det, p.min_tree_distance_m, p.max_tree_distance_m)
        better = alive_only(here > state.best_fertility, alive)
        if not np.count_nonzero(better):
            return state.best_fertility
        best = np.where(better, here, state.best_fertility)
        count = int(state.new_count.max())
        if count:
            world, agent = np.nonzero(better)
            crowded = nearest_new_tree_distance(state.new_trees[:, :count], world, xy[world, agent]) < p.min_tree_distance_m
            best[world[crowded], agent[crowded]] = state.best_fertility[world[crowded], agent[crowded]]
        return best

    # ------------------------------------------------------------------ observe / render
    def camera_half_width(self, state: DroneState) -> np.ndarray:
        """(B, A) metres: half the side of each camera's square footprint on the ground."""
        height = state.position[..., 2] - state.ground
        return np.maximum(self.params.camera_min_half_width_m, height * self._view)

    def observe(self, state: DroneState) -> dict[str, np.ndarray]:
        """vector (B, A, 20) float32 (two stacks, newest first; the frames times vector_observation_gain); visual
        (B, A, 16, 16, 1) float32."""
        if self.params.cameras_render:
            visual = camera_images(state.camera, self.raster, state.position[..., :2], self.camera_half_width(state))
        else:
            visual = blank_images(state.position.shape[:2] + self.observation_space["visual"].shape)
        return {"vector": read_only(self.vector_observation(state)), "visual": visual}

    def vector_observation(self, state: DroneState) -> np.ndarray:
        """(B, A, 20) float32: the frames times params.vector_observation_gain, as the drones observe them."""
        gain = self.params.vector_observation_gain
        return state.frames if gain == 1.0 else state.frames * np.float32(gain)

    def action_mask(self, state: DroneState) -> np.ndarray:
        """(B, A, 2) bool: the drop is open to a living drone that holds a seed at least drop_min_distance_m from
        its station, where a drop plants one (the stores aside); read from the original's Entropy panels
        (rewards/drone_based_reforestation.yaml, 'The drop's action mask')."""
        distance, _ = self._station_distances(state.position, state.station)
        return toggle_mask(state.alive & state.holding & (distance >= self.params.drop_min_distance_m))

    state_components = state_components  # the global state's world facts: see global_state.py
    world_state = world_state

    def render(self, state: DroneState, index: int) -> np.ndarray:
        from .render import draw_reforestation

        return draw_reforestation(state, index, self)


def spawn_ring_radius(p: DroneBasedReforestationParams, count: int) -> float:
    """Radius of the circle the drones start on: spawn_radius_m, widened so that neighbours on it start at least
    spawn_gap_m apart (with 12 drones on a 6 m circle they would start 3.1 m apart, grouped up from the start)."""
    if count < 2:
        return p.spawn_radius_m
    return max(p.spawn_radius_m, p.spawn_gap_m / (2.0 * np.sin(np.pi / count)))


def _zero_unless_alive(values: np.ndarray, alive: np.ndarray | None) -> np.ndarray:
    """``values`` (B, A) where the drone is alive, else 0; ``alive`` None stands for every drone alive."""
    return values if alive is None else np.where(alive, values, 0.0)
