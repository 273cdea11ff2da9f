"""The expression language of reward terms, events and shaping potentials.

A task author writes a formula over an environment's vocabulary of named quantities::

    expression = compile_expression("clip(1 - distance_to_fire_m / 500, 0, 1)", vocabulary)
    reward = expression.evaluate(now, before)      # (batch, agents) float64

:func:`compile_expression` parses the source into a tree of a few whitelisted node types
(:mod:`.syntax`; nothing ever reaches ``eval``, ``exec`` or Python's compiler), checks every node's
kind (number or boolean), shape (per agent or per world), unit and range (:mod:`.checker`,
:mod:`.units`, :mod:`.intervals`) and fuses it into nested closures of NumPy calls (:mod:`.plan`).
Compilation is total: an expression that compiles never raises and never yields NaN or inf for
inputs inside their quantities' ranges, and every value lies in ``[low, high]``. Mistakes raise
:class:`ExpressionError` with the 0-based offset and length of the offending token.
:func:`describe_grammar` gives the operators and functions as data for the docs.
"""

from __future__ import annotations

import functools
import keyword
import math
import re
from dataclasses import dataclass, field
from typing import Callable, Literal, Mapping

import numpy as np

from ...base.errors import is_integer
from . import intervals, plan, units
from .checker import Checker
from .errors import ExpressionError
from .grammar import describe_grammar
from .syntax import calls_of, parse

__all__ = ["Expression", "ExpressionError", "Kind", "Per", "Quantity", "compile_expression", "describe_grammar",
           "input_problems", "timed_calls"]

Per = Literal["agent", "world"]
Kind = Literal["number", "bool"]
_IDENTIFIER = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")
_MEAN_AGENTS = 1024  # the agent count team_mean's rounding allowance assumes when none is given
_CACHED_EXPRESSIONS = 4096  # compiled expressions (and their syntax trees) remembered; a few MB at most


@dataclass(frozen=True)
class Quantity:
    """A named quantity an expression may read.

    per: "agent" for a (batch, agents) array, "world" for a (batch,) array. kind: "number"
    (float64 arrays) or "bool" (bool arrays). unit: e.g. "m", "deg", "m/s", "1" for dimensionless
    ("" for booleans; see :mod:`.units` for the grammar). low/high: the closed range of every value
    the simulator can produce (0..1 for booleans); the compiler's guarantees rest on it.
    """

    name: str
    per: Per
    kind: Kind
    unit: str
    low: float
    high: float
    description: str

    def __post_init__(self) -> None:
        if not _IDENTIFIER.fullmatch(self.name) or keyword.iskeyword(self.name) or "__" in self.name:
            raise ValueError(f"quantity name {self.name!r} must be an identifier, not a keyword, without '__'")
        if self.per not in ("agent", "world") or self.kind not in ("number", "bool"):
            raise ValueError(f"quantity {self.name!r}: per must be 'agent' or 'world' and kind 'number' or 'bool'")
        try:
            object.__setattr__(self, "low", float(self.low))
            object.__setattr__(self, "high", float(self.high))
        except (TypeError, ValueError):
            raise ValueError(f"quantity {self.name!r}: low and high must be numbers") from None
        if not (-intervals.LIMIT <= self.low <= self.high <= intervals.LIMIT):
            raise ValueError(f"quantity {self.name!r}: range [{self.low}, {self.high}] is not a finite interval")
        units.parse_unit(self.unit)


@dataclass(frozen=True)
class Expression:
    """A compiled expression: what it is, what it reads, and how to evaluate it.

    ``evaluate(now, before)`` takes the quantities after and before the step by name and returns
    a (batch, agents) array for a per-agent expression or (batch,) for a per-world one, float64
    for kind "number" and bool for kind "bool". It never aliases an input array. Only the names
    in ``reads`` are looked up in ``now`` and those in ``reads_prev`` in ``before`` (which may be
    None when ``reads_prev`` is empty); number quantities must be float64 arrays.
    """

    source: str
    kind: Kind
    per: Per
    unit: str
    low: float
    high: float
    reads: frozenset[str]
    reads_prev: frozenset[str]
    _run: Callable = field(repr=False, compare=False)
    _recipe: tuple = field(repr=False, compare=False)  # compile_expression's other arguments, to pickle

    def __post_init__(self) -> None:
        object.__setattr__(self, "evaluate", self._run)  # the fused closure itself: no extra call per evaluation

    def __reduce__(self):
        # closures do not pickle; the source and the vocabulary do, and compile to the same plan
        vocabulary, want, per, agents = self._recipe
        return _recompile, (self.source, vocabulary, want, per, agents)

    def evaluate(self, now: Mapping[str, np.ndarray], before: Mapping[str, np.ndarray]) -> np.ndarray:
        return self._run(now, before)


def compile_expression(source: str, vocabulary: Mapping[str, Quantity], *, want: Kind = "number",
                       per: Per | None = None, agents: int | None = None) -> Expression:
    """Parse, check and compile ``source`` over ``vocabulary``.

    want: the kind the caller needs (a reward is a "number", an ending a "bool"). per: the shape
    the caller needs, "agent" or "world"; None accepts both (a per-world value is then the
    caller's to broadcast over its agents).
    agents: the largest number of agents per world, which bounds team_sum's range (team_sum is
    refused without it; evaluating with more agents voids the range). Raises ExpressionError at
    the offending token, ValueError for a malformed vocabulary or agents.
    """
    if want not in ("number", "bool") or per not in (None, "agent", "world"):
        raise ValueError(f"want must be 'number' or 'bool' and per None, 'agent' or 'world', got {want!r}, {per!r}")
    if agents is not None and (not is_integer(agents) or agents < 1):
        raise ValueError(f"agents must be a positive integer, got {agents!r}")
    if not isinstance(source, str):
        raise ExpressionError(f"an expression is text, got {type(source).__name__}", 0, 0)
    for name, quantity in vocabulary.items():
        if name != quantity.name:
            raise ValueError(f"vocabulary key {name!r} holds quantity {quantity.name!r}")
    return _compiled(source, tuple(vocabulary.values()), want, per, agents)


@functools.lru_cache(maxsize=_CACHED_EXPRESSIONS)
def _compiled(source: str, quantities: tuple[Quantity, ...], want: Kind, per: Per | None,
              agents: int | None) -> Expression:
    """:func:`compile_expression` of checked arguments, remembered: a sweep compiles the same expressions over
    the same vocabulary at every point (an Expression is immutable and its plan keeps no state, so points
    share it). Errors are not remembered: they propagate from each call."""
    vocabulary = {q.name: q for q in quantities}
    checker = Checker(vocabulary, agents, agents or _MEAN_AGENTS)
    typed = checker.check(_parsed(source))
    whole = (0, len(source))
    if typed.kind != want:
        wanted, found = ("a number", "a boolean") if want == "number" else ("a boolean (e.g. a comparison)", "a number")
        raise ExpressionError(f"expected {wanted}, got {found}", *whole)
    if typed.per is None:
        raise ExpressionError("the expression reads no quantity: it is a constant", *whole)
    if per == "world" and typed.per == "agent":
        raise ExpressionError("expected a per-world value, got a per-agent one; reduce it with "
                              "team_mean, team_min, team_max or team_sum", *whole)
    if per == "agent" and typed.per == "world":
        raise ExpressionError("expected a per-agent value, got a per-world one", *whole)
    unit = "" if typed.kind == "bool" else units.format_unit(typed.unit or units.DIMENSIONLESS)
    low, high = typed.interval
    assert math.isfinite(low) and math.isfinite(high)
    return Expression(source, typed.kind, typed.per, unit, low, high, frozenset(checker.reads),
                      frozenset(checker.reads_prev), plan.result(typed.op), (dict(vocabulary), want, per, agents))


@functools.lru_cache(maxsize=_CACHED_EXPRESSIONS)
def _parsed(source: str):
    """The syntax tree of ``source`` (frozen nodes), remembered: a sweep whose points change the vocabulary's
    ranges checks the same text again, and parsing is half the cost of compiling."""
    return parse(source)


def timed_calls(source: str) -> tuple[int, ...]:
    """0-based offsets of the ``prev(`` and ``delta(`` calls in ``source`` (an expression that parses), in the
    order they are written: where an expression that may not look back in time does."""
    return tuple(sorted(call.function.offset for call in calls_of(_parsed(source), ("prev", "delta"))))


def _recompile(source, vocabulary, want, per, agents) -> Expression:
    return compile_expression(source, vocabulary, want=want, per=per, agents=agents)


def input_problems(vocabulary: Mapping[str, Quantity], values: Mapping[str, np.ndarray]) -> list[str]:
    """What is wrong with ``values`` as inputs of expressions over ``vocabulary`` (empty when nothing).

    The guarantees of :func:`compile_expression` hold for inputs that match their quantities:
    float64 (bool for booleans), (batch, agents) or (batch,) with one batch size and agent count
    throughout, and every number inside [low, high]. A vocabulary's tests run this on the values
    its readers produce.
    """
    problems, batch, agents = [], None, None
    for name, array in values.items():
        quantity = vocabulary.get(name)
        if quantity is None:
            problems.append(f"{name}: not in the vocabulary")
            continue
        dtype = np.dtype(bool) if quantity.kind == "bool" else np.dtype(np.float64)
        rank = 2 if quantity.per == "agent" else 1
        if not isinstance(array, np.ndarray) or array.dtype != dtype or array.ndim != rank:
            got = f"{array.dtype} with {array.ndim} axes" if isinstance(array, np.ndarray) else type(array).__name__
            problems.append(f"{name}: expected {dtype} with {rank} axes, got {got}")
            continue
        batch = array.shape[0] if batch is None else batch
        if array.shape[0] != batch or (rank == 2 and agents is not None and array.shape[1] != agents):
            problems.append(f"{name}: shape {array.shape} disagrees with the other quantities")
        agents = array.shape[1] if rank == 2 and agents is None else agents
        inside = quantity.low <= array.min() and array.max() <= quantity.high if array.size else True
        if quantity.kind == "number" and not inside:
            problems.append(f"{name}: values in [{array.min():g}, {array.max():g}] outside its range "
                            f"[{quantity.low:g}, {quantity.high:g}]")
    return problems
