"""Joint-Discrete views of the MultiDiscrete environments, for libraries whose models take one Discrete action
(BenchMARL's and TorchRL's categorical heads, many MARL codebases).

The mapping: MultiDiscrete(nvec) becomes Discrete(prod(nvec)); joint action ``j`` is the branches' choices
``(a_0, ..., a_{n-1})`` read as the digits of ``j`` in the mixed radix ``nvec``, the first branch most
significant (``numpy.unravel_index(j, nvec)``): Wildfire Resource Management's four ternary branches give 81
joint actions (``j = 27 a_0 + 9 a_1 + 3 a_2 + a_3``), Ocean Plastic Collection's (2, 3) six (``j = 3 a_0 + a_1``).
Observations, rewards, endings and infos are the wrapped env's, except an action mask (``infos["action_mask"]``,
where the environment masks its branches): the joint view's is the joint actions' (``joint_mask``), a joint action
open where each of its branches' choices is. A joint action is checked as an action of the
Discrete space on the unwrapped env's own path (:mod:`hivex_dsl.sim.spaces`), so a bad one raises the same
:class:`~hivex_dsl.base.errors.ActionError` naming the agent (or slot) and the space.

:func:`joint_vector_env` wraps the Gymnasium vector env, :class:`JointDiscreteParallelEnv` a PettingZoo
ParallelEnv. The environments with Discrete or hybrid actions have nothing to join (the flat views of
:mod:`.flat` serve the hybrid ones): both refuse them with a ValueError that says so.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from gymnasium import spaces
from gymnasium.vector import VectorEnv
from pettingzoo.utils.wrappers import BaseParallelWrapper

from ..sim.spaces import mask_row, stack_agent_actions
from .flat import SlotActionView, live_agents_actions


def joint_action_space(space: spaces.Space) -> spaces.Discrete:
    """Discrete(prod(nvec)) of a MultiDiscrete(nvec) space; a ValueError for any other space."""
    if not isinstance(space, spaces.MultiDiscrete) or space.nvec.ndim != 1:
        raise ValueError(f"a joint-Discrete view joins the branches of a MultiDiscrete action; this environment's "
                         f"action space is {space} (use it as it is, or hivex_dsl.adapters.flat for a hybrid one)")
    return spaces.Discrete(int(np.prod(space.nvec)))


def joint_meanings(space: spaces.MultiDiscrete) -> str:
    """The mapping in words, as the hint of an ActionError."""
    return f"joint action j picks the MultiDiscrete({space.nvec.tolist()}) choices numpy.unravel_index(j, nvec)"


def split_joint(space: spaces.MultiDiscrete, joint: np.ndarray) -> np.ndarray:
    """(...) joint actions -> (..., branches) MultiDiscrete actions, int64."""
    return np.stack(np.unravel_index(np.asarray(joint, np.int64), tuple(space.nvec.tolist())), axis=-1)


def joint_mask(space: spaces.MultiDiscrete, mask: Any) -> np.ndarray:
    """(..., sum(nvec)) branch masks (or one agent's tuple of branch rows, PettingZoo's form) -> (..., prod(nvec))
    int8, joint action j open where every branch's choice in ``numpy.unravel_index(j, nvec)`` is."""
    mask = mask_row(mask).astype(bool)
    parts = np.split(mask, np.cumsum(space.nvec)[:-1], axis=-1)
    joint = parts[0]
    for part in parts[1:]:  # the first branch most significant, as split_joint reads j
        joint = (joint[..., :, None] & part[..., None, :]).reshape(joint.shape[:-1] + (-1,))
    return joint.astype(np.int8)


def _joint_masks(space: spaces.MultiDiscrete, info: dict[str, Any]) -> dict[str, Any]:
    if "action_mask" in info:
        info["action_mask"] = joint_mask(space, info["action_mask"])
    return info


class _JointActions(SlotActionView):
    """Joint Discrete actions (slots,) of a MultiDiscrete :class:`~hivex_dsl.adapters.gymnasium.HivexVectorEnv`."""

    def __init__(self, env: VectorEnv):
        branches = env.single_action_space
        super().__init__(env, joint_action_space(branches), joint_meanings(branches))

    def actions(self, actions: Any) -> np.ndarray:
        """(slots,) joint actions -> (slots, branches); checked first as actions of the Discrete space."""
        return split_joint(self.wrapped_space, self.checked(actions).reshape(self.num_envs))

    def reset(self, **kwargs: Any):
        observations, infos = self.env.reset(**kwargs)
        return observations, _joint_masks(self.wrapped_space, infos)

    def step(self, actions: Any):
        observations, rewards, terminated, truncated, infos = super().step(actions)
        return observations, rewards, terminated, truncated, _joint_masks(self.wrapped_space, infos)


def joint_vector_env(env: VectorEnv) -> VectorEnv:
    """The vector env with one Discrete action per slot (see the module)."""
    return _JointActions(env)


class JointDiscreteParallelEnv(BaseParallelWrapper):
    """A PettingZoo ParallelEnv of a MultiDiscrete environment with one Discrete action per agent."""

    def __init__(self, env):
        super().__init__(env)
        self._branches = env.action_space(env.possible_agents[0])
        self._joint = joint_action_space(self._branches)

    def action_space(self, agent: str) -> spaces.Space:
        return self._joint

    def step(self, actions: dict):
        live = self.env.agents
        if live:  # no live agent: the env says why it cannot step
            actions = live_agents_actions(self.env, actions)
            joint = stack_agent_actions(self._joint, actions, live, joint_meanings(self._branches))[0]
            actions = dict(zip(live, split_joint(self._branches, joint)))
        observations, rewards, terminations, truncations, infos = self.env.step(actions)
        return observations, rewards, terminations, truncations, self._infos(infos)

    def reset(self, seed=None, options=None):
        observations, infos = self.env.reset(seed=seed, options=options)
        return observations, self._infos(infos)

    def _infos(self, infos: dict[str, dict]) -> dict[str, dict]:
        for info in infos.values():
            _joint_masks(self._branches, info)
        return infos
