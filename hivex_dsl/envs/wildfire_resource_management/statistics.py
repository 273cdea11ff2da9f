"""The statistics Wildfire Resource Management logs ("WildfireResourceManagement/<name>").

Readings (from the published values, which are the same in every task where a name is not task-weighted):
"Individual Performance" (about 18 in all three tasks, although Keep All weighs the own tower x10) is
the tower's performance P itself, unweighted; "Collective Performance" is what the collective term paid;
the two "Reward for Moving Resources to ..." follow the task's weights (to Self 143 in Keep All, to
Neighbours 513 in Distribute All) and are what the watch-tower and neighbourhood terms paid.
"""

from __future__ import annotations

from ...statistics import StatisticSet
from .terms import tower_performance

STATISTICS = StatisticSet("wildfire_resource_management", "WildfireResourceManagement")


@STATISTICS.counter("Individual Performance", "The tower's performance P (fire distance and approach), unweighted.")
def individual_performance(prev, state, actions, params):
    return tower_performance(state, params)


STATISTICS.mirror("Collective Performance", "What the collective term paid (weighted).", "collective_performance")
STATISTICS.mirror("Reward for Moving Resources to Neighbours", "What the neighbourhood term paid (weighted).",
                  "neighbour_performance")
STATISTICS.mirror("Reward for Moving Resources to Self", "What the own tower's term paid (weighted).",
                  "watch_tower_performance")
