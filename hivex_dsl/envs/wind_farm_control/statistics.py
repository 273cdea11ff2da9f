"""The statistics Wind Farm Control logs ("WindFarmControl/<name>"): both are what a task paid for a term."""

from __future__ import annotations

from ...sim.statistics import StatisticSet

STATISTICS = StatisticSet("wind_farm_control", "WindFarmControl")

STATISTICS.mirror("Individual Performance", "What the task paid for generated energy (weighted; 0 in Avoid Damage, "
                  "as published).", "generate_energy")
STATISTICS.mirror("Avoid Damage Reward", "What the task paid for turning the blades parallel to the wind (weighted; "
                  "logged only in Avoid Damage).", "avoid_damage")
