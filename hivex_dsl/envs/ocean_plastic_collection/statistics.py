"""The statistics Ocean Plastic Collection logs ("OceanPlasticCollector/<name>")."""

from __future__ import annotations

from ...sim.statistics import StatisticSet
from .terms import TERMS

STATISTICS = StatisticSet("ocean_plastic_collection", "OceanPlasticCollector", notes=(
    "Statistics: 'Local Reward' is the vessel-episode's total of what Collect Trash paid it (+1 a pebble, -1 in "
    "Avoid Plastic), added once per vessel-episode: not its crashes, Collide with Trash or the tasks' shaping terms "
    "(the original's untrained policy logs +19.0 in the main task and -18.9 in Avoid Plastic, mirror images, where "
    "counting the crash's -100 would put them far apart), and not a running mean (once Avoid Plastic's vessels live "
    "to the time limit, every run's summary point is an integer over the 15 vessel-episodes it holds, and one lies "
    "above -1, which no mean of a falling running total can). 'Global Reward' reads the shared terms (the team's "
    "lowest collected count; the published Avoid Plastic cell, whose only shared term has weight 0, logs Global 0) "
    "and stays a running mean (hivex_dsl.sim.statistics): the running total of what they paid, averaged over the "
    "steps it changed on (a total growing as the square of time averages about a third of its final value); the "
    "main task's return adds up from its Local only with Global so read. Both compare with the published cells in "
    "their pooled form (Local: the mean over vessel-episodes; Global: the sum of the added totals over their "
    "count); the reward table's Local note gives the evidence.",
))

# Local counts Collect Trash alone, once per vessel-episode: the original's untrained Local is a mirror image across
# the main task and Avoid Plastic (+18.97, -18.94), and its late Avoid Plastic points are integers over the vessel-
# episodes of a summary (the reward table's Local note has the evidence).
LOCAL_TERMS = ("collect_trash",)
if not set(LOCAL_TERMS) <= {t.name for t in TERMS}:
    raise ValueError(f"ocean_plastic_collection: LOCAL_TERMS names unknown terms {set(LOCAL_TERMS)}")

STATISTICS.mirror("Local Reward", "The vessel-episode's total of Collect Trash at the task's weight (+1 a pebble "
                  "collected, -1 in Avoid Plastic, which logs it without paying it; not its crashes, Collide with Trash "
                  "or the tasks' shaping terms).", *LOCAL_TERMS)
STATISTICS.running_mean("Global Reward", "The mean of the vessel's running total of what the shared (team or global "
                        "scope) terms paid (weighted: the team's lowest collected count), over the steps that total "
                        "changed on.", *(t.name for t in TERMS if t.contract.scope != "agent"))
