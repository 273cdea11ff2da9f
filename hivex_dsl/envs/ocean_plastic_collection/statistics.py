"""The statistics Ocean Plastic Collection logs ("OceanPlasticCollector/<name>")."""

from __future__ import annotations

from ...sim.statistics import StatisticSet
from .terms import TERMS

STATISTICS = StatisticSet("ocean_plastic_collection", "OceanPlasticCollector", notes=(
    "Statistics: 'Local Reward' reads the vessel's own events (collecting and touching plastic, its crashes; not "
    "the tasks' shaping terms, Nearby Trash Count Delta and Close to Other Vessel, since the published Local stays "
    "pebble-sized in those tasks: 142.2 and 165.2) and 'Global Reward' the shared terms "
    "(the team's lowest collected count): the published Avoid Plastic cell, whose only shared term has weight 0, "
    "logs Global 0 and Local -2.9. Both are running means (hivex_dsl.sim.statistics), not episode sums: the "
    "original adds the vessel's running total of what those terms paid to ML-Agents' StatsRecorder each time it "
    "changes, and TensorBoard shows the average of the values added (a vessel collecting n pebbles one at a time "
    "logs (n + 1) / 2; the lowest count's total, growing as the square of time, averages about a third of its "
    "final value). Compared with the published cells in their pooled form, sum of the added totals over their "
    "count across every agent-episode; the reward table's last note gives the evidence.",
))

# The tasks' own shaping terms (Find Highest Polluted Area's nearby count, Group Up's closeness) stay out of Local:
# the published Local is pebble-sized in those tasks (142.2 and 165.2, main 158.7), while counting them gives
# the scripted skipper 371 and 2,417 against its 81 in the main task (measured with 1,000 pebbles).
TASK_SHAPING = ("nearby_trash_count_delta", "close_to_other_vessel")
if not set(TASK_SHAPING) <= {t.name for t in TERMS}:
    raise ValueError(f"ocean_plastic_collection: TASK_SHAPING names unknown terms {set(TASK_SHAPING)}")

STATISTICS.running_mean("Local Reward", "The mean of the vessel's running total of what its own events paid "
                        "(weighted: collecting and touching plastic, crossing the border, colliding with a vessel; "
                        "not the tasks' shaping terms), over the steps that total changed on.",
                        *(t.name for t in TERMS if t.contract.scope == "agent" and t.name not in TASK_SHAPING))
STATISTICS.running_mean("Global Reward", "The mean of the vessel's running total of what the shared (team or global "
                        "scope) terms paid (weighted: the team's lowest collected count), over the steps that total "
                        "changed on.", *(t.name for t in TERMS if t.contract.scope != "agent"))
