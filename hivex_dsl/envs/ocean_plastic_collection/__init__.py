"""Ocean Plastic Collection: vessels sweep floating plastic pebbles off a seeded pollution heat map."""

from __future__ import annotations

from ...compiler.registry import EnvironmentEntry, GeneratorSlot, register
from ...lang.spec.catalogue import PAPER_ENVIRONMENTS
from ...sim.procgen.pollution import PollutionSpec, SpawnSpec, load_pollution_preset, spawn_problem
from .global_state import state_facts
from .params import OceanPlasticCollectionParams
from .scripted import scripted_policy
from .simulator import OceanPlasticSimulator
from .statistics import STATISTICS
from .terms import TERMS

PRESET = load_pollution_preset()


def one_world(compiled) -> list[tuple[tuple, str]]:
    """The heat map and the spawn points must cover the same square world."""
    pollution, spawn = compiled.generators["pollution"], compiled.generators["spawn"]
    if pollution.half_extent_m != spawn.half_extent_m:
        return [(("generators", "spawn", "half_extent_m"),
                 f"{spawn.half_extent_m:g} m differs from generators.pollution.half_extent_m "
                 f"({pollution.half_extent_m:g} m); both describe the one world")]
    return []


def vessels_fit(compiled) -> list[tuple[tuple, str]]:
    """Every vessel must find a spawn point (procgen.pollution.spawn_problem)."""
    problem = spawn_problem(compiled.generators["spawn"], compiled.agents)
    return [(("agents",), problem)] if problem else []


ENTRY = register(EnvironmentEntry(
    info=PAPER_ENVIRONMENTS["ocean_plastic_collection"],
    params_model=OceanPlasticCollectionParams,
    terms=TERMS,
    statistics=STATISTICS,
    state_facts=state_facts,
    make_simulator=OceanPlasticSimulator,
    scripted_policy=scripted_policy,
    events={
        "crossed_border": "the vessel left the square world this step",
        "collided_with_other_vessel": "the vessel came closer than collision_distance_m to another vessel this step",
        "collided_with_trash": "the vessel's collector ran into (and picked up) at least one pebble this step",
        "crash_ended_world": ("a vessel of this world crashed this step under crash_outcome: end_world (never under "
                              "end or respawn): every task ends the world's episode on it"),
    },
    world_events=frozenset({"crash_ended_world"}),  # one vessel's crash ends every vessel's episode
    checks=(one_world, vessels_fit),
    generators={
        "pollution": GeneratorSlot(PollutionSpec, lambda level: PRESET.pollution, (
            "The seeded pollution heat map and the number of floating plastic pebbles sampled from it "
            "(generators/pollution.yaml); its half extent is the world's border.")),
        "spawn": GeneratorSlot(SpawnSpec, lambda level: PRESET.spawn, (
            "Where the vessels start: apart from each other, away from the border, with random headings "
            "(generators/pollution.yaml).")),
    },
    notes=(
        "Observations: vector Box(12) = two stacks (newest first) of local position (2, position / half extent), "
        "direction (2, cos and sin of the heading) and the closest other vessel's position (2, / half extent; "
        "(0, 0) when no other vessel is in the world); visual Box(25, 25, 2) = two stacks of the trash camera on the "
        "last axis, 25 x 25 cells of 2 m centred on and turned with the vessel (row 0 ahead, column 0 to the left), "
        "each cell min(1, pebbles / camera_full_count) (params.camera_source 'pebbles', the default; 'heat_map' "
        "shows the heat map's density instead, 'blank' nothing). The older stack holds the previous decision's "
        "observation and starts as zeros, as ML-Agents' stacking sensors do (the reward table's note on observation "
        "stacks).",
        "The paper gives -100 for crossing the border or colliding with another vessel but does not say what "
        "follows; by default (crash_outcome: end_world) the episode of every vessel of the world ends, as the "
        "original's Episode Length and returns show (the reward table's ending note); crash_outcome: end ends "
        "the crashed vessel's alone, and respawn restarts it at rest at a free spawn point instead.",
        "A pebble is collected when it lies in the rectangle the collector swept this step (collector_reach_m "
        "ahead of the vessel's centre back to where the collector was, collector_half_width_m either side); "
        "Collide with Trash fires on exactly those steps, as the vessel touches plastic only with its collector.",
        "Pebbles do not drift and are not replaced: the paper calls the plastic a fixed amount. The world "
        "(half extent 200 m), heat map (fractal noise at contrast 1.5, no hotspots), pebble count (6,000; both "
        "fitted so random play collects and passes what the original's untrained policy did: the reward table's "
        "supply note) and spawn rules are the `pollution` and `spawn` "
        "generators; vessel speed (top 2 m per step) and turn rate (6 degrees per step) are fitted to the original's "
        "Episode Length and Local Reward curves (the reward table's pace note); the collector (3 m x 3 m) is this "
        "project's choice. A collector sweeps only while its vessel moves or turns, so a "
        "vessel spawned over pebbles takes none before it acts.",
        "Scale: a vessel collecting c pebbles in an episode earns c from Collect Trash and, from Global Lowest "
        "Trash Collected (paid on collection), about 0.01 x (pebbles collected by the whole team) x (the lowest "
        "count at the time), about 0.01 x 3c x 0.4c = 0.012 c^2 for three vessels at an even pace. The scripted "
        "skipper collects about 986 pebbles a vessel-episode (return about 14,300; it never crashes); the logged "
        "Local Reward is the vessel-episode's collected count and Global Reward a running mean, pooled over "
        "vessel-episodes (the reward table's notes). Random "
        "play collects about 18 before one vessel of its world crosses the border and ends the world's episode.",
    ),
))
