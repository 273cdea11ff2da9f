"""Layer 7, adapters: zoo/ belongs to the adapters layer; it stays at ``hivex_dsl.zoo``, a public path.

PettingZoo's module convention, one module ``<id>_v0`` per registered environment, made from the registry
when first imported (no file per environment: a finder on ``sys.meta_path`` builds it, so both
``from hivex_dsl.zoo import wind_farm_control_v0`` and ``import hivex_dsl.zoo.wind_farm_control_v0`` work)::

    from hivex_dsl.zoo import ocean_plastic_collection_v0
    env = ocean_plastic_collection_v0.parallel_env(task="plastic_collection", max_cycles=500)
    aec = ocean_plastic_collection_v0.env(render_mode="human")

Each module has ``env(**kwargs)`` (AEC), ``parallel_env(**kwargs)``, ``raw_env`` (the AEC class) and
takes ``scenario``, ``task``, ``level``, ``max_cycles`` (the episode length), ``render_mode``,
``split``, ``respawn`` and any top-level scenario field (see
:func:`hivex_dsl.adapters.registration.make_scenario`). Imports: adapters (and, through them, the layers below).
"""

from __future__ import annotations

import importlib.abc
import importlib.machinery
import sys
from types import ModuleType
from typing import Any, Optional, Sequence

from pettingzoo.utils.conversions import parallel_to_aec_wrapper
from pettingzoo.utils.wrappers import OrderEnforcingWrapper

from ..adapters.registration import make_scenario
from ..compiler import registry
from ..sim.spaces import stack_agent_actions

__all__ = ["module_api", "module_name"]
SUFFIX = "_v0"


def module_api(environment: str):
    """(env, parallel_env, raw_env) of one environment."""

    def parallel_env(scenario: Any = None, task=None, level=None, max_cycles=None, render_mode=None,
                     split: str = "train", respawn: bool = False, **fields: Any):
        from ..adapters.pettingzoo import HivexParallelEnv

        compiled = make_scenario(environment, scenario, task, level, max_cycles, **fields)
        return HivexParallelEnv(compiled, render_mode=render_mode, split=split, respawn=respawn)

    class raw_env(parallel_to_aec_wrapper):  # noqa: N801 - PettingZoo's name
        """The AEC view of :func:`parallel_env` (PettingZoo's ``raw_env``)."""

        def __init__(self, **kwargs: Any):
            super().__init__(parallel_env(**kwargs))

        def step(self, action: Any) -> None:
            """Take the selected agent's action, checked at once (an ActionError naming the agent and the space,
            nothing changed), as the parallel env checks it: PettingZoo's wrapper would keep a bad action and
            fail only at the cycle's last agent, on every retry."""
            agent = self.agent_selection
            if not (self.terminations[agent] or self.truncations[agent]):
                sim = self.env.core.sim
                stack_agent_actions(sim.action_space, {agent: action}, [agent], sim.action_meanings)
            super().step(action)

    def env(**kwargs: Any):
        """The AEC env with PettingZoo's order enforcing wrapper."""
        return OrderEnforcingWrapper(raw_env(**kwargs))

    raw_env.__name__ = raw_env.__qualname__ = "raw_env"
    return env, parallel_env, raw_env


def module_name(environment: str) -> str:
    """``wind_farm_control`` -> ``hivex_dsl.zoo.wind_farm_control_v0``."""
    return f"{__name__}.{environment}{SUFFIX}"


def _environment_of(fullname: str) -> Optional[str]:
    """The registered environment a ``hivex_dsl.zoo.<id>_v0`` module name stands for, else None."""
    prefix = f"{__name__}."
    if not (fullname.startswith(prefix) and fullname.endswith(SUFFIX)):
        return None
    environment = fullname[len(prefix):-len(SUFFIX)]
    return environment if "." not in environment and environment in registry.environments() else None


class _ZooModules(importlib.abc.MetaPathFinder, importlib.abc.Loader):
    """Finds and builds ``hivex_dsl.zoo.<id>_v0`` for every registered environment."""

    def find_spec(self, fullname: str, path: Optional[Sequence[str]], target: Any = None):
        if _environment_of(fullname) is None:
            return None
        return importlib.machinery.ModuleSpec(fullname, self, origin="hivex_dsl.zoo (generated from the registry)")

    def create_module(self, spec) -> None:
        return None  # Python's default module

    def exec_module(self, module: ModuleType) -> None:
        environment = _environment_of(module.__name__)
        module.__doc__ = (f"PettingZoo module of {environment}: ``env()``, ``parallel_env()``, ``raw_env`` "
                          "(see :mod:`hivex_dsl.zoo`).")
        module.env, module.parallel_env, module.raw_env = module_api(environment)
        module.__all__ = ["env", "parallel_env", "raw_env"]


if not any(isinstance(finder, _ZooModules) for finder in sys.meta_path):
    sys.meta_path.append(_ZooModules())


def __getattr__(name: str) -> ModuleType:
    """``from hivex_dsl.zoo import <id>_v0`` (and ``hivex_dsl.zoo.<id>_v0`` as an attribute) imports the module."""
    if _environment_of(f"{__name__}.{name}") is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    return importlib.import_module(f"{__name__}.{name}")


def __dir__() -> list[str]:
    return sorted(list(globals()) + [f"{environment}{SUFFIX}" for environment in registry.environments()])
