"""Flat views for libraries that refuse Dict spaces (SB3's and RLlib's default models, TorchRL's MLPs).

The mapping, for every environment:

- Observation: a Dict observation becomes one float32 Box: its parts in the space's key order
  (``vector`` then ``visual``), each flattened in C order (``visual`` (H, W, C) row by row) and
  concatenated; bounds are the parts' bounds. Box observations stay as they are.
- Action: a hybrid Dict action {``continuous``: Box(-1, 1, (k,)), ``discrete``: MultiDiscrete(n)}
  becomes one Box(-1, 1, (k + len(n),)): the first k values are the continuous part as they are;
  value k + i in [-1, 1] picks discrete choice ``min(n_i - 1, floor((x + 1) / 2 * n_i))``, i.e.
  splits [-1, 1] into n_i equal bins (for n_i = 2: x < 0 -> 0, x >= 0 -> 1). Discrete and
  MultiDiscrete actions stay as they are (SB3 and RLlib take them; for TorchRL's and BenchMARL's one categorical
  head, :mod:`.joint` joins MultiDiscrete branches). Flat actions are checked as
  actions of the flat Box on the unwrapped env's own path (:mod:`hivex_dsl.sim.spaces`) before they are
  split: a value outside [-1, 1], NaN, a boolean, a wrong shape or a torch tensor that requires grad
  raises the same :class:`~hivex_dsl.base.errors.ActionError` as the unwrapped env (SB3 and RLlib clip
  their actions into the Box first).

:func:`flat_vector_env` wraps the Gymnasium vector env, :class:`FlatParallelEnv` a PettingZoo
ParallelEnv (before SuperSuit's vector conversion); both keep our infos, except that a hybrid environment's action
mask (``infos["action_mask"]``, over its discrete branches) moves to ``infos["discrete_action_mask"]``: the flat
Box has no discrete choices for it to mask (TorchRL would read an ``action_mask`` as a mask of the whole action), so
it stays there for a consumer that bins the discrete values itself. Like the parallel env, the views accept
and ignore an action for an agent that ended earlier in its world's episode (TorchRL sends one for every agent).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from gymnasium import spaces
from gymnasium.vector import VectorActionWrapper, VectorEnv, VectorWrapper
from gymnasium.vector.utils import batch_space
from pettingzoo.utils.wrappers import BaseParallelWrapper

from ..sim.spaces import check_slot_actions, mask_row, stack_agent_actions


def live_agents_actions(env, actions: Any) -> Any:
    """``actions`` without those for agents that ended earlier in this world's episode, as the parallel env itself
    accepts and ignores them (TorchRL's PettingZooWrapper, and BenchMARL on it, send one for every agent of a group):
    a view checks its own actions before the env does, so it drops them first. A name that is no agent stays, to be
    refused."""
    live = env.agents
    if isinstance(actions, dict) and len(actions) > len(live):
        possible = env.possible_agents
        return {a: action for a, action in actions.items() if a in live or a not in possible}
    return actions


def is_hybrid(space: spaces.Space) -> bool:
    return isinstance(space, spaces.Dict) and set(space.spaces) == {"continuous", "discrete"}


DISCRETE_MASK_KEY = "discrete_action_mask"  # where the flat views of a hybrid environment keep its action mask


def moved_mask(info: dict[str, Any]) -> dict[str, Any]:
    """``info`` (a vector env's infos, or one agent's) with ``action_mask`` under :data:`DISCRETE_MASK_KEY`, as the
    row of the discrete branches' choices ((num_envs, N) or (N,) int8; see :func:`hivex_dsl.sim.spaces.mask_row`)."""
    if "action_mask" in info:
        info[DISCRETE_MASK_KEY] = mask_row(info.pop("action_mask"))
    return info


def flat_observation_space(space: spaces.Space) -> spaces.Space:
    if not isinstance(space, spaces.Dict):
        return space
    parts = list(space.spaces.values())
    low = np.concatenate([np.broadcast_to(p.low, p.shape).ravel() for p in parts]).astype(np.float32)
    high = np.concatenate([np.broadcast_to(p.high, p.shape).ravel() for p in parts]).astype(np.float32)
    return spaces.Box(low, high, dtype=np.float32)


def flatten_observation(space: spaces.Space, observation: Any, lead: int = 0) -> np.ndarray:
    """One observation (``lead`` = 0) or a batch of them (``lead`` = 1 leading axis) as flat float32."""
    if not isinstance(space, spaces.Dict):
        return observation
    shape = np.shape(observation[next(iter(space.spaces))])[:lead]
    return np.concatenate([np.asarray(observation[k], np.float32).reshape(shape + (-1,)) for k in space.spaces],
                          axis=-1)


def flat_action_space(space: spaces.Space) -> spaces.Space:
    if not is_hybrid(space):
        return space
    size = space["continuous"].shape[0] + len(space["discrete"].nvec)
    return spaces.Box(-1.0, 1.0, (size,), np.float32)


def flat_action_meanings(space: spaces.Space) -> str:
    """The flat Box's layout for a hybrid space, as the hint of an ActionError: 'values 0-2 continuous, ...'."""
    k, nvec = space["continuous"].shape[0], space["discrete"].nvec.tolist()
    return (f"{_positions(0, k)}: the continuous part; {_positions(k, k + len(nvec))}: the discrete part "
            f"MultiDiscrete({nvec}), [-1, 1] split into equal bins")


def _positions(start: int, stop: int) -> str:
    return f"value {start}" if stop == start + 1 else f"values {start}..{stop - 1}"


def unflatten_action(space: spaces.Space, action: Any) -> Any:
    """A flat action (..., k + m) -> the hybrid Dict action (see the module's mapping)."""
    if not is_hybrid(space):
        return action
    action = np.asarray(action, np.float32)
    continuous = space["continuous"]
    k = continuous.shape[0]
    nvec = space["discrete"].nvec
    bins = np.floor((np.clip(action[..., k:], -1.0, 1.0) + 1.0) * 0.5 * nvec).astype(np.int64)
    return {"continuous": np.clip(action[..., :k], continuous.low, continuous.high).astype(np.float32),
            "discrete": np.minimum(bins, nvec - 1)}


class KeepsAutoresetMode:
    """``autoreset_mode`` of the wrapped env, which TorchRL's GymWrapper reads from the env it is given."""

    @property
    def autoreset_mode(self):
        return self.env.unwrapped.autoreset_mode


class _FlatObservations(KeepsAutoresetMode, VectorWrapper):
    """Not a VectorObservationWrapper: that refuses SAME_STEP, whose ``final_obs`` this one flattens too."""

    def __init__(self, env: VectorEnv):
        super().__init__(env)
        self._dict_space = env.single_observation_space
        self.single_observation_space = flat_observation_space(self._dict_space)
        self.observation_space = batch_space(self.single_observation_space, self.num_envs)

    def observations(self, observations: Any) -> Any:
        return flatten_observation(self._dict_space, observations, lead=1)

    def reset(self, **kwargs: Any):
        obs, infos = self.env.reset(**kwargs)
        return self.observations(obs), infos

    def step(self, actions: Any):
        obs, rewards, terminated, truncated, infos = self.env.step(actions)
        obs = self.observations(obs)
        if "final_obs" in infos:  # SAME_STEP: the last observations of ended slots, flat as well
            final = infos["final_obs"].copy()
            for slot in np.flatnonzero(infos["_final_obs"]):
                final[slot] = flatten_observation(self._dict_space, final[slot])
            infos["final_obs"] = final
        return obs, rewards, terminated, truncated, infos


class SlotActionView(KeepsAutoresetMode, VectorActionWrapper):
    """A vector env seen through another action space per slot: ``single_action_space`` is the view's, the
    wrapped env's is ``self.wrapped_space``, and :meth:`checked` validates the view's actions on the vector env's
    own path (an ActionError names the slot's agent and world, with ``meanings`` as its hint)."""

    def __init__(self, env: VectorEnv, single_action_space: spaces.Space, meanings: str):
        super().__init__(env)
        self.wrapped_space = env.single_action_space
        self.single_action_space = single_action_space
        self.action_space = batch_space(single_action_space, self.num_envs)
        self._shape, self._agent_names = env.unwrapped.core.shape, env.unwrapped.compiled.agent_names
        self._meanings = meanings

    def checked(self, actions: Any) -> np.ndarray:
        """(slots, ...) actions of the view -> (worlds, agents, ...), checked as actions of its space."""
        return check_slot_actions(self.single_action_space, actions, self._shape, self._agent_names, self._meanings)


class _FlatActions(SlotActionView):
    """Flat actions (slots, k + m) of a hybrid :class:`~hivex_dsl.adapters.gymnasium.HivexVectorEnv`."""

    def __init__(self, env: VectorEnv):
        hybrid = env.single_action_space
        super().__init__(env, flat_action_space(hybrid), flat_action_meanings(hybrid))

    def actions(self, actions: Any) -> Any:
        """(slots, k + m) flat actions -> the hybrid dict of (slots, k) and (slots, m) arrays; checked first
        (a value outside [-1, 1], NaN, a boolean... raises an ActionError naming the slot's agent and world)."""
        checked = self.checked(actions)
        return unflatten_action(self.wrapped_space, checked.reshape((self.num_envs,) + checked.shape[2:]))

    def reset(self, **kwargs: Any):
        observations, infos = self.env.reset(**kwargs)
        return observations, moved_mask(infos)

    def step(self, actions: Any):
        observations, rewards, terminated, truncated, infos = super().step(actions)
        return observations, rewards, terminated, truncated, moved_mask(infos)


def flat_vector_env(env: VectorEnv) -> VectorEnv:
    """The vector env with a flat Box observation and (hybrid envs) a flat Box action; see the module."""
    if isinstance(env.single_action_space, spaces.Dict):
        env = _FlatActions(env)
    if isinstance(env.single_observation_space, spaces.Dict):
        env = _FlatObservations(env)
    return env


class FlatParallelEnv(BaseParallelWrapper):
    """A PettingZoo ParallelEnv with flat observations and actions per agent (see the module). ``discrete_mask``
    false drops a hybrid environment's action mask instead of moving it (TorchRL builds its info spec from the first
    infos and cannot read the per-step ones)."""

    def __init__(self, env, discrete_mask: bool = True):
        super().__init__(env)
        self._discrete_mask = discrete_mask
        agent = env.possible_agents[0]
        self._dict_obs, self._hybrid = env.observation_space(agent), env.action_space(agent)
        self._obs_space = flat_observation_space(self._dict_obs)
        self._act_space = flat_action_space(self._hybrid)

    def observation_space(self, agent: str) -> spaces.Space:
        return self._obs_space

    def action_space(self, agent: str) -> spaces.Space:
        return self._act_space

    def _flat(self, observations: dict) -> dict:
        return {a: flatten_observation(self._dict_obs, o) for a, o in observations.items()}

    def reset(self, seed=None, options=None):
        observations, infos = self.env.reset(seed=seed, options=options)
        return self._flat(observations), self._infos(infos)

    def step(self, actions: dict):
        if is_hybrid(self._hybrid) and self.env.agents:  # no live agent: the env says why it cannot step
            actions = self._unflattened(actions)
        observations, rewards, terminations, truncations, infos = self.env.step(actions)
        for info in infos.values():
            if "terminal_observation" in info:
                info["terminal_observation"] = flatten_observation(self._dict_obs, info["terminal_observation"])
        return self._flat(observations), rewards, terminations, truncations, self._infos(infos)

    def _infos(self, infos: dict[str, dict]) -> dict[str, dict]:
        """Per-agent infos, a hybrid environment's action masks moved (see the module)."""
        if is_hybrid(self._hybrid):
            for info in infos.values():
                moved_mask(info)
                if not self._discrete_mask:
                    info.pop(DISCRETE_MASK_KEY, None)
        return infos

    def _unflattened(self, actions: Any) -> dict:
        """{agent: flat action (k + m,)} -> {agent: hybrid dict action}; checked first, on the parallel env's
        path, as actions of the flat Box (an ActionError names the agent)."""
        live = self.env.agents
        actions = live_agents_actions(self.env, actions)
        flat = stack_agent_actions(self._act_space, actions, live, flat_action_meanings(self._hybrid))[0]
        parts = unflatten_action(self._hybrid, flat)
        return {a: {"continuous": c, "discrete": d} for a, c, d in zip(live, parts["continuous"], parts["discrete"])}
