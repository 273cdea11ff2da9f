"""B copies of one compiled scenario stepping in lockstep: the engine behind both adapters.

The simulator moves the world; this module adds what every environment shares: the reward
composer, episode clocks and truncation, task endings declared as events in the reward table,
per-agent episode sums of every active term and the environment's logged statistics, the seed schedule of
the train/test split, and the decision period (ML-Agents' DecisionRequester: one ``step`` is one decision of
``decision_period`` physics steps, see :meth:`BatchedEnv.step`).
"""

from __future__ import annotations

from typing import Any, Literal, NamedTuple, Optional

import numpy as np
from gymnasium import spaces

from ..base.errors import ResetNeeded
from ..base.numeric import all_true, constant
from ..compiler import CompiledScenario
from ..sim.reward.composer import RewardComposer
from ..sim.spaces import hold_inactive, placeholder_actions
from ..sim.stacking import stack_per_decision
from ..sim.statistics import RunningMeans, StatisticSet, episode_statistics
from .contract import Simulator, StepOutcome, missing_members
from .seeding import SeedSchedule

Split = Literal["train", "test"]
_ZERO = constant(0.0)  # rewards and terms are float64 (see hivex_dsl.base.numeric)


class Transition(NamedTuple):
    """One batched decision (``decision_period`` physics steps). Arrays are (batch, agents); ``ended`` marks
    agents whose episode ended in it. Rewards and term values are the decision's sums over its physics steps,
    the endings what happened in any of them; ``env_info`` is the simulator's facts after the last one.

    A named tuple for the same reason as :class:`StepOutcome`.
    """

    observations: Any
    rewards: np.ndarray
    terminated: np.ndarray
    truncated: np.ndarray
    terms: dict[str, np.ndarray]
    ended: np.ndarray
    env_info: dict[str, np.ndarray]
    world_terminated: np.ndarray  # (batch,) bool: a world-level ending happened in the world on this step


class BatchedEnv:
    """``batch`` worlds of one scenario. Agents of a world may end early; a world ends when all have.

    Endings have a scope. An agent's own ending (the simulator's ``terminated``, a task's ``ends_on``
    event that is not a world event, a per-agent ending expression) ends that agent's episode. A
    world-level ending (a task's ``ends_on`` event that the registry lists in ``world_events``, e.g. the
    fire went out, or a per-world ending expression) ends the episode of every agent of the world at
    once, and is reported in ``Transition.world_terminated``. Consumers that respawn agents (the vector
    env, ``parallel_env(respawn=True)``) restart a world only at :meth:`world_endings`: never because
    its agents' own endings happen to coincide.

    Clocks: ``clock`` (batch,) and ``lengths`` (batch, agents) count physics steps (``episode_length`` is in
    physics steps, as ML-Agents' MaxStep), ``decisions`` (batch, agents) counts each agent's decisions in its
    episode (the same array as ``lengths`` when ``decision_period`` is 1). ``env_steps``, the expression feed
    (``prev()`` is the value one physics step before) and the statistics counters tick per physics step.
    """

    def __init__(self, compiled: CompiledScenario, batch: int = 1, split: Split = "train",
                 distinct_copies: bool = False):
        if batch < 1:
            raise ValueError(f"batch must be >= 1, got {batch}")
        if split not in ("train", "test"):
            raise ValueError(f"split must be 'train' or 'test', got {split!r}")
        self.compiled = compiled
        self.batch = batch
        self.agents = compiled.agents
        self.sim: Simulator = compiled.entry.make_simulator(compiled)
        missing = missing_members(self.sim)
        if missing:
            raise TypeError(f"{compiled.environment}: its simulator {type(self.sim).__name__} lacks {', '.join(missing)} "
                            "(see hivex_dsl.runtime.contract.Simulator)")
        expressions = compiled.expressions
        self.feed = expressions.feed(self.shape, compiled) if expressions is not None else None
        terms = expressions.registry(compiled.entry.terms, self.feed) if expressions is not None else compiled.entry.terms
        self.composer = RewardComposer(terms, compiled.weights, compiled.schedules, compiled.unpaid)
        self.env_steps = 0  # the clock of weight schedules: steps taken by every world together (settable to resume)
        self.schedule = SeedSchedule(getattr(compiled.seeds, split), distinct_copies)
        self.state: Any = None
        self.rng: Optional[np.random.Generator] = None
        shape = (batch, self.agents)
        self.clock = np.zeros(batch, np.int64)
        self.alive = np.zeros(shape, bool)
        self.ended_last = np.zeros(shape, bool)  # agents whose episode ended on the last decision (see step)
        self.returns = np.zeros(shape)
        self.term_sums = {name: np.zeros(shape) for name in self.composer.active}
        self.statistics: StatisticSet = compiled.entry.statistics or StatisticSet(compiled.environment, "")
        self._counters = tuple((s.name, s.counter, s.at_end) for s in self.statistics.counters)
        self.counter_sums = {name: np.zeros(shape) for name, _, _ in self._counters}  # at-end ones: the last value
        self.running = RunningMeans(self.statistics, self.composer.active, shape)  # the running-mean statistics
        self._running = bool(self.running.terms)
        self.lengths = np.zeros(shape, np.int64)
        self.period = compiled.decision_period
        self.decisions = self.lengths if self.period == 1 else np.zeros(shape, np.int64)
        self._stacks = int(getattr(self.sim, "observation_stacks", 1))
        # at a period of 1 the simulator's own shift of its stacks every physics step is a shift every decision
        self._stacked = tuple(getattr(self.sim, "stacked_fields", ())) if self.period > 1 and self._stacks > 1 else ()
        self.everyone_playing = False  # == bool(self.alive.all()), kept so a step needs no reduction for it
        self.oldest_clock = 0  # == int(self.clock.max()): a step knows without a reduction whether a world truncates
        self._step_info = getattr(self.sim, "step_info", None)
        self._action_mask = getattr(self.sim, "action_mask", None)  # see contract.MasksActions
        world_events = compiled.entry.world_events
        held = getattr(self.sim, "held_events", ())  # the simulator holds these agents (see contract.HoldsEndings)
        self._agent_ends_on = tuple(e for e in compiled.ends_on if e not in world_events and e not in held)
        self._world_ends_on = tuple(e for e in compiled.ends_on if e in world_events)
        self._no_world_ending = np.zeros(batch, bool)
        self._no_world_ending.flags.writeable = False  # shared by every step that has no world ending
        self.placeholder = placeholder_actions(self.sim.action_space)  # what an agent out of its episode does

    @property
    def shape(self) -> tuple[int, int]:
        return (self.batch, self.agents)

    def reset(self, seed: Optional[int] = None) -> Any:
        """Start a new episode in every world; returns batched observations.

        A seed starting a stream (the first reset, an explicit ``seed``, each seed of a list) builds
        the worlds from scratch; a reset that continues an integer stream starts the new episodes
        with ``reset_where`` like the worlds of the vector env do, so what a simulator keeps between
        episodes of a stream (e.g. an island) is the same whichever adapter runs it.
        """
        continues = seed is None and self.state is not None and not isinstance(self.schedule.seeds, tuple)
        self.rng = self.schedule.next_rng(seed)
        if continues:
            self.state = self.sim.reset_where(self.state, np.ones(self.batch, bool), self.rng)
        else:
            self.state = self.sim.reset(self.rng, self.batch)
        self._clear(np.ones(self.batch, bool))
        if self.feed is not None:
            self.feed.start(self.state)
        return self.sim.observe(self.state)

    def reset_worlds(self, mask: np.ndarray) -> Any:
        """Reset the worlds where ``mask`` (batch,) is true, continuing the random stream."""
        self._require_reset()
        self.state = self.sim.reset_where(self.state, mask, self.rng)
        self._clear(mask)
        if self.feed is not None:
            self.feed.start(self.state, mask)
        return self.sim.observe(self.state)

    def respawn_agents(self, mask: np.ndarray) -> None:
        """Start new episodes for the agents where ``mask`` (batch, agents) is true, in their running worlds.

        Their worlds' clocks go on; the simulator's ``respawn_where`` puts them back (continuing the
        random stream) and their per-agent sums start from zero. A simulator without one (its agents
        never end on their own unless a scenario says so, e.g. a turbine) starts them again where they are.
        Does not observe.
        """
        self._require_reset()
        if not np.count_nonzero(mask):
            return
        respawn = getattr(self.sim, "respawn_where", None)
        if respawn is not None:
            self.state = respawn(self.state, mask, self.rng)
        self._clear_agents(mask)
        if self.feed is not None:
            self.feed.respawn(self.state, mask)

    def world_endings(self, result: "Transition") -> np.ndarray:
        """(batch,) bool: worlds whose episode ends with this step as a whole -- the clock reached the
        episode length, or a world-level ending happened (``result.world_terminated``). Agents whose own
        endings coincide (every drone's battery empty on one step) do not end their world."""
        return (self.clock >= self.compiled.episode_length) | result.world_terminated

    def observe(self) -> Any:
        self._require_reset()
        return self.sim.observe(self.state)

    @property
    def masks_actions(self) -> bool:
        """Whether the simulator says which discrete choices are open at a decision (:meth:`action_mask`)."""
        return self._action_mask is not None

    def action_mask(self) -> Optional[np.ndarray]:
        """(batch, agents, N) int8, 1 where a choice of the discrete branches is open at the next decision (N the
        branches' sizes summed, branch after branch; Gymnasium's and PettingZoo's mask dtype), or None where the
        simulator masks nothing (see :class:`~hivex_dsl.runtime.contract.MasksActions`)."""
        self._require_reset()
        if self._action_mask is None:
            return None
        return self._action_mask(self.state).astype(np.int8)

    def _clear(self, mask: np.ndarray) -> None:
        self.clock[mask] = 0
        self._clear_agents(np.broadcast_to(mask[:, None], self.shape))
        self.oldest_clock = int(self.clock.max())

    def _clear_agents(self, mask: np.ndarray) -> None:
        """Zero the per-agent episode records where ``mask`` (batch, agents) is true; they play again."""
        self.alive[mask] = True
        self.returns[mask] = 0.0
        self.lengths[mask] = 0
        if self.decisions is not self.lengths:
            self.decisions[mask] = 0
        for sums in self.term_sums.values():
            sums[mask] = 0.0
        for sums in self.counter_sums.values():
            sums[mask] = 0.0
        if self._running:
            self.running.clear(mask)
        self.everyone_playing = bool(self.alive.all())

    def _require_reset(self) -> None:
        if self.state is None:
            raise ResetNeeded("call reset() before step(): the environment has not been reset yet")

    def step(self, actions: Any, restart: Optional[np.ndarray] = None, respawn: Optional[np.ndarray] = None,
             ) -> Transition:
        """Advance every world one decision with already validated (batch, agents, ...) actions.

        A decision is ``decision_period`` physics steps with the same actions held (ML-Agents' DecisionRequester
        with TakeActionsBetweenDecisions): rewards and term values are summed over them, an agent ending at
        one of them plays a placeholder and earns nothing for the rest, and the endings are those of any of
        them. Observations are taken once, after the last (observing costs as much as a step with a camera); their
        older stacks are the previous decision's newest, as ML-Agents' stacking sensors shift once a decision
        (:mod:`hivex_dsl.sim.stacking`).

        ``restart`` (batch,) bool, if given, starts new episodes in those worlds right after the
        decision (continuing the random stream), so the returned observations are their first ones;
        observing once after the restart spares a second observation of every world, which for
        camera environments costs as much as the step. Their transition values (rewards, ended,
        ...) are the decision's, for the caller to discard. ``respawn`` (batch, agents) bool, if given,
        respawns those agents (:meth:`respawn_agents`) after the decision, before any restart.
        """
        self._require_reset()
        start = self.state
        if self.period > 1:
            self.decisions += self.alive  # an agent ending inside the period ends on this decision
        summed = self._physics_step(actions)
        if self.period > 1:  # a term may hand out an array of the state, which the next physics step may change
            summed = (summed[0], {name: np.array(value) for name, value in summed[1].items()}) + summed[2:]
        for _ in range(1, self.period):
            summed = _summed(summed, self._physics_step(actions))
        rewards, terms, terminated, truncated, ended, world_terminated = summed
        if self._stacked:
            self.state = stack_per_decision(start, self.state, self._stacked, self._stacks)
        self.ended_last = ended  # their last observation is this decision's (the global state shows it)
        env_info = self._step_info(self.state) if self._step_info is not None else {}
        if respawn is not None:
            self.respawn_agents(respawn)
        if restart is not None and np.count_nonzero(restart):
            self.state = self.sim.reset_where(self.state, restart, self.rng)
            self._clear(restart)
            if self.feed is not None:
                self.feed.start(self.state, restart)
        return Transition(self.sim.observe(self.state), rewards, terminated, truncated, terms, ended, env_info,
                          world_terminated)

    def _physics_step(self, actions: Any) -> tuple:
        """One physics step of every world: -> (rewards, terms, terminated, truncated, ended, world_terminated),
        (batch, agents) arrays, ``terms`` a dict of them, and world_terminated (batch,). Agents out of their
        episode play the placeholder and earn nothing."""
        live, everyone = self.alive, self.everyone_playing
        if not everyone:  # an agent whose episode ended does nothing until its world resets
            actions = hold_inactive(actions, live, self.placeholder)
        prev = self.state
        self.state, outcome = self.sim.step(prev, actions, self.rng)
        if self.feed is not None:
            self.feed.advance(self.state, outcome.events)
        if self.compiled.schedules:
            self.composer.set_clock(self.env_steps)
        rewards, terms = self.composer(prev, self.state, actions, self.compiled.params, self.shape)
        if not everyone:  # ended agents earn nothing (skipped while everyone plays: most steps)
            rewards = np.where(live, rewards, _ZERO)
            terms = {name: np.where(live, value, _ZERO) for name, value in terms.items()}
        self.clock += 1
        self.oldest_clock += 1
        self.env_steps += self.batch
        self.lengths += live
        self.returns += rewards
        for name, value in terms.items():
            self.term_sums[name] += value
        self._count(prev, actions, live, everyone)
        if self._running:  # ended agents' terms are 0 here: their totals do not change
            self.running.add(self.composer.weights, terms)
        return (rewards, terms) + self._endings(live, outcome)

    def _count(self, prev: Any, actions: Any, live: np.ndarray, everyone: bool) -> None:
        """Add this step's value of every counter statistic to its episode sums, or keep it for an at-end one
        (ended agents add or change nothing)."""
        params = self.compiled.params
        for name, counter, at_end in self._counters:
            value = counter(prev, self.state, actions, params)
            if at_end:
                np.copyto(self.counter_sums[name], value, where=True if everyone else live)
            else:
                self.counter_sums[name] += value if everyone else np.where(live, value, _ZERO)

    def statistic_sums(self) -> dict[str, np.ndarray]:
        """Every statistic's (batch, agents) value over the current (or just ended) episodes, by logged name
        without the environment prefix: a sum, or for a running mean its per agent-episode mean, whose sums and
        counts (for the pooled form) are ``self.running`` (see :mod:`hivex_dsl.sim.statistics`)."""
        return episode_statistics(self.statistics, self.compiled.weights, self.counter_sums, self.term_sums,
                                  self.shape, self.running.values() if self._running else None)

    def _world_terminated(self, outcome: StepOutcome) -> np.ndarray:
        """(batch,) bool: a world-level ending of the task happened in the world on this step."""
        world = self._no_world_ending if outcome.world_ended is None else outcome.world_ended
        for event in self._world_ends_on:  # a world event holds for every agent of its world
            world = world | outcome.events[event].any(axis=1)
        if self.feed is not None and self.compiled.expressions.endings:
            hit = self.compiled.expressions.world_ended(self.feed)
            if hit is not None:
                world = world | hit
        return world

    def _endings(self, live: np.ndarray, outcome: StepOutcome
                 ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """(terminated, truncated, ended) of the step just taken, each (batch, agents), and the (batch,)
        world-level endings; updates who is alive. A world-level ending terminates every live agent of
        its world.

        Most steps nobody ends: while no world reaches the episode length truncation is known to be all
        false, and while moreover every agent plays and none terminates the alive mask stays as it is.
        """
        ending = outcome.terminated
        for event in self._agent_ends_on:
            ending = ending | outcome.events[event]
        if self.feed is not None and self.compiled.expressions.endings:
            hit = self.compiled.expressions.ended(self.feed, self.shape)
            if hit is not None:
                ending = ending | hit
        world = self._world_terminated(outcome)
        if world is not self._no_world_ending and np.count_nonzero(world):
            ending = ending | world[:, None]
        terminated = live & ending
        if self.oldest_clock < self.compiled.episode_length:  # no world truncates
            truncated = np.zeros(terminated.shape, bool)
            if self.everyone_playing and not np.count_nonzero(terminated):
                return terminated, truncated, terminated.copy(), world
            ended = terminated.copy()
        else:
            # the clock's end truncates every agent still playing, one that also terminated on this step too:
            # terminated decides its bootstrap, and "all truncated" (RLlib's, TorchRL's, SuperSuit's test of a
            # world's end) holds, which a crash on the last step would otherwise hide from them
            truncated = live & (self.clock >= self.compiled.episode_length)[:, None]
            ended = terminated | truncated
        self.alive = live & ~ended
        self.everyone_playing = all_true(self.alive)
        return terminated, truncated, ended, world

    def episode_summary(self, world: int, agent: int) -> dict[str, Any]:
        """Return, length (physics steps), decisions, per-term sums and statistics of one agent's current (or
        just ended) episode; with running-mean statistics, ``running`` holds each one's ``sums`` and ``counts``
        (its pooled form over many episodes is their sums' ratio)."""
        return {
            "return": float(self.returns[world, agent]),
            "length": int(self.lengths[world, agent]),
            "decisions": int(self.decisions[world, agent]),
            "reward_terms": {name: float(s[world, agent]) for name, s in self.term_sums.items()},
            "statistics": {name: float(s[world, agent]) for name, s in self.statistic_sums().items()},
        } | ({"running": self.running.parts(lambda a: a[world, agent].item())} if self._running else {})

    def render(self, world: int = 0) -> np.ndarray:
        self._require_reset()
        return self.sim.render(self.state, world)


def _summed(first: tuple, then: tuple) -> tuple:
    """Two consecutive physics steps of a decision as one (see :meth:`BatchedEnv._physics_step`): rewards and
    term values added (in step order, so a decision's sum is the left-to-right sum of its steps'), endings OR-ed."""
    rewards, terms, terminated, truncated, ended, world = first
    return (rewards + then[0], {name: value + then[1][name] for name, value in terms.items()},
            terminated | then[2], truncated | then[3], ended | then[4], world | then[5])
