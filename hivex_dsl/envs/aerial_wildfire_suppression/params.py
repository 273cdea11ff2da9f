"""Physical constants of Aerial Wildfire Suppression; every one bounded, documented and overridable.

[paper] values come from the paper, [orig] from the original release (ENVIRONMENTS.md), [ours]
are this project's defaults where neither says. The wind fields come from the shared wind model,
the fire fields from the shared fire engine (hivex_dsl.sim.fire); terrain, forest, ignition and
weather are generators (a scenario overrides them under `generators:`).
"""

from __future__ import annotations

from typing import Any, ClassVar, Literal

from pydantic import Field, model_validator

from ...sim.cameras import CameraParams
from ...sim.fire import FireSpec
from ...sim.procgen.wind import WindParams
from ..island import RedrawIsland, redraw_island_field

CAMERA_PIXELS = 42  # [paper] 42x42x3 downward camera


class AerialWildfireParams(WindParams, FireSpec, CameraParams):
    # each with what was done before it came, written out (not AS_DEFAULT) so that a default changed later does not
    # change what an older lock or checkpoint plays: the lone planes' rules (issue 52, sessions 34-38), and Find
    # tasks' planes that dropped and refilled (session 40)
    ADDED_FIELDS: ClassVar[dict[str, Any]] = {
        "turn_rule": "proportional", "finished_planes": "respawn", "spawn_rule": "ours", "episodes_continue": 0,
        "water_in_find_tasks": True, "terrain_cast": "step", "drop_mask": "flying", "drop_ground": "island",
        "village_zone": "circle", "extinguished_spread": False, "village_distance": "horizontal",
        "burn_list": "age", "fire_start": "running", "fire_cadence": "interval",
        "downwind_angle": "horizontal"}

    border_half_extent_m: float = Field(750.0, ge=100.0, le=10_000.0, description=(
        "[paper] Half the side of the square border (1500 x 1500); crossing it finishes that plane (see "
        "finished_planes)."))
    island_half_extent_m: float = Field(600.0, ge=50.0, le=10_000.0, description=(
        "[paper] Half the side of the island square (1200 x 1200); beyond it, up to the border, is the water ring. "
        "Must equal the forest generator's half extent."))
    plane_speed_m: float = Field(5.0, gt=0.0, le=50.0, description=(
        "[orig] Metres a plane flies per step: the release's HivexAgent speed, applied once an academy step. With "
        "waiting planes its Pick Up Water worlds last their slowest plane's flight, which meets the original's "
        "untrained 172-250 decisions; 3 was this toolkit's fit to those pages read as one plane's flight, the "
        "default until issue 52's session 43 (the reward table's notes)."))
    turn_rate_deg: float = Field(5.0, gt=0.0, le=45.0, description="[orig] Degrees a plane turns per step at steer +/-1.")
    turn_rule: Literal["proportional", "full"] = Field("full", description=(
        "'full' [orig]: any nonzero steer turns the whole turn_rate_deg its way, as the release's Transform.Rotate "
        "about an axis scaled by the steer, which Unity normalises. 'proportional' [ours]: a plane turns "
        "turn_rate_deg x steer a step, the default until issue 52's session 43 (the reward table's notes)."))
    finished_planes: Literal["respawn", "wait"] = Field("wait", description=(
        "'wait' [orig]: a plane that crossed the border or met its task's end stops and plays on, paid what its "
        "world still pays it (the pick-up task's cost of time included, not Fire Out; a waiting finder of the fire "
        "or the village is paid and counted again every step), until AgentDone's count of finishes reaches the "
        "plane count; then all their episodes end together and the world starts afresh, as the release's "
        "AgentManager ends them (Pick Up Water's pages obey it point for point, its untrained entropy too: the "
        "reward table's notes). 'respawn' [ours]: it starts a new episode alone over the burning island, the "
        "default until issue 52's session 43."))
    episodes_continue: int = Field(1, ge=0, le=1, description=(
        "[orig] 1: an episode cut by the time limit continues its world, as the release's MaxStep does (each "
        "plane's OnEpisodeBegin only respawns it): the island, the forest and its fire, the wind, the weather, "
        "the count of finishes (finished_planes wait) and the village's flag go on, so a fire that reached the "
        "village costs every plane again on the first step of each episode after; the world is drawn afresh "
        "only when the fire goes out or the count reaches the plane count (the release's TriggerDone). 0 [ours]: "
        "every episode starts a fresh world, the default until issue 52's session 43 (the reward table's notes)."))
    spawn_radius_m: float = Field(750.0, ge=0.0, le=10_000.0, description=(
        "[orig] Planes spawn uniformly within this distance of the centre (inside the border) with a random heading."))
    spawn_rule: Literal["ours", "release"] = Field("release", description=(
        "'release' [orig]: the release's RespawnAgent, a direction from a uniform point of a square, normalised, a "
        "distance uniform up to spawn_radius_m, nothing kept away. 'ours' [ours]: uniform over the spawn disk, "
        "planes without water over the island two steps from the ring, every plane two steps beyond the village "
        "radius and out of the fire's sight, the default until issue 52's session 43 (the reward table's notes)."))
    spawn_holding_water: Literal["auto", "always", "never"] = Field("auto", description=(
        "[orig] Whether planes start holding water; auto: they do, except in tasks that end on picking up water."))
    water_in_find_tasks: bool = Field(False, description=(
        "[orig] Whether planes refill and drop water in the tasks that end on finding the fire or the village. "
        "The release's Find Fire and Find Village call neither PickupWater nor DropWater (their OnActionReceived "
        "calls FindFireTask or FindVillageTask alone), so their planes keep the water they start with; their "
        "published test cells log no drop, pick-up or prepared tree at any level (the reward table's notes). True "
        "is the rule before issue 52's session 40."))
    terrain_cast: Literal["step", "frame"] = Field("frame", description=(
        "Where a plane reads the ground for the drop's action mask and for whether its drop lands. 'frame' [orig]: "
        "the release's HivexAgent.AutoAdjustHeight casts a ray down once a rendered frame (Update; every "
        "wind_frame_steps academy steps under mlagents-learn's defaults) and keeps the hit, which "
        "WriteDiscreteActionMask and DropWater read, so both see where the plane was at the last frame: a plane "
        "that flew out over the sea may still drop (its water lost) and one that flew in over land waits for the "
        "next frame; the default since issue 52's session 46, when its three level-1 seeds and its grid were trained "
        "to the end (the reward table's notes). 'step' [ours]: the ground under the plane at each step, the rule "
        "before."))
    drop_mask: Literal["flying", "release"] = Field("release", description=(
        "Which planes the drop's action mask opens to, and over what ground. 'release' [orig]: the release's "
        "WriteDiscreteActionMask tests neither the freeze flag nor the island's edge, so any plane holding water, "
        "flying or waiting (finished_planes wait), where its cast (terrain_cast) reads terrain at least 0.02 m "
        "high on the generator's whole map, which runs on under the water ring past the island's 600 m; a drop "
        "it opens to a waiting plane, or over the ring's seabed below the sea level, does nothing; the default "
        "since issue 52's session 47, when its three level-1 seeds and its grid were trained to the end (the reward "
        "table's notes). 'flying' [ours]: flying planes over the island's forest grid alone, the rule before."))
    drop_ground: Literal["island", "terrain"] = Field("terrain", description=(
        "Over what ground a drop lands (its water is spent and counted as a Water Drop), read where the plane's "
        "cast is (terrain_cast). 'terrain' [orig]: the release's DropWater tests only that its cast hit the terrain "
        "at 10 m or more (here above the sea level, 7 m), wherever that lies: past the island's 600 m too, where "
        "the generator's headlands run on under the water ring and PickupWater fills every plane without water, so "
        "a plane over such a headland refills and drops every other decision, its swath wetting what lies within "
        "its reach; the default since issue 52's session 49, when its three level-1 seeds and its grid were "
        "trained to the end (the reward table's notes). 'island' [ours]: land of the island's forest grid alone, "
        "the rule before."))
    redraw_island: RedrawIsland = redraw_island_field()
    drop_points: int = Field(4, ge=1, le=8, description="[orig] Points of the water swath, the first under the plane.")
    drop_point_spacing_m: float = Field(20.0, ge=0.0, le=100.0, description="[orig] Metres between swath points, ahead of the plane.")
    drop_radius_m: float = Field(30.0, gt=0.0, le=60.0, description=(
        "[orig] Existing or burning trees within this distance of a swath point become wet."))
    extinguished_spread: bool = Field(True, description=(
        "[orig] Whether a burning tree that water reaches goes on trying its neighbours for the rest of its burn, "
        "as the release's fire does (true): its BurnNext spreads from every tree of its burning list, whatever the "
        "tree's state, and no drop touches that list, so an extinguished tree stops counting as burning (planes no "
        "longer see it, the village does not, Extinguishing Trees counts it) but not spreading; false stops it at "
        "once, this toolkit's reading before (the reward table's note 'The village's zone, its distance and the "
        "water that does not stop the fire')."))
    fire_view_half_m: float = Field(150.0, gt=0.0, le=1_000.0, description=(
        "[orig] The closest burning tree is observed within +/- this many metres (a square) of the plane."))
    village_radius_m: float = Field(150.0, gt=0.0, le=1_000.0, description=(
        "[paper] Fire this close to the village centre costs 'too close to village' (village_zone says how close is "
        "measured); a plane this close has found it."))
    village_distance: Literal["horizontal", "release"] = Field("release", description=(
        "[orig] How a plane's distance to the village is read for Find Village: 'release' in 3-D, as the release's "
        "FindVillageTask (Vector3.Distance under 150 m) from the plane, which its AutoAdjustHeight keeps 100 m above "
        "the terrain its last frame's cast hit, to the village on its ground, so a plane over the village's level "
        "ground finds it about 112 m away; 'horizontal' [ours] the horizontal distance, this toolkit's reading before "
        "(the reward table's note 'The village's zone, its distance and the water that does not stop the fire')."))
    village_zone: Literal["circle", "square"] = Field("square", description=(
        "[orig] Where a burning tree costs 'too close to village' and counts in Fire too Close to City: 'square' the "
        "release's zone, every forest cell within village_radius_m of the village's in x and in y (CityGenerator."
        "FindClosestTrees keeps the trees standing within 50 cells, 150 m, of the village's cell each way, and "
        "CheckCloseTreeBurning sets the flag once any of them burns), so a fire coming at a corner is flagged up to "
        "212 m away; 'circle' [paper] a burning tree whose cell centre lies within village_radius_m, this "
        "toolkit's reading before (the reward table's note 'The village's zone, its distance and the water that "
        "does not stop the fire')."))
    camera_pixel_m: float = Field(5.0, gt=0.0, le=50.0, description=(
        "[ours] Ground metres per camera pixel; 42 pixels see 210 m, centred under the plane, forward up."))
    camera_sees_border: bool = Field(True, description=(
        "[ours] Whether the cameras draw the dark outside beyond the border. The release's border is a test of "
        "coordinates alone (CrossedBorderCheck: |x| or |z| at least 750 m) inside a terrain of about 1,666 m whose "
        "sea runs on past it, so its cameras see water on both sides of it; false draws the water ring there too, "
        "and only the observed position tells a plane where the border is (the reward table's notes). Drawn only "
        "under camera_images rendered: the blank camera of the original's runs (the default) shows no border at "
        "all, so the default stays true, as every record trained."))
    fire_step_interval: int = Field(17, ge=1, le=1_000, description=(
        "[records] Environment steps per fire step under fire_cadence 'interval', fitted to the original's first "
        "training points under the release's spread rules, its fire start and its burning list (fire_start, "
        "burn_list release): over the first 90,000 agent-steps of the ten levels (three seeds each, the mean of "
        "their runs), Fire too Close to City binned by Episode Length is 1.06 times the original's at 17 steps, as "
        "one by-length geometric mean (16 gave 1.15, 18 0.81, 20 0.61, 22 0.47; benchmarks/aws_early_fire.py "
        "--by-length). 22 was the fit under this toolkit's fire start and age-kept list, the default until issue "
        "52's session 89 (the reward table's notes). A tree burns for 170 steps. The release itself steps its "
        "fire every rendered frame, 16.7 steps, after a stream's first world, and every two frames before: "
        "fire_cadence 'frames', the default, which does not read this field."))
    fire_cadence: Literal["interval", "frames"] = Field("frames", description=(
        "When the fire steps. 'interval' [records]: every fire_step_interval steps in every world, the default "
        "until issue 52's session 92. 'frames' [orig]: "
        "as the release's BurnNext coroutine steps it (read from its IL): at the end of a rendered frame "
        "(wind_frame_steps), every other frame in a stream's first world, and every frame once a redraw of the "
        "world lands while a BurnNext waits (ResetForest clears its flag without stopping it, so two chains "
        "alternate from then on); a fire going out always lands so, a redraw by the planes' finishes at every "
        "other frame (burn_clock.py; the reward table's notes)."))
    low_overcast: float = Field(0.0, ge=0.0, le=1.0, description=(
        "[orig] Overcast below this counts as a factor of spread. The release counts it only where the overcast "
        "is exactly 0, which its raw Perlin overcast map almost never is: 0 counts it nowhere."))
    spread_weather_at: Literal["burning", "neighbour"] = Field("neighbour", description=(
        "[orig] Where a try reads hot, dry and low overcast: at the tree it tries, as the release's "
        "ForestDataGenerator.BurnNNeighbourIndexes does ('burning': at the burning tree)."))
    spread_max_distance_m: float = Field(10.0, ge=0.0, le=100.0, description=(
        "[orig] A burning tree tries only the trees within this many metres in 3-D (cell centres with their "
        "ground heights), as the release's Vector3.Distance check; 0 tries its whole block."))
    spread_wind: Literal["main", "local"] = Field("local", description=(
        "[orig] The downwind factor reads the wind at the burning tree, the main wind turned by the wind's noise "
        "field, as the release's Wind.GetWindAtLocation ('main': the world's main wind)."))
    downwind_angle: Literal["horizontal", "3d"] = Field("3d", description=(
        "[orig] A target counts as downwind by the angle in 3-D between its offset from the burning tree, heights "
        "included, and the level wind, as the release's BurnNNeighbourIndexes reads it (Vector3.Angle); "
        "'horizontal' by its direction on the map, the default until issue 52's session 92."))
    burn_list: Literal["age", "release"] = Field("release", description=(
        "[orig] The release's ForestDataGenerator.BurnNext keeps its burning list as a queue that drops from its "
        "front, each step, as many trees as caught fire 10 steps before, a count that never held the fire's first "
        "trees: the youngest trees, as many as the fire started with, go on trying past their burn, burnt; the "
        "list's oldest fifth shows burnt; the fire is out once quiet_steps_out steps pass without an ignition "
        "(hivex_dsl.sim.fire.queue). 'age' [ours], the default until issue 52's session 89: a tree tries for "
        "burn_steps fire steps, and the fire is out once nothing tries and quiet_steps_out steps passed without an "
        "ignition."))
    fire_start: Literal["running", "release"] = Field("release", description=(
        "[orig] The release's ForestDataGenerator.InitiateFireEnvProbability: one block burns, the first "
        "candidate's if it holds min_burning trees or more, else the first in rank order holding more alone, else "
        "the last candidate's: the fire starts in one place. 'running' [ours], the default until issue 52's "
        "session 89: the ranked candidates' blocks burn in rank order until their running count of trees exceeds "
        "min_burning, so a fire often starts in two places or more."))
    wind_original_law: int = Field(1, ge=0, le=1, description=(
        "[orig] The release's Wind.CalcMainWind (1): once a rendered frame the main wind's vector lerps toward the "
        "target by a fraction growing by wind_lerp_speed a game second (the AWS scene's 0.001: a 60-degree shift "
        "about every 1,940 steps); 0 eases it by wind_ease_rate a step."))
    wind_noise_scale_m: float = Field(500.0, ge=10.0, le=100_000.0, description=(
        "[orig] Metres of one unit of the wind's noise field: the AWS scene's incr of 0.002."))
    wind_noise_octaves: int = Field(1, ge=1, le=8, description=(
        "[orig] Octaves of the wind's noise field: Unity's PerlinNoise, one."))
    wind_drift_m: float = Field(0.0, ge=0.0, le=100.0, description=(
        "[orig] Metres the wind's noise field moves a step: the release holds it still while training "
        "(drawWindField is off) and in its test runs."))
    weather_grid_cells: int = Field(16, ge=2, le=128, description=(
        "[ours] The smooth weather fields are sampled on this many cells per side of the island for the fire and "
        "ignition (nearest cell); the fields vary over hundreds of metres, a cell is 75 m."))
    water_wait_penalty: float = Field(1.0 / 30.0, ge=0.0, le=1.0, description=(
        "[orig] Per step without water, the 'time step without water' term costs this much (100 / 3000)."))

    @model_validator(mode="after")
    def _island_inside_border(self) -> "AerialWildfireParams":
        if self.island_half_extent_m >= self.border_half_extent_m:
            raise ValueError(f"island_half_extent_m ({self.island_half_extent_m:g}) must be smaller than "
                             f"border_half_extent_m ({self.border_half_extent_m:g}): the water ring lies between them")
        return self
