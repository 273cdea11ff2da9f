"""The statistics Ocean Plastic Collection logs ("OceanPlasticCollector/<name>")."""

from __future__ import annotations

from ...sim.statistics import StatisticSet
from .terms import TERMS

STATISTICS = StatisticSet("ocean_plastic_collection", "OceanPlasticCollector", notes=(
    "Statistics: 'Local Reward' reads what Collect Trash paid the vessel alone (+1 a pebble, -1 in Avoid Plastic), "
    "not its crashes, Collide with Trash or the tasks' shaping terms: the original's untrained policy logs +19.0 in "
    "the main task and -18.9 in Avoid Plastic, mirror images, where counting the crash's -100 would put them at least "
    "3.6 apart and Avoid Plastic's -2 a touched pebble would double the second; 'Global Reward' reads the shared "
    "terms (the team's lowest collected count): the published Avoid Plastic cell, whose only shared term has weight "
    "0, logs Global 0. Both are running means (hivex_dsl.sim.statistics), not episode sums: a running total of "
    "what those terms paid, averaged over the steps it changed on (a vessel collecting n pebbles one at a time "
    "logs (n + 1) / 2; the lowest count's total, growing as the square of time, averages about a third of its "
    "final value). Compared with the published cells in their pooled form, sum of the added totals over their "
    "count across every agent-episode; the reward table's Local note gives the evidence, and what the original's "
    "records say against the running-mean logging.",
))

# Local counts Collect Trash alone: the original's untrained Local is a mirror image across the main task and
# Avoid Plastic (+18.97, -18.94), so it moves by +1 or -1 a pebble with the task's sign and leaves out the crash
# (the reward table's Local note has the evidence).
LOCAL_TERMS = ("collect_trash",)
if not set(LOCAL_TERMS) <= {t.name for t in TERMS}:
    raise ValueError(f"ocean_plastic_collection: LOCAL_TERMS names unknown terms {set(LOCAL_TERMS)}")

STATISTICS.running_mean("Local Reward", "The mean of the vessel's running total of what Collect Trash paid it "
                        "(weighted: +1 a pebble collected, -1 in Avoid Plastic; not its crashes, Collide with Trash "
                        "or the tasks' shaping terms), over the steps that total changed on.", *LOCAL_TERMS)
STATISTICS.running_mean("Global Reward", "The mean of the vessel's running total of what the shared (team or global "
                        "scope) terms paid (weighted: the team's lowest collected count), over the steps that total "
                        "changed on.", *(t.name for t in TERMS if t.contract.scope != "agent"))
