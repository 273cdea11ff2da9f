"""hivex-dsl: declarative HIVEX scenarios compiled to batched NumPy multi-agent environments.

>>> import hivex_dsl
>>> sc = hivex_dsl.compile("scenarios/wind_farm_control/main.yaml")     # doctest: +SKIP
>>> env = hivex_dsl.parallel_env(sc, render_mode="rgb_array")           # doctest: +SKIP
"""

from __future__ import annotations

import os
from typing import Any, Mapping, Optional, Union

from .compiler import CompiledScenario, compile, compile_all
from .errors import ActionError, HivexError, ResetNeeded, ScenarioError

__version__ = "0.1.0"

ScenarioLike = Union[CompiledScenario, str, os.PathLike, Mapping[str, Any]]


def _compiled(scenario: ScenarioLike) -> CompiledScenario:
    return scenario if isinstance(scenario, CompiledScenario) else compile(scenario)


def parallel_env(scenario: ScenarioLike, render_mode: Optional[str] = None, split: str = "train"):
    """A PettingZoo ParallelEnv of one world (accepts a CompiledScenario, a path or a plain dict)."""
    from .adapters.pettingzoo import HivexParallelEnv

    return HivexParallelEnv(_compiled(scenario), render_mode=render_mode, split=split)


def vector_env(scenario: ScenarioLike, num_envs: int = 1, render_mode: Optional[str] = None, split: str = "train"):
    """A Gymnasium VectorEnv of ``num_envs`` worlds with every agent a slot (parameter sharing)."""
    from .adapters.gymnasium import HivexVectorEnv

    return HivexVectorEnv(_compiled(scenario), num_worlds=num_envs, render_mode=render_mode, split=split)


__all__ = ["ActionError", "CompiledScenario", "HivexError", "ResetNeeded", "ScenarioError", "compile",
           "compile_all", "parallel_env", "vector_env", "__version__"]
