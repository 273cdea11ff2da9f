"""An environment's identity (:class:`EnvironmentInfo`), and the five HIVEX environments' as the paper lists them.

An environment states its identity, agent bounds, episode length and which difficulty axis it has (layout
``pattern`` or ``terrain_level``) in the :class:`EnvironmentInfo` of its registry entry
(:mod:`hivex_dsl.compiler.registry`). :data:`PAPER_ENVIRONMENTS` holds the paper's five (pure data): the
catalogue is open, and any other environment (a package under hivex_dsl/envs/, or one another installed package
declares) brings its own info. The paper's five come first in every listing, in the paper's order.
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


PAPER_ENVIRONMENTS: dict[str, EnvironmentInfo] = {
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


def listing_key(env_id: str) -> tuple[int, str]:
    """The order of environments in every listing: the paper's five in the paper's order, then the others by id."""
    ids = list(PAPER_ENVIRONMENTS)
    return (ids.index(env_id), "") if env_id in PAPER_ENVIRONMENTS else (len(ids), env_id)
