"""The one rollout helper: whole episodes of a policy, with returns, per-term sums, statistics and term traces.

`hivex run`, `hivex audit`, the fidelity page and the tests all roll episodes through :func:`rollout`.
Episodes run one after another in one world (the scenario's split seeds, like a user's environment);
``trace=True`` also records, per active term, the per-step facts the audit checks contracts against.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Optional

import numpy as np

from ..compiler import CompiledScenario
from ..runtime.batched import BatchedEnv, Split
from ..sim.spaces import check_actions
from ..sim.statistics import pooled
from .policies import Policy, decide, make_policy


@dataclass
class TermTrace:
    """Per-step facts of one term's unweighted values over a rollout's live agent-steps."""

    low: float = np.inf  # the smallest per-step value seen
    high: float = -np.inf  # the largest
    nonzero: int = 0  # live agent-steps with a value other than 0
    live: int = 0  # live agent-steps
    before_end: int = 0  # non-zero values on steps that did not end the agent's episode (terminal timing)
    first_step: list[np.ndarray] = field(default_factory=list)  # (agents,) values on each episode's first step

    def add(self, value: np.ndarray, live: np.ndarray, ended: np.ndarray, first: bool) -> None:
        """``value``, ``live`` and ``ended`` are one world's (agents,) arrays of one step."""
        seen = value[live]
        if seen.size:
            self.low, self.high = min(self.low, float(seen.min())), max(self.high, float(seen.max()))
        self.nonzero += int(np.count_nonzero(seen))
        self.live += int(seen.size)
        self.before_end += int(np.count_nonzero(value[live & ~ended]))
        if first:
            self.first_step.append(value.copy())


@dataclass
class Rollout:
    """``episodes`` whole episodes of one policy: every array is (episodes, agents); ``lengths`` in physics steps,
    ``decisions`` each agent's decisions in its episode (an agent ending inside a decision period ends on that
    decision), traces per decision (see :meth:`hivex_dsl.runtime.BatchedEnv.step`)."""

    compiled: CompiledScenario
    policy: str  # the policy's name ('scripted', 'random', 'zeros', or a callable's __name__)
    returns: np.ndarray
    lengths: np.ndarray
    decisions: np.ndarray
    terms: dict[str, np.ndarray]  # unweighted per-term episode sums of the active terms
    statistics: dict[str, np.ndarray]  # logged statistics' per agent-episode values (see hivex_dsl.sim.statistics)
    traces: dict[str, TermTrace] = field(default_factory=dict)  # per active term, when traced
    running: dict[str, tuple[np.ndarray, np.ndarray]] = field(default_factory=dict)  # running mean -> (sums, counts)

    def weighted(self, term: str) -> np.ndarray:
        """What ``term`` paid per agent and episode: its weight times its episode sums (0 where the task logs the
        term but does not pay it: ``CompiledScenario.unpaid``)."""
        return (0.0 if term in self.compiled.unpaid else self.compiled.weights[term]) * self.terms[term]

    def pooled(self) -> dict[str, float]:
        """Each running-mean statistic over every agent-episode as the original's TensorBoard point shows it:
        sum of sums over sum of counts (:func:`hivex_dsl.sim.statistics.pooled`); what a published value compares
        with, where the mean of ``statistics`` would weigh a short episode as much as a long one."""
        return {name: pooled(sums, counts) for name, (sums, counts) in self.running.items()}


def rollout(compiled: CompiledScenario, policy: str | Policy, episodes: int, split: Split = "test",
            seed: Optional[int] = None, progress=None, trace: bool = False) -> Rollout:
    """Roll ``episodes`` whole episodes of ``policy`` in one world: 'scripted', 'random', 'zeros', or any
    batched policy, observations (1, agents, ...) -> actions (1, agents, ...) (a trained network's, say).
    Every policy given the same split and ``seed`` plays the same episodes, so their returns compare.

    ``seed`` (optional) restarts the split's seed stream and seeds the random policy (0 otherwise);
    ``progress`` (a :class:`hivex_dsl.evaluation.progress.EpisodeBar`) is told of steps and episodes. The policy
    acts once per decision (every ``decision_period`` physics steps); its steps are decisions. A policy with a true
    ``takes_action_mask`` attribute (a trained network's) is also given the environment's action mask
    (:func:`~hivex_dsl.evaluation.policies.decide`).
    """
    core = BatchedEnv(compiled, batch=1, split=split)
    space = core.sim.action_space
    if callable(policy):
        act, policy = policy, getattr(policy, "__name__", "custom")
    else:
        act = make_policy(policy, compiled, space, core.shape, seed=0 if seed is None else seed)
    shape = (episodes, core.agents)
    returns, lengths, decisions = np.zeros(shape), np.zeros(shape, np.int64), np.zeros(shape, np.int64)
    terms = {name: np.zeros(shape) for name in core.composer.active}
    statistics = {name: np.zeros(shape) for name in core.statistics.names}
    running = {name: (np.zeros(shape), np.zeros(shape, np.int64)) for name in core.running.terms}
    traces = {name: TermTrace() for name in core.composer.active} if trace else {}
    for episode in range(episodes):
        observations = core.reset(seed if episode == 0 else None)
        step = 0
        while core.alive.any():
            live = core.alive[0].copy()
            actions = check_actions(space, decide(act, observations, core), compiled.agent_names,
                                    core.sim.action_meanings)
            result = core.step(actions)
            observations = result.observations
            for name, tracer in traces.items():
                tracer.add(result.terms[name][0], live, result.ended[0], step == 0)
            step += 1
            if progress:
                progress.step(episode, step, compiled.episode_decisions)
        returns[episode], lengths[episode], decisions[episode] = core.returns[0], core.lengths[0], core.decisions[0]
        for name in terms:
            terms[name][episode] = core.term_sums[name][0]
        for name, sums in core.statistic_sums().items():
            statistics[name][episode] = sums[0]
        for name, (sums, counts) in running.items():
            sums[episode], counts[episode] = core.running.sums[name][0], core.running.counts[name][0]
        if progress:
            progress.episode_done(episode, float(returns[episode].mean()), step)
    return Rollout(compiled, policy, returns, lengths, decisions, terms, statistics, traces, running)


__all__ = ["Rollout", "TermTrace", "rollout"]
