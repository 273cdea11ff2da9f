"""Reward terms: plain vectorised functions registered with a contract.

A term is ``fn(prev, state, actions, params) -> (batch, agents) float64``: ``prev`` and
``state`` are the simulator states before and after the step, ``actions`` the batched actions
that led from one to the other, ``params`` the environment's validated params model. A term is
pure: it reads these and nothing else. Its contract (range, sign, timing, scope) is checked
when it is registered and property-tested for every term in tests/.
"""

from __future__ import annotations

import inspect
import math
import re
from dataclasses import dataclass
from typing import Any, Callable, Iterator, Literal

import numpy as np

Sign = Literal["bonus", "penalty", "mixed"]
Timing = Literal["dense", "event", "terminal"]
Scope = Literal["agent", "team", "global"]

TERM_SIGNATURE = ("prev", "state", "actions", "params")
_NAME = re.compile(r"^[a-z][a-z0-9_]*$")


@dataclass(frozen=True)
class TermContract:
    """What a reward term promises, in the words of the docs and the lock file.

    low/high: the closed range every per-step value lies in.
    sign: bonus (never negative), penalty (never positive) or mixed.
    timing: dense (every step), event (when something happens), terminal (at episode end).
    scope: agent (own behaviour), team (shared by a group) or global (same for all agents).
    """

    name: str
    title: str
    description: str
    low: float
    high: float
    sign: Sign
    timing: Timing
    scope: Scope
    paper_row: int | None = None
    equation: str = ""

    def __post_init__(self) -> None:
        if not _NAME.match(self.name):
            raise ValueError(f"term name {self.name!r} must be snake_case")
        if not (math.isfinite(self.low) and math.isfinite(self.high) and self.low <= self.high):
            raise ValueError(f"term {self.name!r}: range [{self.low}, {self.high}] is not a finite interval")
        if self.sign == "bonus" and self.low < 0:
            raise ValueError(f"term {self.name!r} is a bonus but its range starts below 0")
        if self.sign == "penalty" and self.high > 0:
            raise ValueError(f"term {self.name!r} is a penalty but its range ends above 0")

    def as_dict(self) -> dict[str, Any]:
        return {
            "name": self.name,
            "title": self.title,
            "description": self.description,
            "range": [self.low, self.high],
            "sign": self.sign,
            "timing": self.timing,
            "scope": self.scope,
            "paper_row": self.paper_row,
            "equation": self.equation,
        }


TermFn = Callable[[Any, Any, Any, Any], np.ndarray]


@dataclass(frozen=True)
class RewardTerm:
    contract: TermContract
    fn: TermFn

    @property
    def name(self) -> str:
        return self.contract.name

    def __call__(self, prev: Any, state: Any, actions: Any, params: Any) -> np.ndarray:
        return self.fn(prev, state, actions, params)


class TermRegistry:
    """The reward terms of one environment, in registration (paper row) order."""

    def __init__(self, environment: str):
        self.environment = environment
        self._terms: dict[str, RewardTerm] = {}

    def term(self, name: str, **contract: Any) -> Callable[[TermFn], TermFn]:
        """Decorator registering ``fn`` under ``name`` with the given contract fields."""

        def register(fn: TermFn) -> TermFn:
            self.add(RewardTerm(TermContract(name=name, **contract), fn))
            return fn

        return register

    def add(self, term: RewardTerm) -> None:
        if term.name in self._terms:
            raise ValueError(f"{self.environment}: reward term {term.name!r} registered twice")
        params = tuple(inspect.signature(term.fn).parameters)
        if params != TERM_SIGNATURE:
            raise TypeError(
                f"{self.environment}: reward term {term.name!r} must take {TERM_SIGNATURE}, takes {params}"
            )
        self._terms[term.name] = term

    def __getitem__(self, name: str) -> RewardTerm:
        return self._terms[name]

    def __contains__(self, name: object) -> bool:
        return name in self._terms

    def __iter__(self) -> Iterator[RewardTerm]:
        return iter(self._terms.values())

    def __len__(self) -> int:
        return len(self._terms)

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(self._terms)
