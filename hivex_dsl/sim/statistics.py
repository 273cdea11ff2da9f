"""Per-episode statistics named as the paper's published results log them.

The original environments log, besides the return, statistics such as Aerial Wildfire Suppression's
"Water Pickup" or Drone-Based Reforestation's "Tree Drop Count"; the published test results
(:mod:`hivex_dsl.evaluation.published`) give each as the per-agent sum over a test episode. Each environment
declares here, in its ``statistics.py``, how it computes every name it logs:

- a **counter**: ``fn(prev, state, actions, params) -> (batch, agents)`` numbers or bools (an event
  counts 1) read from the simulator's state each step (like a reward term), summed per agent over the episode,
  whatever the task pays (the original logs a drop's reward where its task weighs drops 0);
- a **mirror**: the weighted sum of some reward terms' episode sums (no per-step cost);
- **not computed**: a logged name this toolkit cannot compute, with the reason.

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
    """One logged statistic: a per-step ``counter`` or a ``mirror`` of weighted reward terms."""

    name: str
    description: str
    counter: StatisticFn | None = None
    mirror: tuple[str, ...] = ()  # the reward terms whose weighted episode sums this statistic adds up

    @property
    def kind(self) -> str:
        return "counter" if self.counter is not None else "mirror"


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

        def register(fn: StatisticFn) -> StatisticFn:
            params = tuple(inspect.signature(fn).parameters)
            if params != TERM_SIGNATURE:
                raise TypeError(f"{self.environment}: statistic {name!r} must take {TERM_SIGNATURE}, takes {params}")
            self._add(Statistic(name, description, counter=fn))
            return fn

        return register

    def mirror(self, name: str, description: str, *terms: str) -> None:
        """A statistic that is the weighted episode sum of ``terms`` (0 for a term the task does not pay)."""
        if not terms:
            raise ValueError(f"{self.environment}: statistic {name!r} mirrors no term")
        self._add(Statistic(name, description, mirror=tuple(terms)))

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
        wanted = [t for s in self for t in s.mirror]
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


def episode_statistics(statistics: StatisticSet, weights: Mapping[str, float],
                       counter_sums: Mapping[str, np.ndarray], term_sums: Mapping[str, np.ndarray],
                       shape: tuple[int, ...]) -> dict[str, np.ndarray]:
    """Every statistic's per-agent episode sum, each shaped like the sums (``shape``).

    ``counter_sums``: the counters' unweighted sums; ``term_sums``: the active terms' unweighted sums.
    """
    out: dict[str, np.ndarray] = {}
    for stat in statistics:
        if stat.counter is not None:
            out[stat.name] = counter_sums[stat.name]
            continue
        total = np.zeros(shape)
        for term in stat.mirror:
            if term in term_sums:
                total = total + weights[term] * term_sums[term]
        out[stat.name] = total
    return out


__all__ = ["Statistic", "StatisticSet", "episode_statistics"]
