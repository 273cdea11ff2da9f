"""Gymnasium VectorEnv with parameter sharing: every (world, agent) pair is one slot.

``num_worlds`` copies of the scenario step together; the slots are the flattened
(world, agent) pairs, so ``num_envs == num_worlds * agents`` and one policy acts for all.
Autoreset follows Gymnasium's NEXT_STEP mode per world: a world whose agents have all ended
reports its last observation with terminated/truncated, and the next ``step`` resets it
(ignoring its actions) and returns its first observation with reward 0.
"""

from __future__ import annotations

from typing import Any, Optional

import numpy as np
from gymnasium.vector import AutoresetMode, VectorEnv
from gymnasium.vector.utils import batch_space

from ..compiler import CompiledScenario
from ..runtime import BatchedEnv, Split
from ..spaces import check_actions


def _flatten(tree: Any, slots: int) -> Any:
    if isinstance(tree, dict):
        return {k: _flatten(v, slots) for k, v in tree.items()}
    return tree.reshape((slots,) + tree.shape[2:])


def _unflatten(tree: Any, shape: tuple[int, int]) -> Any:
    if isinstance(tree, dict):
        return {k: _unflatten(v, shape) for k, v in tree.items()}
    array = np.asarray(tree)
    if array.shape[:1] != (shape[0] * shape[1],):
        raise ValueError(f"actions have leading size {array.shape[:1]}, expected ({shape[0] * shape[1]},) slots")
    return array.reshape(shape + array.shape[1:])


class HivexVectorEnv(VectorEnv):
    """Slots are (world, agent) pairs in world-major order: slot = world * agents + agent."""

    def __init__(self, compiled: CompiledScenario, num_worlds: int = 1, render_mode: Optional[str] = None,
                 split: Split = "train"):
        if render_mode not in (None, "rgb_array"):
            raise ValueError(f"render_mode must be None or 'rgb_array', got {render_mode!r}")
        seeds = getattr(compiled.seeds, split, None)
        if isinstance(seeds, tuple):
            raise ValueError(
                f"the scenario's {split} seeds are a per-episode list {list(seeds)[:5]}: the vector env's worlds start "
                "their episodes on their own and continue one random stream, so they cannot play the listed seeds in "
                "turn; use parallel_env for per-episode seeds, or give this split one integer seed")
        self.compiled = compiled
        self.core = BatchedEnv(compiled, batch=num_worlds, split=split)
        self.num_worlds = num_worlds
        self.agents_per_world = compiled.agents
        self.num_envs = num_worlds * compiled.agents
        self.single_observation_space = self.core.sim.observation_space
        self.single_action_space = self.core.sim.action_space
        self.observation_space = batch_space(self.single_observation_space, self.num_envs)
        self.action_space = batch_space(self.single_action_space, self.num_envs)
        self.render_mode = render_mode
        self.metadata = {"autoreset_mode": AutoresetMode.NEXT_STEP, "render_modes": ["rgb_array"],
                         "render_fps": self.core.sim.render_fps}
        self._pending_reset = np.zeros(num_worlds, bool)

    def reset(self, *, seed: Optional[int] = None, options: Optional[dict] = None):
        if seed is not None and not isinstance(seed, (int, np.integer)):
            raise ValueError("seed must be one integer: it seeds the stream shared by every world")
        observations = self.core.reset(None if seed is None else int(seed))
        self._pending_reset[:] = False
        return _flatten(observations, self.num_envs), {}

    def step(self, actions: Any):
        shape = self.core.shape
        batched = check_actions(self.single_action_space, _unflatten(actions, shape),
                                self.compiled.agent_names, self.core.sim.action_meanings)
        pending = self._pending_reset
        restarting = pending.any()
        # only worlds that ended a step ago restart, so the sums of episodes ending now stay for the infos
        result = self.core.step(batched, restart=pending if restarting else None)
        observations, rewards = result.observations, result.rewards
        terminated, truncated = result.terminated, result.truncated
        infos = self._infos(result)
        if restarting:  # those worlds return their first observation, reward 0 and no ending
            resetting = pending[:, None]
            rewards = np.where(resetting, 0.0, rewards)
            terminated, truncated = terminated & ~resetting, truncated & ~resetting
        infos["active"] = self.core.alive.reshape(-1).copy()
        self._pending_reset = ~self.core.alive.any(axis=1)
        return (_flatten(observations, self.num_envs), rewards.reshape(-1), terminated.reshape(-1),
                truncated.reshape(-1), infos)

    def _infos(self, result) -> dict[str, Any]:
        ended = result.ended & ~self._pending_reset[:, None]
        core = self.core
        infos: dict[str, Any] = {"reward_terms": {k: v.reshape(-1) for k, v in result.terms.items()}}
        if result.env_info:
            infos["env"] = {k: np.asarray(v).reshape(-1) for k, v in result.env_info.items()}
        if ended.any():
            infos["episode"] = {
                "return": np.where(ended, core.returns, 0.0).reshape(-1),
                "length": np.where(ended, core.lengths, 0).reshape(-1),
                "reward_terms": {k: np.where(ended, s, 0.0).reshape(-1) for k, s in core.term_sums.items()},
                "statistics": {k: np.where(ended, s, 0.0).reshape(-1) for k, s in core.statistic_sums().items()},
            }
            infos["_episode"] = ended.reshape(-1)
        return infos

    def render(self):
        return None if self.render_mode is None else self.core.render(0)

    def close_extras(self, **kwargs: Any) -> None:
        """Nothing to release: the worlds are only NumPy arrays."""
