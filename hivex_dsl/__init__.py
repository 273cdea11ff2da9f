"""hivex-dsl: declarative HIVEX scenarios compiled to batched NumPy multi-agent environments.

>>> import hivex_dsl
>>> sc = hivex_dsl.compile("scenarios/wind_farm_control/main.yaml")     # doctest: +SKIP
>>> env = hivex_dsl.parallel_env(sc, render_mode="rgb_array")           # doctest: +SKIP
"""

from __future__ import annotations

import os
from typing import Any, Mapping, Optional, Union

from . import _moved
from .base.errors import ActionError, HivexError, ResetNeeded, ScenarioError
from .compiler import CompiledScenario, compile, compile_all

_moved.install()  # old module paths (hivex_dsl.errors, hivex_dsl.spec, ...) import their moved modules

__version__ = "0.1.0"

ScenarioLike = Union[CompiledScenario, str, os.PathLike, Mapping[str, Any]]


def _compiled(scenario: ScenarioLike) -> CompiledScenario:
    return scenario if isinstance(scenario, CompiledScenario) else compile(scenario)


def parallel_env(scenario: ScenarioLike, render_mode: Optional[str] = None, split: str = "train",
                 respawn: bool = False):
    """A PettingZoo ParallelEnv of one world (accepts a CompiledScenario, a path or a plain dict).

    ``respawn=True``: agents whose own episode ends are respawned at once and never leave ``agents`` (for
    SuperSuit's vector conversion); see :class:`hivex_dsl.adapters.pettingzoo.HivexParallelEnv`.
    """
    from .adapters.pettingzoo import HivexParallelEnv

    return HivexParallelEnv(_compiled(scenario), render_mode=render_mode, split=split, respawn=respawn)


def vector_env(scenario: ScenarioLike, num_worlds: int = 1, render_mode: Optional[str] = None, split: str = "train",
               autoreset_mode: Any = "next_step", **unexpected: Any):
    """A Gymnasium VectorEnv of ``num_worlds`` worlds with every agent a slot (parameter sharing):
    its ``num_envs`` is worlds x agents. ``autoreset_mode``: "next_step" (default) or "same_step"."""
    from .adapters.gymnasium import HivexVectorEnv

    if "num_envs" in unexpected:
        raise KeywordError("vector_env takes num_worlds= (the number of worlds); num_envs is the slot count "
                        "it reports, worlds x agents")
    if unexpected:
        raise KeywordError(f"vector_env got unexpected keyword arguments {sorted(unexpected)}")
    return HivexVectorEnv(_compiled(scenario), num_worlds=num_worlds, render_mode=render_mode, split=split,
                          autoreset_mode=autoreset_mode)


class KeywordError(HivexError, TypeError):
    """A keyword argument the function does not take (e.g. vector_env's old ``num_envs``)."""


def _register_gymnasium_ids() -> None:
    from .adapters.registration import register_gymnasium

    register_gymnasium()


_register_gymnasium_ids()


def __getattr__(name: str):
    """``hivex_dsl.errors`` and the other old top-level paths of :mod:`hivex_dsl._moved`, as attributes."""
    return _moved.moved_attribute(name)


__all__ = ["ActionError", "CompiledScenario", "HivexError", "ResetNeeded", "ScenarioError", "compile",
           "compile_all", "parallel_env", "vector_env", "__version__"]
