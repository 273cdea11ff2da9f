"""Per-episode statistics named as the paper's published results log them.

The original environments log, besides the return, statistics such as Aerial Wildfire Suppression's
"Water Pickup" or Drone-Based Reforestation's "Tree Drop Count"; the published test results
(:mod:`hivex_dsl.evaluation.published`) give most as the per-agent sum over a test episode, some as the mean
of values added during it (a running mean, below). Each environment declares here, in its ``statistics.py``, how
it computes every name it logs:

- a **counter**: ``fn(prev, state, actions, params) -> (batch, agents)`` numbers or bools (an event
  counts 1) read from the simulator's state each step (like a reward term), summed per agent over the episode,
  whatever the task pays (the original logs a drop's reward where its task weighs drops 0);
- a **mirror**: the weighted sum of some reward terms' episode sums (no per-step cost);
- a **running mean**: what ML-Agents' ``StatsRecorder.Add(name, value)`` logs with its default aggregation
  (``StatAggregationMethod.Average``) when the original adds an agent's *running total* of some weighted
  reward terms each time that total changes. Per agent-episode: the running total ``R_t`` of the terms' weighted
  per-step pay ``p_t``; on every step with ``p_t != 0`` (the total changed; a step whose terms cancel to exactly
  0 does not count) ``R_t`` is added to a sum and 1 to a count; the episode's value is ``sum / count`` (0 when
  the total never changed). A vessel collecting n pebbles one a step logs (1 + ... + n) / n = (n + 1) / 2.
  TensorBoard's point is the **pooled** form over the agent-episodes of a summary period, sum of sums / sum of
  counts (:func:`pooled`), which is what a published value compares with (``hivex_dsl.evaluation``); the mean of
  the per-episode values weighs a short episode as much as a long one;
- an **at-end** value: ``fn(prev, state, actions, params) -> (batch, agents)`` read each step like a counter but
  kept, not summed: the episode's value is what the agent's last step read (a snapshot the original adds once an
  episode, e.g. Wildfire Resource Management's "Individual Resource Count", a tower's resources as it ends);
- **not computed**: a logged name this toolkit cannot compute, with the reason.

Counters and mirrors are per-agent episode sums, running means and at-end values are not; all are (batch, agents)
arrays.

Names are the logged ones **without** the ``"<Environment>/"`` prefix (``"Water Pickup"``, not
``"AerialWildfireSuppression/Water Pickup"``): :meth:`StatisticSet.logged_name` adds it back, and
:meth:`hivex_dsl.evaluation.published.PublishedCell.statistic` accepts either form. The return
("Environment/Cumulative Reward") is the episode's ``return`` and is not a statistic here.
"""

from __future__ import annotations

import inspect
from dataclasses import dataclass
from typing import Any, Callable, Iterator, Mapping

import numpy as np

from .reward.terms import TERM_SIGNATURE

StatisticFn = Callable[[Any, Any, Any, Any], np.ndarray]


@dataclass(frozen=True)
class Statistic:
    """One logged statistic: a per-step ``counter`` (summed, or kept ``at_end``), a ``mirror`` or a ``running_mean``
    of weighted reward terms."""

    name: str
    description: str
    counter: StatisticFn | None = None
    mirror: tuple[str, ...] = ()  # the reward terms whose weighted episode sums this statistic adds up
    running_mean: tuple[str, ...] = ()  # the reward terms whose weighted running total this statistic averages
    at_end: bool = False  # the counter's value at the agent's last step, not its sum over the episode

    @property
    def kind(self) -> str:
        if self.counter is not None:
            return "at_end" if self.at_end else "counter"
        return "running_mean" if self.running_mean else "mirror"

    @property
    def terms(self) -> tuple[str, ...]:
        """The reward terms the statistic reads (none for a counter)."""
        return self.mirror or self.running_mean


class StatisticSet:
    """The statistics one environment logs, in the order the docs list them."""

    def __init__(self, environment: str, prefix: str, notes: tuple[str, ...] = ()):
        self.environment = environment
        self.prefix = prefix  # the logged names' "<prefix>/" (e.g. "AerialWildfireSuppression")
        self.notes = notes  # how a name was read where the original's meaning is not written down, and why
        self._stats: dict[str, Statistic] = {}
        self.not_computed: dict[str, str] = {}  # logged name -> why this toolkit cannot compute it

    def counter(self, name: str, description: str) -> Callable[[StatisticFn], StatisticFn]:
        """Decorator: ``fn(prev, state, actions, params) -> (batch, agents)`` summed over the episode."""
        return self._per_step(name, description, at_end=False)

    def at_end(self, name: str, description: str) -> Callable[[StatisticFn], StatisticFn]:
        """Decorator: ``fn(prev, state, actions, params) -> (batch, agents)`` as it reads on the agent's last step."""
        return self._per_step(name, description, at_end=True)

    def _per_step(self, name: str, description: str, at_end: bool) -> Callable[[StatisticFn], StatisticFn]:
        def register(fn: StatisticFn) -> StatisticFn:
            params = tuple(inspect.signature(fn).parameters)
            if params != TERM_SIGNATURE:
                raise TypeError(f"{self.environment}: statistic {name!r} must take {TERM_SIGNATURE}, takes {params}")
            self._add(Statistic(name, description, counter=fn, at_end=at_end))
            return fn

        return register

    def mirror(self, name: str, description: str, *terms: str) -> None:
        """A statistic that is the weighted episode sum of ``terms`` (0 for a term the task does not pay)."""
        if not terms:
            raise ValueError(f"{self.environment}: statistic {name!r} mirrors no term")
        self._add(Statistic(name, description, mirror=tuple(terms)))

    def running_mean(self, name: str, description: str, *terms: str) -> None:
        """A statistic that averages the running total of ``terms``' weighted pay over the steps it changed on
        (see the module doc; a term the task does not pay adds nothing)."""
        if not terms:
            raise ValueError(f"{self.environment}: statistic {name!r} averages no term")
        self._add(Statistic(name, description, running_mean=tuple(terms)))

    def cannot_compute(self, name: str, why: str) -> None:
        """A logged statistic this toolkit does not compute, and why."""
        self._check_new(name)
        self.not_computed[name] = why

    def _check_new(self, name: str) -> None:
        if name in self._stats or name in self.not_computed or "/" in name:
            raise ValueError(f"{self.environment}: statistic {name!r} declared twice or prefixed")

    def _add(self, statistic: Statistic) -> None:
        self._check_new(statistic.name)
        self._stats[statistic.name] = statistic

    def problems(self, term_names: tuple[str, ...]) -> list[str]:
        """Names of reward terms that the statistics refer to but the environment lacks."""
        wanted = [t for s in self for t in s.terms]
        return [f"{self.environment}: a statistic refers to unknown reward term {t!r}" for t in wanted
                if t not in term_names]

    def logged_name(self, name: str) -> str:
        return f"{self.prefix}/{name}"

    def __iter__(self) -> Iterator[Statistic]:
        return iter(self._stats.values())

    def __len__(self) -> int:
        return len(self._stats)

    def __getitem__(self, name: str) -> Statistic:
        return self._stats[name]

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(self._stats)

    @property
    def counters(self) -> tuple[Statistic, ...]:
        return tuple(s for s in self if s.counter is not None)

    @property
    def running_means(self) -> tuple[Statistic, ...]:
        return tuple(s for s in self if s.running_mean)


class RunningMeans:
    """The accumulators of an environment's running-mean statistics over B worlds x N agents.

    Per statistic, each (batch, agents): ``totals`` (the running total of this agent-episode), ``sums`` (the
    totals added on the steps it changed) and ``counts`` (those steps). ``active`` names the terms a task pays
    (the others pay 0 and add nothing).
    """

    def __init__(self, statistics: StatisticSet, active: tuple[str, ...], shape: tuple[int, ...]):
        self.terms = {s.name: tuple(t for t in s.running_mean if t in active) for s in statistics.running_means}
        self.totals = {name: np.zeros(shape) for name in self.terms}
        self.sums = {name: np.zeros(shape) for name in self.terms}
        self.counts = {name: np.zeros(shape, np.int64) for name in self.terms}
        self._paying = tuple((name, terms) for name, terms in self.terms.items() if terms)

    def add(self, weights: Mapping[str, float], values: Mapping[str, np.ndarray]) -> None:
        """One step: ``values`` are the active terms' unweighted (batch, agents) values (0 for an agent out of its
        episode), ``weights`` the terms' weights now."""
        for name, terms in self._paying:
            pay = weights[terms[0]] * values[terms[0]]
            for term in terms[1:]:
                pay = pay + weights[term] * values[term]
            total = self.totals[name]
            total += pay
            changed = pay != 0
            self.sums[name] += np.where(changed, total, 0.0)
            self.counts[name] += changed

    def clear(self, mask: np.ndarray) -> None:
        """Start new agent-episodes where ``mask`` (batch, agents) is true."""
        for name in self.terms:
            self.totals[name][mask] = 0.0
            self.sums[name][mask] = 0.0
            self.counts[name][mask] = 0

    def parts(self, pick: Callable[[np.ndarray], Any]) -> dict[str, dict[str, Any]]:
        """Each statistic's ``{"sums", "counts"}`` through ``pick`` (a (batch, agents) array -> what a summary
        holds: one agent's value, the ended slots'), the parts an episode summary carries for pooling."""
        return {name: {"sums": pick(self.sums[name]), "counts": pick(self.counts[name])} for name in self.terms}

    def values(self) -> dict[str, np.ndarray]:
        """Each statistic's (batch, agents) per agent-episode value: sums / counts, 0 where nothing changed."""
        return {name: episode_mean(self.sums[name], self.counts[name]) for name in self.terms}


def episode_mean(sums: np.ndarray, counts: np.ndarray) -> np.ndarray:
    """A running mean's per agent-episode values from its sums and counts (same shape): 0 where a count is 0."""
    return np.divide(sums, counts, out=np.zeros(np.shape(sums)), where=np.asarray(counts) > 0)


def pooled(sums: np.ndarray, counts: np.ndarray) -> float:
    """A running mean over many agent-episodes as TensorBoard shows it (every added value weighs the same): the
    sum of ``sums`` over the sum of ``counts`` (any equal shapes), 0 where nothing was added."""
    count = int(np.sum(counts))
    return float(np.sum(sums)) / count if count else 0.0


def episode_statistics(statistics: StatisticSet, weights: Mapping[str, float],
                       counter_sums: Mapping[str, np.ndarray], term_sums: Mapping[str, np.ndarray],
                       shape: tuple[int, ...], running: Mapping[str, np.ndarray] | None = None
                       ) -> dict[str, np.ndarray]:
    """Every statistic's per agent-episode value, each shaped like the sums (``shape``).

    ``counter_sums``: the counters' unweighted sums (an at-end counter's last value); ``term_sums``: the active
    terms' unweighted sums; ``running``: the running means' values (:meth:`RunningMeans.values`).
    """
    out: dict[str, np.ndarray] = {}
    for stat in statistics:
        if stat.counter is not None:
            out[stat.name] = counter_sums[stat.name]
            continue
        if stat.running_mean:
            out[stat.name] = running[stat.name] if running is not None else np.zeros(shape)
            continue
        total = np.zeros(shape)
        for term in stat.mirror:
            if term in term_sums:
                total = total + weights[term] * term_sums[term]
        out[stat.name] = total
    return out


__all__ = ["RunningMeans", "Statistic", "StatisticSet", "episode_mean", "episode_statistics", "pooled"]
