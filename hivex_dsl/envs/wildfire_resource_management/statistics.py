"""The statistics Wildfire Resource Management logs ("WildfireResourceManagement/<name>")."""

from __future__ import annotations

from ...sim.statistics import StatisticSet
from .resources import TENTHS
from .terms import held_performance

STATISTICS = StatisticSet("wildfire_resource_management", "WildfireResourceManagement", notes=(
    "Statistics: 'Individual Performance' is the tower's performance (P times the resources it holds), not "
    "weighted by the task: it is about 18 in all three published tasks although Keep All weighs the own tower x10.",
    "Statistics: 'Individual Resource Count' is logged once a tower-episode, as the episode ends, in tenths: "
    "99.3% of the original's per-run values are whole tenths averaged over the world-episodes of a summary point.",
    "Statistics: the two 'Reward for Moving Resources to ...' are what the own-tower and neighbourhood terms paid, "
    "weighted: they follow the task weights in the published results (to Self 143 in Keep All against 0.2 in the "
    "main task, to Neighbours 513 in Distribute All against 49).",
))


@STATISTICS.counter("Individual Performance", (
    "The tower's performance P (fire distance and approach), unweighted by the task; times the resources it holds "
    "under performance_weight 'resources'."))
def individual_performance(prev, state, actions, params):
    return held_performance(state, params)


STATISTICS.mirror("Collective Performance", "What the collective term paid (weighted).", "collective_performance")
STATISTICS.mirror("Reward for Moving Resources to Neighbours", "What the neighbourhood term paid (weighted).",
                  "neighbour_performance")
STATISTICS.mirror("Reward for Moving Resources to Self", "What the own tower's term paid (weighted).",
                  "watch_tower_performance")


@STATISTICS.at_end("Individual Resource Count", (
    "The tower's resources as its episode ends: what it keeps and what its neighbours give it (its total support; "
    "1.0 is one agent's whole share), in tenths, logged once a tower-episode."))
def individual_resource_count(prev, state, actions, params):
    return state.support / TENTHS
