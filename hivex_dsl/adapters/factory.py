"""A scenario as an environment of the RL libraries' APIs: :func:`parallel_env` (PettingZoo) and :func:`vector_env`
(Gymnasium), the package's own ``hivex_dsl.parallel_env`` and ``hivex_dsl.vector_env``. Each accepts a
CompiledScenario, a path (or a bundled scenario's name) or a plain dict; the adapters they build are imported
when called."""

from __future__ import annotations

import os
from typing import Any, Mapping, Optional, Union

from ..base.errors import KeywordError
from ..compiler import CompiledScenario, compile

ScenarioLike = Union[CompiledScenario, str, os.PathLike, Mapping[str, Any]]


def as_compiled(scenario: ScenarioLike) -> CompiledScenario:
    """``scenario`` as a CompiledScenario: as it is if it is one, else compiled."""
    return scenario if isinstance(scenario, CompiledScenario) else compile(scenario)


def parallel_env(scenario: ScenarioLike, render_mode: Optional[str] = None, split: str = "train",
                 respawn: bool = False):
    """A PettingZoo ParallelEnv of one world (accepts a CompiledScenario, a path or a plain dict).

    ``respawn=True``: agents whose own episode ends are respawned at once and never leave ``agents`` (for
    SuperSuit's vector conversion); see :class:`hivex_dsl.adapters.pettingzoo.HivexParallelEnv`.
    """
    from .pettingzoo import HivexParallelEnv

    return HivexParallelEnv(as_compiled(scenario), render_mode=render_mode, split=split, respawn=respawn)


def vector_env(scenario: ScenarioLike, num_worlds: int = 1, render_mode: Optional[str] = None, split: str = "train",
               autoreset_mode: Any = "next_step", ended_agents: str = "respawn", **unexpected: Any):
    """A Gymnasium VectorEnv of ``num_worlds`` worlds with every agent a slot (parameter sharing):
    its ``num_envs`` is worlds x agents. ``autoreset_mode``: "next_step" (default) or "same_step";
    ``ended_agents``: "respawn" (default) or "wait" (an agent whose episode ended alone sits out until its world
    restarts, ``infos["active"]`` False)."""
    from .gymnasium import HivexVectorEnv

    if "num_envs" in unexpected:
        raise KeywordError("vector_env takes num_worlds= (the number of worlds); num_envs is the slot count "
                        "it reports, worlds x agents")
    if unexpected:
        raise KeywordError(f"vector_env got unexpected keyword arguments {sorted(unexpected)}")
    return HivexVectorEnv(as_compiled(scenario), num_worlds=num_worlds, render_mode=render_mode, split=split,
                          autoreset_mode=autoreset_mode, ended_agents=ended_agents)
