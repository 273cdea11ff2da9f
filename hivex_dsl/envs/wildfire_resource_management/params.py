"""Physical constants of Wildfire Resource Management; every one bounded, documented and overridable.

[paper] values come from the paper, [orig] from the original release (ENVIRONMENTS.md), [ours]
are this project's defaults where neither says. The wind fields come from the shared wind model,
the fire fields from the shared fire engine (hivex_dsl.sim.fire), exactly as in Aerial Wildfire
Suppression; terrain, forest, ignition and weather are the island's generators (a scenario
overrides them under `generators:`).
"""

from __future__ import annotations

from typing import Any, ClassVar, Literal

from pydantic import Field, model_validator

from ...sim.fire import FireSpec
from ...sim.procgen.wind import WindParams
from ..island import RedrawIsland, redraw_island_field


class WildfireResourceParams(WindParams, FireSpec):
    # the terms' readings before session 74, written out: locks and checkpoints from before read them so; the
    # budget observed before the eighth value became a param
    ADDED_FIELDS: ClassVar[dict[str, Any]] = {"own_term_weight": "kept_squared", "neighbour_term_weight": "given_total",
                                              "eighth_observation": "budget"}

    island_half_extent_m: float = Field(600.0, ge=50.0, le=10_000.0, description=(
        "[paper] Half the side of the island square (1200 x 1200), shared with Aerial Wildfire Suppression. "
        "Must equal the forest generator's half extent."))
    tower_spacing_m: float = Field(450.0, gt=0.0, le=10_000.0, description=(
        "[orig] The nine watchtowers stand on a 3 x 3 grid at -s, 0, +s metres in x and y (inferred from the "
        "original's shared sample points); must lie inside the island."))
    detection_radius_m: float = Field(600.0, gt=0.0, le=10_000.0, description=(
        "[paper] A tower observes the closest burning tree within this horizontal distance."))
    distance_threshold_m: float = Field(200.0, gt=0.0, le=10_000.0, description=(
        "[paper] d_thresh: the fire distance is normalised by it in the tower performance, which is defined only "
        "for a fire within it (beyond, the remapped distance of an approaching fire turns negative); a tower whose "
        "closest fire is farther has P = idle_performance."))
    power_law_s: float = Field(270.0, ge=1.0, le=100_000.0, description=(
        "[paper] s of the broken power law P = (1 + (d' * 1000 / s)^a)^(-1/2)."))
    power_law_a: float = Field(5.0, ge=0.5, le=20.0, description=(
        "[paper] a of the broken power law P = (1 + (d' * 1000 / s)^a)^(-1/2)."))
    idle_performance: float = Field(0.0, ge=0.0, le=1.0, description=(
        "[ours] Performance P of a tower without a burning tree within distance_threshold_m (the paper defines "
        "P only for a fire within d_thresh); 0 gives the published Individual and Collective Performance sizes."))
    performance_weight: Literal["none", "resources"] = Field("resources", description=(
        "[records] What a tower's performance is as Collective Performance (the term and its statistic) and "
        "Individual Performance read it: 'resources' P times the resources the tower holds (its total support, 1.0 "
        "one agent's share), 'none' P itself, the fire's alone (this project's reading until issue 52). The "
        "original's pages: on the same fires its Keep All and main-task policies log different performance, as P "
        "times the resources gives and P alone cannot (the reward table's note on the towers' resources). The "
        "own-tower and neighbourhood terms read it as own_term_weight and neighbour_term_weight say."))
    own_term_weight: Literal["kept_squared", "held_kept", "allocated_kept", "kept"] = Field("kept", description=(
        "[records] How Watch Tower Performance weighs the own tower: 'kept' P times the share the agent keeps "
        "(r_supporting), r_distributed read as the agent's whole resource (1.0), so neither what it gives nor what "
        "it is given moves its own term, as the prose reads ('weighted by the resources distributed by self to "
        "self'; the default since session 79: the reward table's note 'The own term reads the share kept');"
        " 'allocated_kept' P times the share the agent has allocated (to itself and its neighbours) times the share "
        "it keeps, under which a tenth given raises what keeping pays and Keep All's towers keep too little (the "
        "default of sessions 77-78); 'held_kept' the tower's performance as performance_weight reads it (P times the "
        "resources it holds) times the kept share (the default of sessions 74-76); 'kept_squared' P times the kept "
        "share squared, the equation as printed (this project's reading until session 74). The original's untrained "
        "towers keep 0.15-0.43 of their Individual Performance, 'kept' 0.23-0.26, 'allocated_kept' 0.15-0.21 "
        "(random play, levels 1, 5 and 10), 'held_kept' 0.18-0.24, 'kept_squared' 0.06-0.13 (the reward table's "
        "notes 'The terms read what the towers hold' and 'Three seeds a level')."))
    neighbour_term_weight: Literal["given_total", "given_each"] = Field("given_each", description=(
        "[records] How Neighbour Performance weighs the neighbours: 'given_each' each neighbour's performance as "
        "performance_weight reads it (P times the resources it holds) times the share the agent gives that "
        "neighbour; 'given_total' the neighbours' summed P times the whole share the agent gives them (this "
        "project's reading until session 74). The original's untrained towers give 0.51-1.00 of their Individual "
        "Performance and its trained Keep All 0.03-0.09, 'given_each' 0.68-1.06 and 0.07, 'given_total' 1.9-2.5 "
        "and 0.27-0.65 (the reward table's note 'The terms read what the towers hold')."))
    eighth_observation: Literal["budget", "fire_detected"] = Field("fire_detected", description=(
        "[records] The eighth value of each observation stack, which the paper's table (16 values in 2 stacks) "
        "leaves unnamed: 'fire_detected' 1 while a burning tree lies within detection_radius_m of the tower, else 0 "
        "(the process figure's caption: each agent observes 'whether a fire has been detected within 600 meters'); "
        "'budget' the agent's own unallocated budget / 1.0 (this project's choice until session 95). The original's "
        "Curiosity Inverse Loss lies within 0.03 nats of its policy's Entropy over 10-25, 25-50, 50-75 and 75-100% "
        "of its main task's budget: its towers' observations showed the curiosity module almost nothing of their "
        "own actions, as the flag's do and the budget's, moved 0.1 by every add or subtract, do not (0.35-0.44 "
        "nats; the reward table's note 'What the towers observe')."))
    initial_self_tenths: int = Field(0, ge=0, le=10, description=(
        "[ours] Tenths of its 1.0 that each tower has allocated to itself at reset; the rest starts unallocated."))
    allocatable_tenths: int = Field(9, ge=1, le=10, description=(
        "[records] The most of its ten tenths an agent can allocate; an add beyond it does nothing (an impossible "
        "action). The original's towers end their episodes holding at most 0.9: 9,898 of the 9,900 values its "
        "pages log, the last tenth of training 0.83-0.89 in every cell. In single-precision floats, as Unity "
        "keeps them, 1.0 less nine adds of 0.1 leaves 0.09999993, short of the 0.1 a tenth add needs (a reading "
        "of the mechanism; the reward table's note on the towers' resources). 10 lets every tenth go."))
    redraw_island: RedrawIsland = redraw_island_field()
    spread_chance_per_factor: float = Field(0.5, ge=0.0, le=1.0, description=(
        "[fitted] Ignition chance of one try per true factor (downwind, uphill, hot, dry, low overcast), capped at "
        "1; Aerial Wildfire Suppression's 0.2 [orig] made this fire burn 1.15-1.37 times as long as the original's "
        "Episode Length curves at every level. A free fire here burns through the forest, so its length is the "
        "front's travel time; 0.5 makes it the original's (mean over levels 1.00, each level 0.93-1.12; the "
        "reward table's notes, issue 52)."))
    fire_step_interval: int = Field(1, ge=1, le=1_000, description=(
        "[ours] Environment steps per fire step. With 1 and spread_chance_per_factor 0.5, a free-burning fire "
        "(towers cannot fight it) mostly goes out after 100-350 steps, 165-230 on average a level, as the "
        "original's Episode Length curves (163-228 a level; the reward table's notes, issue 52)."))
    weather_grid_cells: int = Field(16, ge=2, le=128, description=(
        "[ours] The smooth weather fields are sampled on this many cells per side of the island for the fire "
        "(nearest cell), as in Aerial Wildfire Suppression; a cell is 75 m."))
    weather_refresh_interval: int = Field(10, ge=1, le=1_000, description=(
        "[ours] Steps between re-samplings of the weather grid and of the weather at the towers; the fields drift "
        "about 1 m per step over fronts hundreds of metres across, so a sample stays current that long."))

    @model_validator(mode="after")
    def _kept_within_reach(self) -> "WildfireResourceParams":
        if self.initial_self_tenths > self.allocatable_tenths:
            raise ValueError(f"initial_self_tenths ({self.initial_self_tenths}) must not exceed allocatable_tenths "
                             f"({self.allocatable_tenths}): an agent allocates at most that much")
        return self

    @model_validator(mode="after")
    def _towers_on_island(self) -> "WildfireResourceParams":
        if self.tower_spacing_m >= self.island_half_extent_m:
            raise ValueError(f"tower_spacing_m ({self.tower_spacing_m:g}) must be smaller than island_half_extent_m "
                             f"({self.island_half_extent_m:g}): the outer towers stand on the island")
        return self
