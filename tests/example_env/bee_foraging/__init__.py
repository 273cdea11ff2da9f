"""Bee Foraging, the example environment: bees fly from their hive to flowers, gather nectar and bring it home.

Everything the toolkit needs is in this folder: the entry below (registered on import), the simulator, its
reward terms, params, scripted policy and vocabulary, the reward table (rewards.yaml) and the bundled scenarios
(scenarios/). Nothing outside the folder names it.
"""

from __future__ import annotations

from pathlib import Path

from hivex_dsl.compiler.registry import EnvironmentEntry, register
from hivex_dsl.lang.spec.catalogue import EnvironmentInfo

from .params import BeeForagingParams
from .scripted import scripted_policy
from .simulator import ENV_ID, BeeForagingSimulator, state_facts
from .terms import TERMS
from .vocabulary import VOCABULARY

ENTRY = register(EnvironmentEntry(
    info=EnvironmentInfo(id=ENV_ID, title="Bee Foraging", abbreviation="BF", agent_name="bee", default_agents=3,
                         min_agents=1, max_agents=8, default_episode_length=300, level_field=None, level_count=0,
                         neighbour_count=0),
    params_model=BeeForagingParams,
    terms=TERMS,
    make_simulator=BeeForagingSimulator,
    scripted_policy=scripted_policy,
    events={"gathered": "The bee took nectar from a flower this step.",
            "delivered": "The bee unloaded nectar at the hive this step.",
            "meadow_empty": "Every flower is empty and every bee unloaded (a world event)."},
    world_events=frozenset({"meadow_empty"}),
    quantities=VOCABULARY,
    content_dir=Path(__file__).parent,
    state_facts=state_facts,
    notes=("An example for the docs and the tests, not an environment of the paper.",),
))
