"""Physical constants of Drone-Based Reforestation and the presets of its world generators.

[paper] values come from the paper's spec table and reward equations, [ours] are this project's
defaults where the paper and the original release are silent (ENVIRONMENTS.md). The world's size,
terrain and forest are not params: they are the "terrain" and "forest" generator slots, whose
presets are at the end of this module (the shared AWS/WRM terrain recipe scaled to the 400 m world; the
forest is this environment's own patch field, forest.py).
"""

from __future__ import annotations

from typing import Any, ClassVar, Literal

import numpy as np
from pydantic import Field, model_validator

from ...lang.spec.common import StrictModel
from ...sim.cameras import CameraParams
from ...sim.procgen.terrain import TerrainSpec, terrain_spec_for_level
from .forest import ReforestationForestSpec


class DroneBasedReforestationParams(CameraParams):
    ADDED_FIELDS: ClassVar[dict[str, Any]] = {"vector_observation_gain": 1.0}  # what locks and checkpoints saw before

    height_bound_m: float = Field(65.0, ge=10.0, le=100.0, description=(
        "[orig, fitted] Drones fly no higher than this (metres above sea level); heights are normalised by it. The "
        "paper gives 40 m, but the original's Find High Terrain records put its drones higher in the frame its "
        "height reward reads: published 44.5-47.2 m at every terrain level, summary points of the training runs up "
        "to 53.5-56.3 m (mean of three runs) and 58.3-62.7 m (their band); 65 m is the first 5 m above every point "
        "(the reward table's notes)."))
    vector_observation_gain: float = Field(3.0, gt=0.0, le=10.0, description=(
        "[records, fitted] The vector observation (both stacks, every component) is sent times this gain, so a "
        "decision changes it that much more. How the original's release scaled its observations is not on record "
        "(its README: 'Normalized: True'); its training records say its networks saw larger changes than this "
        "toolkit's normalised frames (gain 1). At 1 the curiosity module's forward loss lies 5-15 times under the "
        "original's panel all through training, its Curiosity Reward a drone-episode is a fifth to a tenth of the "
        "original's, and PPO learns a reloading loop the original's drones never did; at 3 the forward loss meets "
        "the original's over its first 100k agent-steps and the drones drop one seed and run out, as the "
        "original's did (the reward table's notes 'The curiosity losses', 'The observation's scale, probed' and "
        "'The vector observation's gain'). The global state holds the vector as the drones observe it."))
    drone_speed_m: float = Field(1.0, gt=0.0, le=2.0, description=(
        "[ours] Horizontal metres flown per step at full throttle (at most 2 m so a step never crosses two "
        "2.5 m running-back increments)."))
    throttle: Literal["forward", "signed"] = Field("forward", description=(
        "[orig, fitted] How the throttle control a in [-1, 1] moves a drone: 'forward' flies max(a, 0) x drone_speed_m "
        "forward (a negative throttle hovers), 'signed' flies a x drone_speed_m (-1 backwards; this toolkit's reading "
        "until issue 52). The original's untrained drones leave the station and do not drift back (the seedless "
        "tasks' first training points: no docking, 118 m explored, potential 0.52), which a zero-mean signed "
        "throttle cannot do (the reward table's note \"Decided (issue 52, session 31)\")."))
    climb_speed_m: float = Field(0.5, gt=0.0, le=1.0, description="[ours] Metres climbed or sunk per step at up/down +/-1.")
    turn_rate_deg: float = Field(6.0, gt=0.0, le=45.0, description="[ours] Degrees turned per step at steer +/-1.")
    min_clearance_m: float = Field(1.0, ge=0.1, le=5.0, description=(
        "[ours] Lowest flying height above the ground; a drone flying into a slope is lifted over it."))
    charge_radius_m: float = Field(7.5, ge=1.0, le=50.0, description=(
        "[paper] d_charge: within this 3D distance of the station a drone recharges and picks up a seed."))
    charge_per_step: float = Field(0.1, gt=0.0, le=1.0, description=(
        "[ours, fitted] Battery share a docked drone regains each step on a return (empty to full in 10 steps; 1 "
        "refills at once), in the tasks whose drones start with a seed (main, Drop Seed: elsewhere a return hands "
        "over no seed and no charge, the reward table's notes); a drone that has not been return_min_distance_m "
        "away since its last return (on the pad it "
        "started on, or lingering after its return) is not charging and drains as anywhere. A docking lasts that "
        "whole charging cycle, 1 / charge_per_step steps, whatever the battery held: "
        "the return (the seed pick-up and its reward) is made on its last step, the battery full. Fitted to the "
        "published Recharge Energy Count, about 10 docked steps a return in every task whose drones return, with "
        "the battery nearly empty (main task) or nearly full (Drop Seed, Pick-up Seed; the reward table's notes)."))
    return_min_distance_m: float = Field(15.0, ge=1.0, le=200.0, description=(
        "[ours] A visit to the station counts as a return (seed pick-up and its reward) only if the drone was "
        "at least this far from the station since its last return, so hovering across the charge radius pays nothing."))
    drop_min_distance_m: float = Field(17.5, ge=1.0, le=100.0, description=(
        "[orig, fitted] A drone can drop its seed only at least this far (3D) from the station; nearer, the drop "
        "action does nothing. The original masks the drop but on a few decisions of a seed holder's episode (its "
        "first training points' entropy) and its untrained drones dropped about 19 m out (the reward table's "
        "note \"Decided (issue 52, session 31)\"). At least charge_radius_m."))
    spawn_radius_m: float = Field(6.0, ge=0.0, le=50.0, description=(
        "[ours] Drones start evenly spaced on a circle of this radius around the station, inside the charge radius "
        "(widened for many drones, see spawn_gap_m)."))
    spawn_gap_m: float = Field(10.0, ge=0.0, le=50.0, description=(
        "[ours] Neighbours on the spawn circle start at least this far apart (twice the 5 m Group-up distance): "
        "with more than 3 drones the circle grows beyond spawn_radius_m, and beyond the charge radius from 5 "
        "drones on, so that no task's drones are grouped (+10 a step in Group Up) from the start."))
    spawn_altitude_m: float = Field(2.0, ge=0.1, le=20.0, description="[ours] Starting height above the station.")
    random_spawn_min_distance_m: float = Field(20.0, ge=0.0, le=150.0, description=(
        "[ours] In the Pick-up Seed and Group Up sub-tasks drones start at random, at least this far from the station."))
    energy_steps_with_seed: int = Field(1000, ge=10, le=1_000_000, description=(
        "[paper] A full battery lasts this many steps carrying a seed (episode length / 2); the Deplete Energy "
        "Holding Seed penalty is -1 / this."))
    energy_steps_without_seed: int = Field(2000, ge=10, le=1_000_000, description=(
        "[paper] A full battery lasts this many steps without a seed (episode length); the Deplete Energy No Seed "
        "penalty is -1 / this."))
    min_tree_distance_m: float = Field(2.5, ge=0.0, le=20.0, description=(
        "[paper] dot_min: a seed earns its quality only at least this far from existing and from new trees."))
    max_tree_distance_m: float = Field(75.0, ge=5.0, le=150.0, description=(
        "[paper] dot_max: a seed earns its quality only within this distance of an existing tree; the quality falls "
        "linearly from 1 at dot_min to 0 here."))
    running_back_step_m: float = Field(2.5, ge=0.5, le=20.0, description=(
        "[paper] s: the incremental running-back reward is paid per this many metres closer to the station."))
    group_distance_m: float = Field(5.0, ge=0.5, le=50.0, description=(
        "[paper] d_thresh: Group-up pays while a neighbour is closer than this."))
    close_tree_radius_m: float = Field(20.0, ge=1.0, le=100.0, description=(
        "[paper] Find Close Tree pays once an existing tree is within this horizontal distance."))
    camera_fov_deg: float = Field(90.0, ge=10.0, le=160.0, description=(
        "[ours] Field of view of the downward camera: its square footprint has half width "
        "height-above-ground x tan(fov / 2)."))
    camera_min_half_width_m: float = Field(2.0, ge=0.5, le=50.0, description=(
        "[ours] Smallest camera footprint half width (when skimming the ground)."))
    camera_cell_m: float = Field(2.0, ge=0.5, le=10.0, description=(
        "[ours] Cell size of the per-world grayscale raster the camera samples (terrain shade, trees, station)."))
    tree_crown_radius_m: float = Field(1.5, ge=0.1, le=10.0, description=(
        "[ours] Radius of a tree as the camera and the renderer draw it."))
    new_tree_capacity: int = Field(1024, ge=16, le=65_536, description=(
        "[ours] Most trees planted per world and episode; once a world holds this many, its drones keep their seeds."))

    @model_validator(mode="after")
    def _consistent(self) -> "DroneBasedReforestationParams":
        if (self.spawn_radius_m**2 + self.spawn_altitude_m**2) ** 0.5 >= self.charge_radius_m:
            raise ValueError(f"the spawn point (radius {self.spawn_radius_m}, altitude {self.spawn_altitude_m}) must lie "
                             f"within charge_radius_m ({self.charge_radius_m}) of the station so drones start there")
        if self.min_tree_distance_m >= self.max_tree_distance_m:
            raise ValueError(f"min_tree_distance_m ({self.min_tree_distance_m}) must be less than "
                             f"max_tree_distance_m ({self.max_tree_distance_m})")
        if self.drop_min_distance_m < self.charge_radius_m:
            raise ValueError(f"drop_min_distance_m ({self.drop_min_distance_m}) must be at least charge_radius_m "
                             f"({self.charge_radius_m}): no seed is dropped at the station")
        if self.return_min_distance_m <= self.charge_radius_m:
            raise ValueError(f"return_min_distance_m ({self.return_min_distance_m}) must exceed charge_radius_m "
                             f"({self.charge_radius_m}) or a drone could return without leaving")
        return self


# ---------------------------------------------------------------------------------------- world presets
# [ours] The shared island recipe (241 cells over 1666 m, noise scale 40: about 6 noise lattice units
# across) drawn on 81 x 81 cells over the paper's 400 m world (5 m cells) with noise scale 13.5, so
# the same number of hills fit across; heights use 1 m per level multiplier unit instead of 7, so
# peaks are 8 m at level 1 and 30 m at level 10, below the paper's 40 m height bound, and the levels keep
# their relative steepness (peak height grows linearly with the multiplier, as in the original).
# The station stands at the centre on flattened ground (the recipe's village, pinned there).
DBR_TERRAIN = dict(size=81, extent_m=400.0, noise_scale=13.5, metres_per_multiplier=1.0,
                   village_half_range_m=0.0, village_flat_radius_m=10.0, village_blend_m=15.0)

# The existing forest: DBR's own patch field (forest.py), the same rule at every terrain level; the defaults of
# ReforestationForestSpec are fitted to the original's main-task drop records (the reward table's note "The
# existing forest fitted to the original's drop records").
DBR_FOREST = dict(cells=100, spacing_m=4.0, half_extent_m=200.0, jitter_m=1.0)


def terrain_preset(level: int | None) -> TerrainSpec:
    """The terrain of a terrain level (1-10) scaled to the Drone-Based Reforestation world."""
    return terrain_spec_for_level(1 if level is None else level, **DBR_TERRAIN)


def forest_preset(level: int | None) -> ReforestationForestSpec:
    """The existing forest: the same patch field at every terrain level, on the 100 x 100 grid of 4 m cells."""
    return ReforestationForestSpec(**DBR_FOREST)


def world_problems(compiled) -> list[tuple[tuple, str]]:
    """The terrain and forest must describe the paper's world the rewards are scaled to."""
    t, f, p = compiled.generators["terrain"], compiled.generators["forest"], compiled.params
    problems = []
    if t.village_half_range_m != 0.0:
        problems.append((("generators", "terrain", "village_half_range_m"),
                         f"{t.village_half_range_m:g}: the drone station sits at the centre of the world; expected 0"))
    if t.extent_m > 400.0:
        problems.append((("generators", "terrain", "extent_m"),
                         f"{t.extent_m:g} m: the world may be at most the paper's 400 m across (half extent 200 m), "
                         "the scale of its distance rewards"))
    if not np.isclose(t.extent_m, 2.0 * f.half_extent_m):
        problems.append((("generators", "forest", "half_extent_m"),
                         f"{f.half_extent_m:g} m: the forest grid must cover the terrain, half of extent_m "
                         f"({t.extent_m / 2.0:g} m)"))
    peak = t.height_multiplier * t.metres_per_multiplier
    if peak + p.min_clearance_m >= p.height_bound_m:
        problems.append((("generators", "terrain", "metres_per_multiplier"),
                         f"peaks reach {peak:g} m at this terrain level; with min_clearance_m {p.min_clearance_m:g} "
                         f"they must stay below the height bound {p.height_bound_m:g} m"))
    return problems
