"""The weighted sum of reward terms, with the unweighted per-term values kept for logging."""

from __future__ import annotations

from typing import Any, Mapping

import numpy as np

from ..errors import did_you_mean
from ..numeric import constant
from .terms import TermRegistry


_ZERO = constant(0.0)


class RewardComposer:
    """reward = sum over terms of weight * term(prev, state, actions, params).

    Every weight's name is checked against the registry first; terms with weight 0 are then
    skipped (never evaluated) and contribute exactly zero.
    """

    def __init__(self, registry: TermRegistry, weights: Mapping[str, float],
                 schedules: Mapping[str, Any] | None = None):
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
        self.steps = 0
        self._build_plan()

    def _build_plan(self) -> None:
        # (name, function, weight as a 0-d operand or None for 1.0), resolved once: this runs every step
        self._plan = tuple((name, self.registry[name].fn, _operand(self.weights.get(name, 0.0)))
                           for name in self.active)

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
        return (np.zeros(shape) if total is None else total), values


def _operand(weight: float):
    """A weight as a 0-d float64 operand, or None for 1.0 (the term's value is used as it is)."""
    return None if weight == 1.0 else constant(weight)
