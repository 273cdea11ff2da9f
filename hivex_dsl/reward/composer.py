"""The weighted sum of reward terms, with the unweighted per-term values kept for logging."""

from __future__ import annotations

from typing import Any, Mapping

import numpy as np

from ..errors import did_you_mean
from .terms import TermRegistry


class RewardComposer:
    """reward = sum over terms of weight * term(prev, state, actions, params).

    Every weight's name is checked against the registry first; terms with weight 0 are then
    skipped (never evaluated) and contribute exactly zero.
    """

    def __init__(self, registry: TermRegistry, weights: Mapping[str, float]):
        for name in weights:
            if name not in registry:
                raise KeyError(
                    f"{registry.environment} has no reward term {name!r}{did_you_mean(name, registry.names)}"
                )
        self.registry = registry
        self.weights = {name: float(w) for name, w in weights.items()}
        self.active = tuple(name for name in registry.names if self.weights.get(name, 0.0) != 0.0)
        self._terms = tuple(registry[name] for name in self.active)
        self._weights = tuple(self.weights[name] for name in self.active)

    def __call__(
        self, prev: Any, state: Any, actions: Any, params: Any, shape: tuple[int, int]
    ) -> tuple[np.ndarray, dict[str, np.ndarray]]:
        """Returns the (batch, agents) reward and each active term's unweighted (batch, agents) value."""
        total = np.zeros(shape, dtype=np.float64)
        values: dict[str, np.ndarray] = {}
        for term, weight in zip(self._terms, self._weights):
            value = np.asarray(term(prev, state, actions, params), dtype=np.float64)
            if value.shape != shape:  # broadcast_to costs more than many terms do
                value = np.broadcast_to(value, shape)
            values[term.name] = value
            total += value if weight == 1.0 else weight * value  # 1.0 * x == x: one NumPy call fewer
        return total, values
