"""The five HIVEX environments as the paper and DESIGN.md list them (pure data).

This is the one place for each environment's identity, agent bounds, episode length and which
difficulty axis it has (layout `pattern` or `terrain_level`). An environment is *available*
once its package registers a simulator (see :mod:`hivex_dsl.compiler.registry`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal, Optional

LevelField = Literal["pattern", "terrain_level"]


@dataclass(frozen=True)
class EnvironmentInfo:
    id: str
    title: str
    abbreviation: str
    agent_name: str
    default_agents: int
    min_agents: int
    max_agents: int
    default_episode_length: int
    level_field: Optional[LevelField]
    level_count: int
    neighbour_count: int  # the paper's "Neighbour Count" specification row
    # physics steps per decision by default: what the original's Episode Length panels show (reward tables' notes)
    default_decision_period: int = 1


CATALOGUE: dict[str, EnvironmentInfo] = {
    info.id: info
    for info in (
        EnvironmentInfo("wind_farm_control", "Wind Farm Control", "WFC", "turbine", 8, 1, 16, 5000, "pattern", 9, 0),
        EnvironmentInfo("wildfire_resource_management", "Wildfire Resource Management", "WRM", "tower", 9, 9, 9, 500, "terrain_level", 10, 3),
        EnvironmentInfo("ocean_plastic_collection", "Ocean Plastic Collection", "OPC", "vessel", 3, 1, 12, 5000, None, 0, 1, 5),
        EnvironmentInfo("drone_based_reforestation", "Drone-Based Reforestation", "DBR", "drone", 3, 1, 12, 2000, "terrain_level", 10, 0, 5),
        EnvironmentInfo("aerial_wildfire_suppression", "Aerial Wildfire Suppression", "AWS", "plane", 3, 1, 12, 3000, "terrain_level", 10, 0),
    )
}

LEVEL_FIELDS: tuple[LevelField, ...] = ("pattern", "terrain_level")


def environments_with(field: str) -> list[str]:
    """Ids of the environments whose scenarios have ``field`` (a level field)."""
    return [info.id for info in CATALOGUE.values() if info.level_field == field]
