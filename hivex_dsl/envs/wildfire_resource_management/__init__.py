"""Wildfire Resource Management: nine watchtowers share resources while a wildfire burns across the island."""

from __future__ import annotations

from ...registry import EnvironmentEntry, register
from ...spec.catalogue import CATALOGUE
from ..island import ISLAND_GENERATORS, island_problems
from .params import WildfireResourceParams
from .resources import neighbour_rows
from .scripted import scripted_policy
from .simulator import EVENTS, WildfireResourceSimulator
from .terms import TERMS


def world_fits(compiled) -> list[tuple[tuple, str]]:
    """The forest must be the island, inside the terrain map (the towers stand on it: params check)."""
    return island_problems(compiled, compiled.params.island_half_extent_m)


ENTRY = register(EnvironmentEntry(
    info=CATALOGUE["wildfire_resource_management"],
    params_model=WildfireResourceParams,
    terms=TERMS,
    make_simulator=WildfireResourceSimulator,
    scripted_policy=scripted_policy,
    events=EVENTS,
    checks=(world_fits,),
    generators=ISLAND_GENERATORS,
    notes=(
        "Task order [paper]: 0 main, 1 keep_all, 2 distribute_all, as the paper's reward-scale table and the "
        "published leaderboard number them; the original training config [orig] comments 'Main: 0, Distribute "
        "All: 1, Keep All: 2'. Name the task in scenarios (keep_all, distribute_all). The published returns "
        "(about 122, 293, 784) fit this order (see the reward table's notes).",
        "Towers [orig]: tower i = 3 row + col stands at x = (col - 1) s, y = (row - 1) s with s = tower_spacing_m "
        "(450 m); row 0 is the south edge. Its three neighbours are the other towers by distance, ties to the "
        "lower index (only the centre tower has a tie: 1, 3, 5, 7 all at s; 7 is dropped); neighbour 1 is the "
        "nearest. Neighbour table: " + "; ".join(neighbour_rows()) + ".",
        "Resources are integers in tenths. Each agent owns 1.0: unallocated budget plus what it gave itself and its "
        "three neighbours, so the parts always sum to 1.0 and none is negative or above 1.0. The four action "
        "branches apply in order (self, neighbour 1, 2, 3): add moves 0.1 from the budget to the target, subtract "
        "moves 0.1 of the agent's own allocation to that target back to the budget; an add without budget or a "
        "subtract from an empty allocation does nothing and is counted in infos['env'] (impossible_actions this "
        "step, impossible_actions_episode so far). At reset the whole 1.0 is unallocated (initial_self_tenths 0, ours).",
        "Observation (16) = 2 stacks (newest first; the older starts as zeros) of: the closest burning tree's "
        "offset from the tower x, y, z / detection_radius_m (z = its ground height minus the tower's; (0, 0, 0) "
        "when none is within 600 m), temperature, humidity and overcast at the tower (re-sampled every "
        "weather_refresh_interval steps), the tower's total support (from itself and every agent that "
        "supports it) / 9.0, the most any tower can receive, and the agent's own unallocated budget (ours: the "
        "paper's table lists 7 of the 8 values per stack).",
        "Tower performance: the closest fire is the horizontally nearest burning tree within detection_radius_m; "
        "C(x) is the 3-D distance to it. d1 / d_thresh is clipped to [0, 1] (unclipped, a fire approaching from "
        "beyond d_thresh = 200 m would give a negative base, and beyond about 310 m no real P). m compares C with "
        "its value at the previous fire step (with fire_step_interval 1, the previous step); a fire that just came "
        "into range approaches, and nothing approaches at reset. A tower that sees no fire has P = idle_performance "
        "(0, ours).",
        "The equations are implemented as printed: Watch Tower Performance is P r_s r_s (r_distributed, the total "
        "support, is named in R(p, r_distributed, r_supporting) but not used), and Neighbourhood Performance is the "
        "plain sum of the neighbours' P although the prose says it is weighted by the resources given to them; "
        "Collective Performance is the equation's 1 - |1 - RMS| over the nine towers, where the prose says the sum "
        "of all towers' performance. So "
        "only the watch-tower term depends on the actions, and keeping everything for the own tower maximises "
        "every task's return.",
        "Fire, terrain, forest, ignition and weather are Aerial Wildfire Suppression's (an island is kept across the "
        "episodes of a seed stream unless redraw_island is 'episode'; the fire is new every episode). Towers "
        "cannot fight the fire; with one fire step per environment step (fire_step_interval 1, ours) it mostly goes "
        "out after 150-350 steps, near the original's logged mean episode lengths of 140-275, and every task ends "
        "then (event fire_out) or after 500 steps.",
        "Scale: Neighbourhood plus Collective Performance, which no action changes, sum to about 390 per episode "
        "here (test seeds 6000-6003, terrain level 1), against about 100 implied by the published returns, so our "
        "towers see more (or more often approaching) fire than the original's. The order of the three tasks' "
        "returns and the ratios of the terms match the published ones; the fire is not calibrated further.",
    ),
))
