"""TorchRL environments of every HIVEX environment (needs the ``torchrl`` extra), as TorchRL's and BenchMARL's
multi-agent PPO take them.

:func:`torchrl_env` is TorchRL's ``PettingZooWrapper(env, use_mask=True, done_on_any=False)`` over one world's
PettingZoo parallel env, seen through the views TorchRL's stock modules need (:func:`marl_view`, no torch needed):

- Observations: one flat float32 vector per agent (:mod:`hivex_dsl.adapters.flat`). TorchRL would read a Dict
  observation (OPC's, DBR's and AWS's ``vector`` + ``visual``) as a nested Composite that ``MultiAgentMLP`` cannot
  take; flat, the image is its pixels in C order after the vector.
- Actions: Wind Farm Control's Discrete(3) as it is; Wildfire Resource Management's and Ocean Plastic
  Collection's MultiDiscrete as one Discrete action, the branches' joint choice (:mod:`hivex_dsl.adapters.joint`:
  81 and 6 actions), since TorchRL's and BenchMARL's categorical heads take one categorical action; Drone Based
  Reforestation's and Aerial Wildfire Suppression's hybrid Dict as one Box(-1, 1) (the flat view: the continuous
  part, then each discrete branch as [-1, 1] split into equal bins), for a TanhNormal head.

Every agent is one group, ``"agents"`` (parameter sharing, the shape of TorchRL's MAPPO tutorial). Agent death
follows PettingZoo's parallel API: an agent whose own episode ends (a crash, an empty battery) leaves until its
world resets; TorchRL's ``("agents", "mask")`` is then False for it, its ``("agents", "done")`` stays True, its
observation and reward are zeros, and the action TorchRL still sends for it is accepted and ignored. The root
``done`` is every agent's (``done_on_any=False``): the world resets when its clock runs out or a world-level ending
(such as AWS's and WRM's ``fire_out``) ends every agent, never at one agent's crash. The world's global state
(PettingZoo's ``state()``, :mod:`hivex_dsl.runtime.global_state`: every agent's vector observation and the world's facts
no agent observes) is the root ``"state"`` key (``return_state=True``), for a centralised critic. The infos are not passed on: TorchRL builds
its info spec from the reset infos, which are empty; the per-step reward terms and ``hivex_episode`` summaries stay
in the parallel env's infos. So does a hybrid environment's action mask (DBR's and AWS's drop): the flat Box action
has no choice for TorchRL's mask to close; an environment with a Discrete or MultiDiscrete action and a mask would
hand it on as TorchRL reads it (``infos[agent]["action_mask"]``, joined by the joint view).
"""

from __future__ import annotations

from typing import Any, Optional

from gymnasium import spaces

from .flat import FlatParallelEnv
from .joint import JointDiscreteParallelEnv

GROUP = "agents"


def marl_view(env):
    """The PettingZoo parallel env as TorchRL's stock multi-agent modules take it: flat observations (and, for
    hybrid actions, one flat Box action), and one Discrete action for a MultiDiscrete environment."""
    env = FlatParallelEnv(env, discrete_mask=False)
    if isinstance(env.action_space(env.possible_agents[0]), spaces.MultiDiscrete):
        env = JointDiscreteParallelEnv(env)
    return env


def torchrl_env(scenario: Any = None, environment: Optional[str] = None, task: Optional[str] = None,
                level: Any = None, max_cycles: Optional[int] = None, seed: Optional[int] = None,
                device: Any = "cpu", render_mode: Optional[str] = None, split: str = "train",
                return_state: bool = True, **fields: Any):
    """One world of a scenario as a TorchRL ``PettingZooWrapper`` (see the module).

    ``scenario``, ``environment``, ``task``, ``level``, ``max_cycles`` (the episode length in ``step()`` calls)
    and other top-level scenario ``fields`` are those of the Gymnasium ids and PettingZoo modules
    (:func:`hivex_dsl.adapters.registration.make_scenario`): ``torchrl_env("ocean_plastic_collection/main")``,
    ``torchrl_env(environment="aerial_wildfire_suppression", task="find_fire", level=3, max_cycles=50)``.
    """
    from torchrl.envs.libs.pettingzoo import PettingZooWrapper
    from torchrl.envs.utils import MarlGroupMapType

    from .factory import parallel_env
    from .registration import make_scenario

    compiled = make_scenario(environment, scenario, task=task, level=level, max_cycles=max_cycles, **fields)
    env = marl_view(parallel_env(compiled, render_mode=render_mode, split=split))
    return PettingZooWrapper(env, group_map=MarlGroupMapType.ALL_IN_ONE_GROUP, use_mask=True, done_on_any=False,
                             categorical_actions=True, seed=seed, device=device, return_state=return_state)

