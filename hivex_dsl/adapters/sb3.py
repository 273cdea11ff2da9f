"""A Stable-Baselines3 VecEnv over the Gymnasium vector env (needs the ``sb3`` extra).

SB3 resets a slot in the step that ends it and wants the last observation in
``infos[i]["terminal_observation"]``: that is the vector env's SAME_STEP mode, used here. Flat
observations and actions (:func:`hivex_dsl.adapters.flat.flat_vector_env`) let SB3's default
``MlpPolicy`` run on every environment. ``infos[i]`` also carries the slot's ``hivex_episode``
summary on the step its episode ends; ``VecMonitor`` counts per-agent returns and lengths. Where the environment
masks actions, ``infos[i]`` (and ``reset_infos[i]``) hold the slot's row of the vector env's mask under the key it
has there (``discrete_action_mask`` in the flat view of a hybrid environment: :mod:`hivex_dsl.adapters.flat`).
"""

from __future__ import annotations

from typing import Any, Optional, Sequence

import numpy as np
from stable_baselines3.common.vec_env.base_vec_env import VecEnv

from .flat import DISCRETE_MASK_KEY, flat_vector_env
from .gymnasium import slot_values


MASK_KEYS = ("action_mask", DISCRETE_MASK_KEY)


class SB3VecEnv(VecEnv):
    """One SB3 slot per (world, agent) of a :class:`~hivex_dsl.adapters.gymnasium.HivexVectorEnv`."""

    def __init__(self, scenario: Any, num_worlds: int = 1, flat: bool = True, split: str = "train"):
        from .factory import vector_env

        env = vector_env(scenario, num_worlds=num_worlds, autoreset_mode="same_step", split=split)
        self.env = flat_vector_env(env) if flat else env
        super().__init__(self.env.num_envs, self.env.single_observation_space, self.env.single_action_space)
        self._actions: Any = None

    def reset(self):
        seed = self._seeds[0] if self._seeds and self._seeds[0] is not None else None
        observations, infos = self.env.reset(seed=seed)
        self._reset_seeds()
        self.reset_infos = self._slot_infos(infos)
        return observations

    def step_async(self, actions: np.ndarray) -> None:
        self._actions = actions

    def step_wait(self):
        observations, rewards, terminated, truncated, infos = self.env.step(self._actions)
        dones = terminated | truncated
        slot_infos = self._slot_infos(infos)
        for i in np.flatnonzero(dones):
            slot_infos[i]["terminal_observation"] = infos["final_obs"][i]
            slot_infos[i]["TimeLimit.truncated"] = bool(truncated[i] and not terminated[i])
            slot_infos[i]["hivex_episode"] = slot_values(infos["hivex_episode"], i)
        return observations, rewards.astype(np.float32), dones, slot_infos

    def _slot_infos(self, infos: dict[str, Any]) -> list[dict]:
        """One info dict per slot, holding its row of the action mask where the vector env's infos have one."""
        slot_infos: list[dict] = [{} for _ in range(self.num_envs)]
        for key in MASK_KEYS:
            if key in infos:
                for info, row in zip(slot_infos, infos[key]):
                    info[key] = row
        return slot_infos

    def close(self) -> None:
        self.env.close()

    def get_attr(self, attr_name: str, indices: Optional[Sequence[int]] = None) -> list:
        return [getattr(self.env, attr_name, None)] * len(self._get_indices(indices))

    def set_attr(self, attr_name: str, value: Any, indices: Optional[Sequence[int]] = None) -> None:
        setattr(self.env, attr_name, value)

    def env_method(self, method_name: str, *args: Any, indices: Optional[Sequence[int]] = None, **kwargs: Any) -> list:
        return [getattr(self.env, method_name)(*args, **kwargs)] * len(self._get_indices(indices))

    def env_is_wrapped(self, wrapper_class: type, indices: Optional[Sequence[int]] = None) -> list[bool]:
        return [False] * len(self._get_indices(indices))

    def get_images(self) -> list:
        return [self.env.unwrapped.core.render(0)]
