"""The statistics Ocean Plastic Collection logs ("OceanPlasticCollector/<name>").

The original logs the reward it gives each vessel ("Local Reward") apart from the reward it gives
the group ("Global Reward"). This toolkit's reading: the local reward is what the agent-scope terms
paid, the global one what the shared terms paid (the team's lowest collected count); the published
Avoid Plastic cell (Global 0, Local -2.9) and the main task (Global 286) agree with that split.
"""

from __future__ import annotations

from ...statistics import StatisticSet
from .terms import TERMS

STATISTICS = StatisticSet("ocean_plastic_collection", "OceanPlasticCollector")

STATISTICS.mirror("Local Reward", "What the vessel's own (agent-scope) terms paid, weighted.",
                  *(t.name for t in TERMS if t.contract.scope == "agent"))
STATISTICS.mirror("Global Reward", "What the shared (team or global scope) terms paid, weighted: the team's "
                  "lowest collected count.", *(t.name for t in TERMS if t.contract.scope != "agent"))
