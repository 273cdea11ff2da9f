"""The weighted sum of reward terms, with the unweighted per-term values kept for logging."""

from __future__ import annotations

import math
from typing import Any, Mapping

import numpy as np

from ...base.errors import did_you_mean
from ...base.numeric import constant
from .terms import TermRegistry


_ZERO = constant(0.0)


class RewardComposer:
    """reward = sum over paid terms of weight * term(prev, state, actions, params).

    Every weight's name is checked against the registry first; terms with weight 0 are then
    skipped (never evaluated) and contribute exactly zero. An ``unpaid`` term (a task's reward table
    column logs it but does not pay it) is evaluated and its value returned for the statistics, but
    adds nothing to the reward.
    """

    def __init__(self, registry: TermRegistry, weights: Mapping[str, float],
                 schedules: Mapping[str, Any] | None = None, unpaid: frozenset[str] = frozenset()):
        schedules = schedules or {}
        for name in list(weights) + list(schedules):
            if name not in registry:
                raise KeyError(
                    f"{registry.environment} has no reward term {name!r}{did_you_mean(name, registry.names)}"
                )
        self.registry = registry
        self.weights = {name: float(w) for name, w in weights.items()}
        self.schedules = dict(schedules)  # name -> schedule with .at(steps) and .start/.end (spec.WeightSchedule)
        self.active = tuple(name for name in registry.names if self.weights.get(name, 0.0) != 0.0
                            or (name in self.schedules and (self.schedules[name].start or self.schedules[name].end)))
        self.unpaid = frozenset(unpaid) & frozenset(self.active)
        self.steps = 0
        self._build_plan()

    def _build_plan(self) -> None:
        # (name, function, weight as a 0-d operand or None for 1.0), resolved once: this runs every step
        self._plan = tuple((name, self.registry[name].fn, _operand(self.weights.get(name, 0.0)))
                           for name in self.active if name not in self.unpaid)
        self._logged = tuple((name, self.registry[name].fn) for name in self.active if name in self.unpaid)

    def paid(self, name: str) -> float:
        """What ``name`` pays per unit of its value now: its weight, or 0 where the task does not pay it."""
        return 0.0 if name in self.unpaid else self.weights.get(name, 0.0)

    def set_clock(self, steps: int) -> None:
        """Move scheduled weights to their value after ``steps`` environment steps (a no-op without schedules)."""
        if not self.schedules or steps == self.steps:
            return
        self.steps = steps
        self.weights.update({name: schedule.at(steps) for name, schedule in self.schedules.items()})
        self._build_plan()

    def __call__(
        self, prev: Any, state: Any, actions: Any, params: Any, shape: tuple[int, int]
    ) -> tuple[np.ndarray, dict[str, np.ndarray]]:
        """Returns the (batch, agents) reward and each active term's unweighted (batch, agents) value."""
        total = None
        values: dict[str, np.ndarray] = {}
        for name, term, weight in self._plan:
            value = np.asarray(term(prev, state, actions, params), dtype=np.float64)
            if value.shape != shape:  # broadcast_to costs more than many terms do
                value = np.broadcast_to(value, shape)
            values[name] = value
            weighted = value if weight is None else weight * value  # 1.0 * x == x: one NumPy call fewer
            if total is None:
                total = _ZERO + weighted  # a new array, with 0.0 + x's signed zeros like summing from zeros
            else:
                total += weighted
        for name, term in self._logged:  # values for the statistics only
            values[name] = np.broadcast_to(np.asarray(term(prev, state, actions, params), dtype=np.float64), shape)
        return (np.zeros(shape) if total is None else total), values


def _operand(weight: float):
    """A weight as a 0-d float64 operand, or None for 1.0 (the term's value is used as it is)."""
    return None if weight == 1.0 else constant(weight)


# The largest |episode return| of one agent a scenario may be able to reach. Training holds returns in float32
# (max 3.4e38) and squares their errors in the value loss, so a return must stay far below sqrt(3.4e38) = 1.8e19;
# the bundled scenarios reach at most 5e11.
RETURN_LIMIT = 1e15


def term_reaches(contract: Any, weights: Mapping[str, float], schedules: Mapping[str, Any]) -> float:
    """The largest |weight x value| a term can add to one agent's reward in a step: its contract's range times
    its weight, or the larger end of its weight's schedule (a schedule moves linearly between its ends)."""
    name = contract.name
    weight = abs(weights.get(name, 0.0))
    if name in schedules:
        weight = max(weight, abs(schedules[name].start), abs(schedules[name].end))
    return weight * max(abs(contract.low), abs(contract.high)) if weight else 0.0


def return_bound_problem(contracts: Any, weights: Mapping[str, float], schedules: Mapping[str, Any],
                         episode_length: int) -> tuple[str, str] | None:
    """(the term to blame, why) when the terms' contracts and weights allow an agent's episode return beyond
    :data:`RETURN_LIMIT` (a bound proven from the ranges, so a reward that passes is finite in float32); the
    term blamed is the one that can add the most. None when the bound holds."""
    reaches = {contract.name: term_reaches(contract, weights, schedules) for contract in contracts}
    step = sum(reaches.values())
    if step * episode_length <= RETURN_LIMIT:
        return None
    worst = max(reaches, key=reaches.get)
    episode = step * episode_length
    return worst, (f"the reward can reach {step:.3g} a step and "
                   f"{'more than 1.8e+308' if math.isinf(episode) else f'{episode:.3g}'} over an episode of "
                   f"{episode_length} steps, past the {RETURN_LIMIT:g} an agent's return may reach (training holds "
                   f"returns in float32 and squares them); {worst!r} alone adds up to {reaches[worst]:.3g} a step: "
                   "lower its weight or clip its value")
