"""The named quantities an expression may read, per environment, and the per-step feed of their values.

Each environment declares its vocabulary as a :class:`Vocabulary`: in its registry entry's ``vocabulary``
(:mod:`hivex_dsl.compiler.registry` passes it to :func:`register_vocabulary`), or, for a package under
hivex_dsl/envs/, as ``VOCABULARY`` of its ``vocabulary.py`` module, found by name. It holds the quantities (with ranges that follow from the compiled scenario's params) and one reader per
quantity that takes it from the simulator's state or the step's events. A running env keeps a
:class:`QuantityFeed`: the values after the last step (``now``) and before it (``before``), reading
only the quantities its expressions use, each once per step.
"""

from __future__ import annotations

import importlib
from dataclasses import dataclass, field
from functools import lru_cache
from typing import Any, Callable, Iterable, Mapping

import numpy as np

from ...lang.expr import Quantity

# reader(state, events, compiled scenario) -> (batch, agents) for per-agent quantities, (batch,) for per-world ones
Reader = Callable[[Any, Mapping[str, np.ndarray], Any], np.ndarray]


@dataclass(frozen=True)
class Vocabulary:
    """``declare(compiled) -> {name: Quantity}`` (ranges follow the params) and ``readers[name]``.

    ``not_modelled``: quantities a researcher may reach for that the simulator does not have, name ->
    why (the docs list them; an expression that reads one, or the name with a unit suffix such as
    ``wind_speed_m_s``, is told why instead of "unknown quantity").
    """

    environment: str
    declare: Callable[[Any], dict[str, Quantity]]
    readers: Mapping[str, Reader]
    events: tuple[str, ...] = ()  # event names the readers take from the step's events
    not_modelled: Mapping[str, str] = field(default_factory=dict)

    def quantities(self, compiled: Any) -> dict[str, Quantity]:
        declared = self.declare(compiled)
        if set(declared) != set(self.readers):
            raise ValueError(f"{self.environment}: declared quantities and readers differ: "
                             f"{sorted(set(declared) ^ set(self.readers))}")
        return declared

    def absence(self, name: str) -> str | None:
        """Why ``name`` (or ``name`` less a unit suffix: ``wind_speed_m_s`` for ``wind_speed``) is not a
        quantity, when it is one the simulator does not model; else None."""
        for missing, why in self.not_modelled.items():
            if name == missing or name.startswith(missing + "_"):
                return f"{missing} is not modelled in {self.environment}: {why}"
        return None

    def values(self, state: Any, events: Mapping[str, np.ndarray], compiled: Any,
               names: Iterable[str]) -> dict[str, np.ndarray]:
        """{name: array} of ``names`` after a step that had ``events``."""
        return {name: self.readers[name](state, events, compiled) for name in names}


_DECLARED: dict[str, Vocabulary] = {}  # the vocabularies registry entries carry, by environment


def register_vocabulary(vocabulary: Vocabulary) -> None:
    """Make ``vocabulary`` its environment's (the registry does this for an entry that carries one)."""
    _DECLARED[vocabulary.environment] = vocabulary


def vocabulary_of(env_id: str) -> Vocabulary:
    """The vocabulary of an environment: the one its entry registered, else ``VOCABULARY`` of
    ``hivex_dsl.envs.<env_id>.vocabulary`` (ModuleNotFoundError without either)."""
    return _DECLARED.get(env_id) or _load(env_id)


@lru_cache(maxsize=None)
def _load(env_id: str) -> Vocabulary:
    module = importlib.import_module(f"hivex_dsl.envs.{env_id}.vocabulary")
    return module.VOCABULARY


class QuantityFeed:
    """The values of the quantities some expressions read, after the last step and before it.

    ``start`` after a reset (all worlds or those of ``mask``): no events happened, and ``before``
    of the next step is the reset state's value. ``advance`` after a step.
    """

    def __init__(self, vocabulary: Vocabulary, names: Iterable[str], shape: tuple[int, int], compiled: Any):
        self.vocabulary = vocabulary
        self.compiled = compiled
        self.names = tuple(sorted(set(names)))
        self._readers = tuple((name, vocabulary.readers[name]) for name in self.names)
        self.quiet = {event: np.zeros(shape, bool) for event in vocabulary.events}
        self.now: dict[str, np.ndarray] = {}
        self.before: dict[str, np.ndarray] = {}

    def start(self, state: Any, mask: np.ndarray | None = None) -> None:
        fresh = self.vocabulary.values(state, self.quiet, self.compiled, self.names)
        if mask is None or not self.now:
            self.now = fresh
            return
        self.now = {name: np.where(mask if value.ndim == 1 else mask[:, None], fresh[name], value)
                    for name, value in self.now.items()}

    def respawn(self, state: Any, mask: np.ndarray) -> None:
        """After agents of ``mask`` (batch, agents) started afresh in running worlds: their per-agent values
        are read again (no events happened to them); per-world values stay the step's."""
        if not self.now:
            return
        fresh = self.vocabulary.values(state, self.quiet, self.compiled, self.names)
        self.now = {name: np.where(mask, fresh[name], value) if value.ndim == 2 else value
                    for name, value in self.now.items()}

    def advance(self, state: Any, events: Mapping[str, np.ndarray]) -> None:
        self.before = self.now
        compiled = self.compiled
        self.now = {name: read(state, events, compiled) for name, read in self._readers}  # runs every step


def quantity(name: str, per: str, kind: str, unit: str, low: float, high: float, description: str) -> Quantity:
    """A :class:`Quantity` with its range as plain floats."""
    return Quantity(name, per, kind, unit, float(low), float(high), description)


def flag(name: str, per: str, description: str) -> Quantity:
    """A boolean quantity (an event or a state flag)."""
    return Quantity(name, per, "bool", "", 0.0, 1.0, description)
