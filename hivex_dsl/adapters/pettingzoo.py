"""PettingZoo ParallelEnv: the batch-of-one view of :class:`hivex_dsl.runtime.BatchedEnv`."""

from __future__ import annotations

from typing import Any, Optional

import numpy as np
from pettingzoo import ParallelEnv

from ..base.errors import ResetNeeded
from ..compiler import CompiledScenario
from ..runtime.batched import BatchedEnv, Split
from ..runtime.global_state import GlobalState
from ..sim.spaces import sampling_mask, stack_agent_actions
from .human import Rendering, available_render_modes, check_render_mode


def _unbatch(observations: Any, world: int, agent: int) -> Any:
    """One agent's observation as fresh writable arrays."""
    if isinstance(observations, dict):
        return {key: np.array(value[world, agent]) for key, value in observations.items()}
    return np.array(observations[world, agent])


def _per_agent(observations: Any) -> list:
    """World 0's observation of every agent: (1, agents, ...) arrays (or a dict of them) -> a list of
    fresh writable arrays (one copy of the batch, then views of it per agent)."""
    if isinstance(observations, dict):
        keys = list(observations)
        return [dict(zip(keys, parts)) for parts in zip(*(np.array(observations[k][0]) for k in keys))]
    return list(np.array(observations[0]))


def _per_agent_values(named: dict[str, np.ndarray], agents: int) -> list[dict[str, Any]]:
    """{name: (1, agents) array} -> one {name: Python value} dict per agent."""
    names = list(named)
    columns = [np.asarray(named[k])[0].tolist() for k in names]
    return [dict(zip(names, row)) for row in zip(*columns)] if names else [{} for _ in range(agents)]


class HivexParallelEnv(Rendering, ParallelEnv):
    """One world of a compiled scenario behind PettingZoo's parallel API.

    ``infos[agent]["reward_terms"]`` holds the unweighted value of every active reward term this
    step, ``infos[agent]["env"]`` the environment's own facts of the step (if it reports any); when an
    agent's episode ends, ``infos[agent]["hivex_episode"]`` holds its return, length and per-term sums.
    Where the environment masks actions (DBR's and AWS's drop: :class:`~hivex_dsl.runtime.contract.MasksActions`),
    every reset's and step's ``infos[agent]["action_mask"]`` says which choices of the discrete branches are open at
    the agent's next decision, as PettingZoo's own environments and its API test take it: the mask
    ``action_space(agent).sample(mask=...)`` takes (int8, 1 open; for the hybrid Dict ``{"continuous": None,
    "discrete": (branch rows,)}``: :func:`hivex_dsl.sim.spaces.sampling_mask`). A closed choice is still accepted and
    does nothing.
    A reset without a seed follows the scenario's seeds for ``split`` (a later copy of the same
    scenario in the process plays a child stream of them: copies are different worlds unless seeded).
    Observations are fresh writable arrays.

    Agent death: by PettingZoo's convention an agent whose episode ended leaves ``agents`` until
    the world resets. With ``respawn=True`` (for SuperSuit's ``pettingzoo_env_to_vec_env_v1`` and
    other consumers that need a constant agent list) an agent whose own episode ends while its world goes on
    reports ``terminated`` and its ``hivex_episode``, is respawned at once (ML-Agents' semantics) and
    stays in ``agents``; its step observation is its first one and its last is in
    ``infos[agent]["terminal_observation"]`` (SB3's key). The world ends as a whole (every agent
    leaves ``agents``) only when its clock runs out or a world-level ending happens (a world event
    such as ``fire_out``, a per-world ending expression), never because agents' own endings coincide:
    a one-agent world's agent, or drones whose batteries empty on one step, respawn.

    Global state (centralised critics): :meth:`state` is the world's (K,) float32 state at the last decision and
    ``state_space`` its Box (see :mod:`hivex_dsl.runtime.global_state`: every agent's vector observation in agent order,
    zeros for an agent that left ``agents`` before this step, then the world facts no agent observes).
    """

    def __init__(self, compiled: CompiledScenario, render_mode: Optional[str] = None, split: Split = "train",
                 respawn: bool = False):
        check_render_mode(render_mode)
        self.compiled = compiled
        self.core = BatchedEnv(compiled, batch=1, split=split, distinct_copies=True)
        self.render_mode = render_mode
        self.respawn = respawn
        self.possible_agents = list(compiled.agent_names)
        self.agents: list[str] = []
        self.metadata = {"name": f"hivex_{compiled.environment}_v0", "render_modes": available_render_modes(),
                         "is_parallelizable": True, "render_fps": self.core.sim.render_fps}
        self._index = {name: i for i, name in enumerate(self.possible_agents)}
        self.observation_spaces = {a: self.core.sim.observation_space for a in self.possible_agents}
        self.action_spaces = {a: self.core.sim.action_space for a in self.possible_agents}
        self.global_state = GlobalState.of(self.core)
        self.state_space = self.global_state.space

    def observation_space(self, agent: str):
        return self.observation_spaces[agent]

    def action_space(self, agent: str):
        return self.action_spaces[agent]

    def state(self) -> np.ndarray:
        """(K,) float32: the world's global state at the last decision, in ``state_space`` (see
        :mod:`hivex_dsl.runtime.global_state`; ``global_state.components`` names its parts)."""
        return self.global_state(self.core)[0]

    def reset(self, seed: Optional[int] = None, options: Optional[dict] = None):
        observations = self.core.reset(seed)
        self.agents = list(self.possible_agents)
        obs = {a: _unbatch(observations, 0, i) for i, a in enumerate(self.agents)}
        infos: dict[str, dict[str, Any]] = {a: {} for a in self.agents}
        self._report_masks(infos)
        self._show()
        return obs, infos

    def step(self, actions: dict[str, Any]):
        """Step the world with ``{agent: action}`` for exactly the live agents (``self.agents``).

        Actions go through :func:`hivex_dsl.sim.spaces.stack_agent_actions`, which ends on the vector env's
        :func:`~hivex_dsl.sim.spaces.check_actions`: anything that is not an action of the space (NaN, out
        of range, a fraction for a discrete space, a boolean, a string, None, a wrong shape, a torch
        tensor that requires grad, a missing or extra agent) raises
        :class:`~hivex_dsl.base.errors.ActionError` naming the agent and the space. A tensor without grad
        on the CPU is read as NumPy reads it. An action for an agent that ended earlier in this world's
        episode is accepted and ignored, as its placeholder plays anyway: TorchRL's PettingZooWrapper (and
        BenchMARL on it) sends an action for every agent of a group, dead or alive. A name that is no agent
        of the environment is refused.
        """
        if not self.agents:
            if self.core.state is None:
                raise ResetNeeded("call reset() before step(): the environment has not been reset yet")
            raise ResetNeeded("every agent is done: call reset() before step()")
        live = self.agents
        if isinstance(actions, dict) and len(actions) > len(live):
            actions = {a: action for a, action in actions.items() if a in live or a not in self._index}
        space = self.core.sim.action_space
        # checked before the placeholders fill the slots of agents that left: filling casts to the space's dtype
        batched = stack_agent_actions(space, actions, live, self.core.sim.action_meanings)
        result = self.core.step(self._fill_inactive(batched, live))
        everyone = len(live) == len(self.possible_agents)
        rows = None if everyone else [self._index[a] for a in live]

        def of_live(values: list) -> list:  # per-agent values (all agents) -> those of the live agents
            return values if rows is None else [values[i] for i in rows]

        # whole rows at once (tolist, zip) instead of NumPy scalars per agent: this runs every step
        obs = dict(zip(live, of_live(_per_agent(result.observations))))
        rewards = dict(zip(live, of_live(result.rewards[0].tolist())))
        terminations = dict(zip(live, of_live(result.terminated[0].tolist())))
        truncations = dict(zip(live, of_live(result.truncated[0].tolist())))
        term_rows = of_live(_per_agent_values(result.terms, len(self.possible_agents)))
        if result.env_info:
            fact_rows = of_live(_per_agent_values(result.env_info, len(self.possible_agents)))
            infos = {a: {"reward_terms": terms, "env": facts} for a, terms, facts in zip(live, term_rows, fact_rows)}
        else:
            infos = {a: {"reward_terms": terms} for a, terms in zip(live, term_rows)}
        ended = result.ended[0]
        if np.count_nonzero(ended):
            for a in live:
                if ended[self._index[a]]:
                    infos[a]["hivex_episode"] = self.core.episode_summary(0, self._index[a])
            if self.respawn and not self.core.world_endings(result)[0]:
                self._respawn(result.ended, obs, infos)
            else:
                self.agents = [a for a in live if not ended[self._index[a]]]
        self._report_masks(infos)
        self._show()
        return obs, rewards, terminations, truncations, infos

    def _report_masks(self, infos: dict[str, dict[str, Any]]) -> None:
        """``infos[agent]["action_mask"]``, the agent's row of the environment's mask in the form its action space
        samples with, for every agent that acts next, where the environment masks actions (see the class)."""
        if self.core.masks_actions:
            rows, space = self.core.action_mask()[0], self.core.sim.action_space
            for agent in self.agents:
                infos[agent]["action_mask"] = sampling_mask(space, rows[self._index[agent]])

    def _respawn(self, ended: np.ndarray, obs: dict, infos: dict) -> None:
        """Respawn the agents where ``ended`` (1, agents); their observations become first ones."""
        self.core.respawn_agents(ended)
        fresh = self.core.observe()
        for i in np.flatnonzero(ended[0]):
            agent = self.possible_agents[i]
            infos[agent]["terminal_observation"] = obs[agent]
            obs[agent] = _unbatch(fresh, 0, i)

    def _fill_inactive(self, batched: Any, live: list[str]) -> Any:
        """Actions for every agent slot; finished agents get a valid placeholder the runtime masks out."""
        if len(live) == len(self.possible_agents):
            return batched
        rows = [self._index[a] for a in live]
        placeholder = self.core.placeholder
        if isinstance(batched, dict):
            return {k: self._fill_part(v, rows, placeholder[k]) for k, v in batched.items()}
        return self._fill_part(batched, rows, placeholder)

    def _fill_part(self, part: np.ndarray, rows: list[int], sample: np.ndarray) -> np.ndarray:
        full = np.empty((1, len(self.possible_agents)) + sample.shape, sample.dtype)
        full[...] = sample  # not np.broadcast_to(...).copy(): its Python-level setup costs more than the copy
        full[0, rows] = part[0]
        return full

    def close(self) -> None:
        """Closes the window of human rendering, if any; a world is only NumPy arrays."""
        self._close_window()
