"""The statistics Ocean Plastic Collection logs ("OceanPlasticCollector/<name>")."""

from __future__ import annotations

from ...sim.statistics import StatisticSet
from .terms import TERMS

STATISTICS = StatisticSet("ocean_plastic_collection", "OceanPlasticCollector", notes=(
    "Statistics: 'Local Reward' is what the vessel's own (agent-scope) terms paid and 'Global Reward' what the "
    "shared terms paid (the team's lowest collected count): the published Avoid Plastic cell, whose only shared "
    "term has weight 0, logs Global 0 and Local -2.9; the main task logs Global 286.",
))

STATISTICS.mirror("Local Reward", "What the vessel's own (agent-scope) terms paid, weighted.",
                  *(t.name for t in TERMS if t.contract.scope == "agent"))
STATISTICS.mirror("Global Reward", "What the shared (team or global scope) terms paid, weighted: the team's "
                  "lowest collected count.", *(t.name for t in TERMS if t.contract.scope != "agent"))
