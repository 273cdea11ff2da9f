"""Wildfire Resource Management: nine watchtowers share resources while a wildfire burns across the island."""

from __future__ import annotations

from ...compiler.registry import EnvironmentEntry, register
from ...lang.spec.catalogue import PAPER_ENVIRONMENTS
from ..island import ISLAND_GENERATORS, island_problems
from .global_state import state_facts
from .params import WildfireResourceParams
from .resources import neighbour_rows
from .scripted import scripted_policy
from .simulator import EVENTS, WildfireResourceSimulator
from .statistics import STATISTICS
from .terms import TERMS


def world_fits(compiled) -> list[tuple[tuple, str]]:
    """The forest must be the island, inside the terrain map (the towers stand on it: params check)."""
    return island_problems(compiled, compiled.params.island_half_extent_m)


ENTRY = register(EnvironmentEntry(
    info=PAPER_ENVIRONMENTS["wildfire_resource_management"],
    params_model=WildfireResourceParams,
    terms=TERMS,
    statistics=STATISTICS,
    state_facts=state_facts,
    make_simulator=WildfireResourceSimulator,
    scripted_policy=scripted_policy,
    events=EVENTS,
    world_events=frozenset({"fire_out"}),  # the island's fire: an ending of the whole world
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
        "moves 0.1 of the agent's own allocation to that target back to the budget; an add without budget (or beyond "
        "allocatable_tenths, 9 by default: a tenth of the 1.0 stays unallocated, as in the original's records) or a "
        "subtract from an empty allocation does nothing and is counted in infos['env'] (impossible_actions this "
        "step, impossible_actions_episode so far; the vector env's infos['env/impossible_actions'] and so on). At reset the whole 1.0 is unallocated (initial_self_tenths 0, ours).",
        "Observation (16) = 2 stacks (newest first; the older starts as zeros) of: the closest burning tree's "
        "offset from the tower x, y, z / detection_radius_m (z = its ground height minus the tower's; (0, 0, 0) "
        "when none is within 600 m), temperature, humidity and overcast at the tower (re-sampled every "
        "weather_refresh_interval steps), the tower's total support (from itself and every agent that "
        "supports it) / 9.0, the most any tower can receive, and whether a burning tree lies within 600 m "
        "(1 or 0; the paper's table lists 7 of the 8 values per stack, its process figure's caption this one; "
        "params.eighth_observation 'budget' observes the agent's own unallocated budget instead).",
        "Tower performance: the closest fire is the horizontally nearest burning tree within detection_radius_m; "
        "C(x) is the 3-D distance to it. P follows the paper's law for a fire within d_thresh = 200 m (d1n = "
        "d1 / d_thresh in [0, 1]); a tower whose closest fire is farther, or that sees none, has P = "
        "idle_performance (0, ours). m compares C with its value at the previous fire step (with "
        "fire_step_interval 1, the previous step); a fire that just came into range approaches, and nothing "
        "approaches at reset. The reward table's notes give the evidence.",
        "Terms: a tower's performance p is P times the resources it holds. Watch Tower Performance is P r_s (r_s the "
        "agent's allocation to itself, the prose's 'distributed by self to self'), Neighbourhood Performance each "
        "neighbour's p times the agent's allocation to that neighbour (the prose's weight; the equation leaves it "
        "out), Collective Performance the equation's 1 - |1 - RMS| of p over the nine towers. The main and "
        "Distribute All tasks pay for giving, Keep All for keeping; own_term_weight and neighbour_term_weight name "
        "the readings before: P r_a r_s (r_a what the agent has allocated; sessions 77-78), p r_s (sessions 74-76), "
        "P r_s r_s and the neighbours' summed P times the whole allocation to them (until session 74).",
        "Fire, terrain, forest, ignition and weather are Aerial Wildfire Suppression's but for the spread chance, "
        "0.5 a factor against its 0.2, fitted to the original's Episode Length curves (a new island every episode "
        "unless redraw_island is 'seed', which keeps it across a seed stream; the fire is new every episode). Towers "
        "cannot fight the fire; with one fire step per environment step (fire_step_interval 1, ours) it burns "
        "through the forest and mostly goes out after 100-350 steps, 165-230 on average a level as the original's "
        "(163-228; the reward table's notes), and every task ends then (event fire_out) or after 500 steps.",
        "Scale (test seed 6000, terrain level 1, ten episodes; benchmarks/results/fidelity.json): uniform random "
        "play's Individual Performance is 14.3 a tower-episode and its Collective Performance 33.0, the scripted "
        "officer's 25.4 and 57.8 (it gathers the resources where the fire is), against the published PPO's 18.0 "
        "and 34.5; the officer's resource rewards (Neighbours 26 in the main task, Self 185 in Keep All, Neighbours "
        "262 in Distribute All) against the published PPO's (49, 143, 513).",
    ),
))
