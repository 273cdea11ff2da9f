"""Gymnasium VectorEnv with parameter sharing: every (world, agent) pair is one slot.

``num_worlds`` copies of the scenario step together; the slots are the flattened
(world, agent) pairs, so ``num_envs == num_worlds * agents`` and one policy acts for all.

Episodes are per slot, with ML-Agents' semantics. Endings have a scope (see
:class:`hivex_dsl.runtime.BatchedEnv`):

- an agent's own ending (a crash, the border, an empty battery, a task's ``ends_on`` event of one
  agent, a per-agent ending expression) reports ``terminated`` for that slot and respawns the agent
  in the same world, which goes on (its clock, fire, forest, planted trees);
- a world restarts as a whole when its clock reaches the episode length (its slots report
  ``truncated``) or a world-level ending happens: a task's ``ends_on`` event that the environment
  declares a world event (AWS's and WRM's ``fire_out``) or a per-world ending expression (its slots
  report ``terminated``).

A world never restarts because its agents' own endings coincide: drones whose batteries run out on
the same step (or the only agent of a one-agent world) respawn in their world. Every slot is always
live, so stock consumers (``RecordEpisodeStatistics``, SB3, CleanRL) count per-agent returns and
lengths right. Both of Gymnasium's autoreset modes are offered (``autoreset_mode``):

- NEXT_STEP (default): a slot that ended returns its last observation; the next ``step`` ignores
  its action and returns its first observation with reward 0 and no ending.
- SAME_STEP: a slot that ended returns its first observation at once; the last one is in
  ``infos["final_obs"]`` (an object array, ``None`` elsewhere) under the mask ``infos["_final_obs"]``, and the
  ended step's per-step infos again in ``infos["final_info"]`` (mask ``infos["_final_info"]``), as Gymnasium's
  own vector envs give them (TorchRL's GymWrapper reads the ended step's values there).

Every step's infos hold one flat (num_envs,) array per value: ``infos["reward_terms/<term>"]`` the unweighted value
of every active reward term, and ``infos["env/<fact>"]`` an environment's own per-step facts (WRM's
``impossible_actions``). Flat, not nested: TorchRL's GymWrapper reads every step info into its specs and cannot
take a nested dict there.

A slot that restarts (NEXT_STEP) on the very step its world ends is reported truncated with an
empty episode (return 0, length 0), as ``RecordEpisodeStatistics`` counts it too. When every world
restarts at once, NEXT_STEP resets them without stepping the simulator, so a one-world vector env
follows the parallel env episode after episode as long as no agent's own episode ends (the parallel env
then lets the agent leave, the vector env respawns it).

``infos["hivex_episode"]`` (mask ``infos["_hivex_episode"]``) holds each ended slot's return,
length (physics steps), decisions (step() calls), per-term sums, statistics and, for a running-mean statistic,
``running[name]["sums"/"counts"]`` (pool them for the original's summary point), never colliding with the wrappers'
``episode`` key. What becomes of an agent whose episode ended while its world goes on (``ended_agents``):
``respawn`` (the default) starts it again at once in its running world, whose clock goes on, so every slot is
always live and there is no ``infos["active"]``; ``wait`` keeps it out of play until its world restarts (as the
parallel env and ``hivex evaluate`` do): its slot then reports reward 0, no ending and ``infos["active"]`` False
(every step's infos hold that (num_envs,) mask), and its next episode starts with its world's. A respawned agent's
next episode is cut at its world's end, a short tail where the original's agents had none (Drone-Based
Reforestation: its trainer config's ``ended_agents``). Observations are fresh writable arrays every
step. A reset without a seed follows the scenario's seed (the first copy of a scenario in a
process plays its stream, later copies child streams of it: copies are different worlds unless
seeded, and a seeded reset is deterministic).

Action masks: an environment whose simulator says which discrete choices can do anything (Drone-Based
Reforestation's and Aerial Wildfire Suppression's drop, :class:`hivex_dsl.runtime.contract.MasksActions`) puts
``infos["action_mask"]`` (num_envs, N) int8 in every reset's and step's infos: 1 where a choice of the discrete
branches is open at the decision the returned observations ask for, N the branches' sizes summed, branch after
branch (ML-Agents' layout; slot s's row split at the branch sizes is the tuple ``MultiDiscrete.sample(mask=...)``
takes). A closed choice is still accepted and does nothing.

Global state (centralised critics): ``env.unwrapped.state()`` is every world's (num_worlds, K) float32 state at the
last decision (``state(per_slot=True)``: (num_envs, K), each slot its world's row), ``single_state_space`` one
world's Box and ``state_space`` the worlds'; see :mod:`hivex_dsl.runtime.global_state`. On demand rather than in the
infos: nothing is computed for a consumer that does not ask, and a (num_worlds, K) array is no per-slot info. It matches
the observations just returned: NEXT_STEP (the default) shows an ended slot's last observation and its world's last
state, which a truncated episode bootstraps from; SAME_STEP shows the new first observation and the restarted world
(the last state of a world that restarted is not kept there).

Dict observations (OPC, DBR, AWS: ``vector`` + ``visual``) come as :class:`DictObservations`, a dict that refuses
to be read as one array: a wrapper made for Box observations (``gymnasium.wrappers.vector.NormalizeObservation``,
which builds on a Dict space without complaint) fails at the first ``reset`` with an error naming the flat view
(:func:`hivex_dsl.adapters.flat.flat_vector_env`) instead of NumPy's AxisError.
"""

from __future__ import annotations

from typing import Any, Literal, Optional, get_args

import numpy as np
from gymnasium import spaces
from gymnasium.vector import AutoresetMode, VectorEnv
from gymnasium.vector.utils import batch_space

from ..base.errors import ActionError, HivexError, is_integer
from ..compiler import CompiledScenario
from ..runtime.batched import BatchedEnv, Split, Transition
from ..runtime.global_state import GlobalState
from ..sim.action_arrays import Unreadable, as_array
from ..sim.spaces import check_slot_actions
from .human import Rendering, available_render_modes, check_render_mode
from .slot_spaces import SlotDict, slot_space, teach_torchrl

STEP_INFO_KEYS = ("reward_terms/", "env/")  # the prefixes of the per-step infos, one flat key per value
_MODES = {"next_step": AutoresetMode.NEXT_STEP, "same_step": AutoresetMode.SAME_STEP}


class DictObservationError(HivexError, TypeError):
    """Dict observations were read as one array (see :class:`DictObservations`)."""


class DictObservations(dict):
    """The vector env's Dict observations ({key: (num_envs, ...) array}): a plain dict, except that NumPy cannot
    read it as one array (``np.asarray``, ``np.mean``...): that raises a DictObservationError (a TypeError) naming
    the flat view, where NumPy made a 0-d object array that failed later (an AxisError in NormalizeObservation)."""

    __slots__ = ()

    def __array__(self, dtype: Any = None, copy: Any = None):
        raise DictObservationError(
            f"these observations are a dict of arrays ({', '.join(map(repr, self))}), not one array: a wrapper "
            "made for Box observations (gymnasium.wrappers.vector.NormalizeObservation, a TransformObservation "
            "calling NumPy...) cannot take them. Wrap the flat view first, "
            "hivex_dsl.adapters.flat.flat_vector_env(env): one float32 Box per slot, the vector then the visual "
            "flattened, e.g. NormalizeObservation(flat_vector_env(gymnasium.make_vec(env_id, num_envs=N)))")


def flatten_slots(tree: Any, slots: int) -> Any:
    """(worlds, agents, ...) arrays (or a dict of them) -> fresh writable (slots, ...) arrays, slot = world * agents
    + agent (the vector env's layout, which policies trained on it see)."""
    if isinstance(tree, dict):
        return {k: flatten_slots(v, slots) for k, v in tree.items()}
    return np.array(tree.reshape((slots,) + tree.shape[2:]))


def unflatten_slots(tree: Any, shape: tuple[int, int]) -> Any:
    """(slots, ...) actions (or a dict of them) -> (worlds, agents, ...) arrays; a clear ActionError when the
    slot count is wrong or the actions are ragged."""
    if isinstance(tree, dict):
        return {k: unflatten_slots(v, shape) for k, v in tree.items()}
    try:
        array = as_array(tree)
    except Unreadable as exc:
        raise ActionError(f"actions are {exc}; expected an array of {shape[0] * shape[1]} slots") from None
    if array.shape[:1] != (shape[0] * shape[1],):
        raise ActionError(f"actions have leading size {array.shape[:1]}; expected {shape[0] * shape[1]} slots "
                          f"({shape[0]} worlds x {shape[1]} agents)")
    return array.reshape(shape + array.shape[1:])


def slot_values(tree: Any, slot: int) -> Any:
    """One slot's values of a (nested dict of) per-slot arrays."""
    return {k: slot_values(v, slot) for k, v in tree.items()} if isinstance(tree, dict) else tree[slot]


def as_autoreset_mode(mode: Any) -> AutoresetMode:
    """An AutoresetMode from itself or its name ("next_step", "same_step"); DISABLED is not offered."""
    if isinstance(mode, AutoresetMode) and mode in _MODES.values():
        return mode
    if isinstance(mode, str) and mode.lower() in _MODES:
        return _MODES[mode.lower()]
    raise ValueError(f"autoreset_mode must be one of {list(_MODES)} (or AutoresetMode.NEXT_STEP / SAME_STEP), "
                     f"got {mode!r}")


EndedAgents = Literal["respawn", "wait"]
ENDED_AGENTS: tuple[str, ...] = get_args(EndedAgents)


class HivexVectorEnv(Rendering, VectorEnv):
    """Slots are (world, agent) pairs in world-major order: slot = world * agents + agent."""

    def __init__(self, compiled: CompiledScenario, num_worlds: int = 1, render_mode: Optional[str] = None,
                 split: Split = "train", autoreset_mode: Any = AutoresetMode.NEXT_STEP,
                 ended_agents: EndedAgents = "respawn"):
        check_render_mode(render_mode)
        if ended_agents not in ENDED_AGENTS:
            raise ValueError(f"ended_agents must be one of {list(ENDED_AGENTS)}, got {ended_agents!r}")
        mode = as_autoreset_mode(autoreset_mode)
        if not is_integer(num_worlds) or num_worlds < 1:
            raise ValueError(f"num_worlds (make_vec's num_envs: copies of the world) must be an integer >= 1, "
                             f"got {num_worlds!r}")
        seeds = getattr(compiled.seeds, split, None)
        if isinstance(seeds, tuple):
            raise ValueError(
                f"the scenario's {split} seeds are a per-episode list {list(seeds)[:5]}: the vector env's worlds start "
                "their episodes on their own and continue one random stream, so they cannot play the listed seeds in "
                "turn; use parallel_env for per-episode seeds, or give this split one integer seed")
        self.compiled = compiled
        self.core = BatchedEnv(compiled, batch=num_worlds, split=split, distinct_copies=True)
        self.num_worlds = num_worlds
        self.respawns = ended_agents == "respawn"
        self.agents_per_world = compiled.agents
        self.num_envs = num_worlds * compiled.agents
        self.single_observation_space = self.core.sim.observation_space
        self.single_action_space = self.core.sim.action_space
        self.observation_space = batch_space(self.single_observation_space, self.num_envs)
        self._action_space = slot_space(self.single_action_space, self.num_envs)
        self.render_mode = render_mode
        self.autoreset_mode = mode
        self.metadata = {"autoreset_mode": mode, "render_modes": available_render_modes(),
                         "render_fps": self.core.sim.render_fps}
        self._pending_worlds = np.zeros(num_worlds, bool)  # NEXT_STEP: worlds that restart on the next step
        self._pending_agents = np.zeros(self.core.shape, bool)  # NEXT_STEP: agents that respawn on the next step
        self.global_state = GlobalState.of(self.core)
        self.single_state_space = self.global_state.space
        self.state_space = batch_space(self.single_state_space, num_worlds)

    @property
    def action_space(self) -> spaces.Space:
        """The slots' actions (num_envs, ...); a hybrid environment's is a :class:`SlotDict`, which TorchRL, when it
        is loaded (it reads this space to build its specs), is taught to read with the env's batch size."""
        if isinstance(self._action_space, SlotDict):
            teach_torchrl()
        return self._action_space

    def state(self, per_slot: bool = False) -> np.ndarray:
        """(num_worlds, K) float32: every world's global state at the last decision (see the module and
        :mod:`hivex_dsl.runtime.global_state`); ``per_slot``: (num_envs, K), slot s holding its world's
        (s // agents)."""
        states = self.global_state(self.core)
        return np.repeat(states, self.agents_per_world, axis=0) if per_slot else states

    def _slots(self, observations: Any) -> Any:
        """(worlds, agents, ...) observations -> the (num_envs, ...) ones returned (a dict as DictObservations)."""
        slots = flatten_slots(observations, self.num_envs)
        return DictObservations(slots) if isinstance(slots, dict) else slots

    def reset(self, *, seed: Optional[int] = None, options: Optional[dict] = None):
        if seed is not None and not isinstance(seed, (int, np.integer)):
            raise ValueError("seed must be one integer: it seeds the stream shared by every world")
        observations = self.core.reset(None if seed is None else int(seed))
        self._pending_worlds[:] = False
        self._pending_agents[:] = False
        self._show()
        infos: dict[str, Any] = {}
        self._report_next(infos)
        return self._slots(observations), infos

    def step(self, actions: Any):
        """Step every world with (num_envs, ...) actions, slot = world * agents + agent (for a Dict space, a
        dict of such arrays).

        Actions are checked by :func:`hivex_dsl.sim.spaces.check_slot_actions`, on the parallel env's path:
        anything that is not an action of the space (NaN, out of range, a fraction for a discrete space,
        a boolean in an array or a list, a string, None, a wrong shape or slot count, a torch tensor that
        requires grad) raises :class:`~hivex_dsl.base.errors.ActionError` naming the space and the culprit
        slot's agent and world. A tensor without grad on the CPU is read as NumPy reads it.
        """
        batched = check_slot_actions(self.single_action_space, actions, self.core.shape, self.compiled.agent_names,
                                     self.core.sim.action_meanings)
        if self.autoreset_mode is AutoresetMode.SAME_STEP:
            out = self._step_same(batched)
        else:
            out = self._step_next(batched)
        self._show()
        return out

    def _step_next(self, batched: Any):
        core, restart = self.core, self._pending_worlds
        shape = core.shape
        if restart.all():  # every world restarts: no simulator step on discarded actions (issue 16)
            observations = core.reset_worlds(restart)
            self._pending_worlds = np.zeros(self.num_worlds, bool)
            self._pending_agents = np.zeros(shape, bool)
            zeros = np.zeros(self.num_envs, bool)
            infos = {f"reward_terms/{name}": np.zeros(self.num_envs) for name in core.term_sums}
            self._report_next(infos)
            return self._slots(observations), np.zeros(self.num_envs), zeros, zeros.copy(), infos
        respawning = self._pending_agents & ~restart[:, None]
        restarting = restart if restart.any() else None
        result = core.step(batched, restart=restarting, respawn=respawning if respawning.any() else None)
        ending = self._world_endings(result) & ~restart
        terminated, truncated, ended = result.terminated, result.truncated, result.ended
        empty = respawning & ending[:, None]  # respawned on the last step of their world: an empty episode
        if empty.any():
            truncated, ended = truncated | empty, ended | empty
            core.alive[empty] = False
            core.ended_last = core.ended_last | empty  # the global state shows them, as the observations do
        counted = ~restart[:, None]
        terminated, truncated, ended = terminated & counted, truncated & counted, ended & counted
        rewards = np.where(counted, result.rewards, 0.0)
        infos = self._infos(result, ended)
        self._pending_worlds = ending
        self._pending_agents = ended & ~ending[:, None] if self.respawns else self._pending_agents
        self._report_next(infos)
        return (self._slots(result.observations), rewards.reshape(-1), terminated.reshape(-1),
                truncated.reshape(-1), infos)

    def _step_same(self, batched: Any):
        core = self.core
        result = core.step(batched)
        ending = self._world_endings(result)
        infos = self._infos(result, result.ended)
        observations = result.observations
        if np.count_nonzero(result.ended):
            final = flatten_slots(observations, self.num_envs)
            done = result.ended.reshape(-1)
            infos["final_obs"] = np.full(self.num_envs, None, dtype=object)
            for slot in np.flatnonzero(done):
                infos["final_obs"][slot] = slot_values(final, slot)
            infos["_final_obs"] = done
            infos["final_info"] = {k: v for k, v in infos.items() if k.startswith(STEP_INFO_KEYS)}
            infos["_final_info"] = done
            if self.respawns:
                core.respawn_agents(result.ended & ~ending[:, None])
            observations = core.reset_worlds(ending) if ending.any() else core.observe()
        self._report_next(infos)
        return (self._slots(observations), result.rewards.reshape(-1), result.terminated.reshape(-1),
                result.truncated.reshape(-1), infos)

    def _world_endings(self, result: Transition) -> np.ndarray:
        """(num_worlds,) bool: the worlds that end with this step, and with ``ended_agents="wait"`` those whose
        agents have all ended too (no one is left to play; the parallel env ends its episode there as well)."""
        ending = self.core.world_endings(result)
        return ending if self.respawns else ending | ~self.core.alive.any(axis=1)

    def _report_next(self, infos: dict[str, Any]) -> None:
        """What the infos say of the next step: with ``ended_agents="wait"``, ``infos["active"]`` (num_envs,) bool,
        the slots whose agent plays it (an ended agent waits for its world's restart); where the environment masks
        actions, ``infos["action_mask"]`` (num_envs, N) int8 (see the module)."""
        if not self.respawns:
            infos["active"] = self.core.alive.reshape(-1).copy()
        if self.core.masks_actions:
            infos["action_mask"] = self.core.action_mask().reshape(self.num_envs, -1)

    def _infos(self, result: Transition, ended: np.ndarray) -> dict[str, Any]:
        core = self.core
        infos: dict[str, Any] = {f"reward_terms/{k}": v.reshape(-1) for k, v in result.terms.items()}  # STEP_INFO_KEYS
        infos |= {f"env/{k}": np.asarray(v).reshape(-1) for k, v in result.env_info.items()}
        if ended.any():
            infos["hivex_episode"] = {
                "return": np.where(ended, core.returns, 0.0).reshape(-1),
                "length": np.where(ended, core.lengths, 0).reshape(-1),  # physics steps
                "decisions": np.where(ended, core.decisions, 0).reshape(-1),  # step() calls, as RecordEpisodeStatistics
                "reward_terms": {k: np.where(ended, s, 0.0).reshape(-1) for k, s in core.term_sums.items()},
                "statistics": {k: np.where(ended, s, 0.0).reshape(-1) for k, s in core.statistic_sums().items()},
            }
            if core.running.terms:  # a running mean's sums and counts: its pooled form over many episodes
                infos["hivex_episode"]["running"] = core.running.parts(lambda a: np.where(ended, a, 0).reshape(-1))
            infos["_hivex_episode"] = ended.reshape(-1)
        return infos

    def close_extras(self, **kwargs: Any) -> None:
        """Closes the window of human rendering, if any; the worlds are only NumPy arrays."""
        self._close_window()
