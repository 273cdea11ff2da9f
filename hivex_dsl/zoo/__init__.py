"""Layer 7, adapters: zoo/ belongs to the adapters layer; it stays at ``hivex_dsl.zoo``, a public path.

PettingZoo's module convention, one module per environment::

    from hivex_dsl.zoo import ocean_plastic_collection_v0
    env = ocean_plastic_collection_v0.parallel_env(task="plastic_collection", max_cycles=500)
    aec = ocean_plastic_collection_v0.env(render_mode="human")

Each module has ``env(**kwargs)`` (AEC), ``parallel_env(**kwargs)``, ``raw_env`` (the AEC class) and
takes ``scenario``, ``task``, ``level``, ``max_cycles`` (the episode length), ``render_mode``,
``split``, ``respawn`` and any top-level scenario field (see
:func:`hivex_dsl.adapters.registration.make_scenario`). Imports: adapters (and, through them, the layers below).
"""

from __future__ import annotations

from typing import Any

from pettingzoo.utils.conversions import parallel_to_aec_wrapper
from pettingzoo.utils.wrappers import OrderEnforcingWrapper

from ..adapters.registration import make_scenario
from ..sim.spaces import stack_agent_actions

__all__ = ["module_api"]


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
