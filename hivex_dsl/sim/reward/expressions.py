"""Reward terms, shaping and endings written as expressions, compiled once per scenario.

A compiled expression term is an ordinary :class:`RewardTerm`: its contract is declared or
inferred from the expression's interval (range, sign) and shape (scope), and its function reads
the env's :class:`QuantityFeed`, so the composer, the episode sums, ``reward_terms``, the lock and
the docs treat it like a registered term. Shaping is a term too: gamma * phi(s') - phi(s).
"""

from __future__ import annotations

import dataclasses
import functools
from dataclasses import dataclass
from typing import Any, Callable, Mapping, Optional, Sequence

import numpy as np

from ...base.errors import Location, Problem, ScenarioError
from ...lang.expr import Expression, ExpressionError, compile_expression, timed_calls
from ...lang.spec.expr_location import traced_location
from ...lang.spec.expression_keys import split_ends_on
from ...lang.spec.expressions import ExpressionTermSpec, ShapingSpec
from ...lang.spec.validate import dotted
from .terms import RewardTerm, TermContract, TermRegistry
from .vocabulary import QuantityFeed, Vocabulary, vocabulary_of

PathKey = tuple
Locate = Callable[..., Location]


@dataclass(frozen=True)
class ExpressionTerm:
    """A term's contract and its compiled expression (or, for shaping, its potential and gamma)."""

    contract: TermContract
    expression: Expression
    gamma: Optional[float] = None  # set for a shaping term

    @property
    def reads(self) -> frozenset[str]:
        return frozenset(self.expression.reads) | frozenset(self.expression.reads_prev)

    def bound(self, feed: QuantityFeed) -> RewardTerm:
        """The term reading ``feed``; a closure, not an object with __call__: it runs every step."""
        evaluate, per_world = self.expression.evaluate, self.expression.per == "world"
        if self.gamma is not None:  # shaping: phi reads no prev(), so each side needs one state
            gamma = np.float64(self.gamma)

            def shaping(prev, state, actions, params):
                now, before = feed.now, feed.before
                value = gamma * evaluate(now, now) - evaluate(before, before)
                return value[:, None] if per_world else value

            return RewardTerm(self.contract, shaping)
        if per_world:
            def world_value(prev, state, actions, params):
                return evaluate(feed.now, feed.before)[:, None]

            return RewardTerm(self.contract, world_value)

        def agent_value(prev, state, actions, params):
            return evaluate(feed.now, feed.before)

        return RewardTerm(self.contract, agent_value)


@dataclass(frozen=True)
class ScenarioExpressions:
    """Everything a scenario wrote as expressions: terms (shaping last) and endings."""

    vocabulary: Optional[Vocabulary] = None
    terms: tuple[ExpressionTerm, ...] = ()
    endings: tuple[Expression, ...] = ()

    @property
    def reads(self) -> frozenset[str]:
        names = set().union(*(t.reads for t in self.terms)) if self.terms else set()
        for ending in self.endings:
            names |= set(ending.reads) | set(ending.reads_prev)
        return frozenset(names)

    @property
    def contracts(self) -> tuple[TermContract, ...]:
        return tuple(t.contract for t in self.terms)

    def feed(self, shape: tuple[int, int], compiled: Any) -> Optional[QuantityFeed]:
        """The feed a running env keeps, or None when no expression reads anything."""
        if self.vocabulary is None or not (self.terms or self.endings):
            return None
        return QuantityFeed(self.vocabulary, self.reads, shape, compiled)

    def registry(self, base: TermRegistry, feed: Optional[QuantityFeed]) -> TermRegistry:
        """``base``'s terms followed by this scenario's, bound to ``feed``."""
        if not self.terms:
            return base
        combined = TermRegistry(base.environment)
        for term in base:
            combined.add(term)
        for term in self.terms:
            combined.add(term.bound(feed))
        return combined

    def ended(self, feed: QuantityFeed, shape: tuple[int, int]) -> Optional[np.ndarray]:
        """(batch, agents) bool: some per-agent ending expression holds after the step; None without any."""
        hit = None
        for ending in self.endings:
            if ending.per == "agent":
                value = ending.evaluate(feed.now, feed.before)
                hit = value if hit is None else hit | value
        return None if hit is None else np.broadcast_to(hit, shape)

    def world_ended(self, feed: QuantityFeed) -> Optional[np.ndarray]:
        """(batch,) bool: some per-world ending expression (an ending of the whole world) holds; None without any."""
        hit = None
        for ending in self.endings:
            if ending.per == "world":
                value = ending.evaluate(feed.now, feed.before)
                hit = value if hit is None else hit | value
        return hit


def compile_expressions(compiled: Any, vocabulary: Optional[Vocabulary],
                        terms: Sequence[tuple[str, ExpressionTermSpec, Locate]], shaping: Optional[ShapingSpec],
                        endings: Sequence[tuple[PathKey, str, Locate]], locate: Locate,
                        registered: tuple[str, ...]) -> ScenarioExpressions:
    """Compile a scenario's expressions against its vocabulary; every problem is located in its file.

    ``terms``: (name, spec, locate) with the term at ``terms.<name>`` of the file ``locate`` reads
    (the reward table's or the scenario's); ``endings``: (path, expression, locate) of each ``ends_on``
    entry that is not an event; ``shaping`` and ``locate``: the scenario's.
    """
    if not (terms or shaping or endings):
        return ScenarioExpressions()
    if vocabulary is None:
        raise ScenarioError([Problem(locate(("terms",)),
                                     f"{compiled.environment} has no vocabulary for expressions yet")])
    quantities = vocabulary.quantities(compiled)
    problems: list[Problem] = []
    built: list[ExpressionTerm] = []

    def attempt(path: PathKey, source: str, want: str, where_is: Locate = locate) -> Optional[Expression]:
        try:
            return compile_expression(source, quantities, want=want, agents=compiled.agents)
        except ExpressionError as exc:
            problems.append(located(where_is, path, source, exc.offset,
                                    f"{dotted(path)}: {_explained(exc, source, vocabulary)}"))
            return None

    for name, spec, where_is in terms:
        path = ("terms", name, "expr")
        expression = attempt(path, spec.expr, "number", where_is)
        if expression is not None:
            contract = _contract(name, spec, expression, quantities, ("terms", name), where_is, problems)
            if contract is not None:
                built.append(ExpressionTerm(contract, expression))
    if shaping is not None:
        taken = set(registered) | {name for name, _, _ in terms}
        built += _shaping_term(shaping, attempt, quantities, locate, problems, taken)
    compiled_endings = [e for e in (attempt(path, source, "bool", where_is) for path, source, where_is in endings)
                        if e is not None]
    if problems:
        raise ScenarioError(problems)
    return ScenarioExpressions(vocabulary, tuple(built), tuple(compiled_endings))


UNTRACED = ("reported at the start of the value: the YAML quoting of this expression could not be followed "
            "to the offending character")


def located(where_is: Locate, path: PathKey, source: str, offset: int, message: str) -> Problem:
    """``message`` at the file, line and column where ``source[offset]`` is written (the expression at ``path``
    of the file ``where_is`` reads); at the start of its value, saying so, when its quoting cannot be followed."""
    start = where_is(path)
    where = traced_location(start, source, offset)
    return Problem(where, message) if where is not None else Problem(start, f"{message} ({UNTRACED})")


def _explained(error: ExpressionError, source: str, vocabulary: Vocabulary) -> str:
    """The error's message; for an unknown quantity the simulator does not model, why it does not."""
    name = source[error.offset: error.offset + error.length]
    why = vocabulary.absence(name) if error.message.startswith("unknown quantity") else None
    return f"unknown quantity {name!r}: {why}" if why else error.message


def _contract(name: str, spec: ExpressionTermSpec, expression: Expression, quantities: Mapping[str, Any],
              path: PathKey, locate: Locate, problems: list[Problem]) -> Optional[TermContract]:
    low, high = float(expression.low), float(expression.high)
    if spec.range is not None:
        if not (spec.range[0] <= low and high <= spec.range[1]):
            problems.append(Problem(locate(path + ("range",)), (
                f"{dotted(path)}.range: [{spec.range[0]:g}, {spec.range[1]:g}] does not contain the expression's "
                f"range [{low:g}, {high:g}] (inferred from the vocabulary's ranges)")))
            return None
        low, high = spec.range
    sign = spec.sign or ("bonus" if low >= 0 else "penalty" if high <= 0 else "mixed")
    try:
        return TermContract(name=name, title=spec.title or name.replace("_", " ").capitalize(),
                            description=spec.description or _described(expression.source),
                            low=low, high=high, sign=sign, timing=spec.timing,
                            scope=spec.scope or _scope(expression, quantities), equation=expression.source)
    except ValueError as exc:
        problems.append(Problem(locate(path + ("sign",)), f"{dotted(path)}.sign: {exc} (range [{low:g}, {high:g}])"))
        return None


@functools.lru_cache(maxsize=4096)
def _described(source: str) -> str:
    """A term's default description, one string object per expression: a sweep's points share it (a copy per
    point of a 2,000-character expression made a 10,000-point sweep of 50 terms hold 1 GB of descriptions)."""
    return f"The expression {source}."


def _scope(expression: Expression, quantities: Mapping[str, Any]) -> str:
    """agent for a per-agent value; team for a per-world value built from agents; global otherwise."""
    if expression.per == "agent":
        return "agent"
    read = set(expression.reads) | set(expression.reads_prev)
    return "team" if any(quantities[n].per == "agent" for n in read) else "global"


def _shaping_term(spec: ShapingSpec, attempt, quantities, locate: Locate, problems: list[Problem],
                  taken: set[str]) -> list[ExpressionTerm]:
    path = ("shaping", "potential")
    if spec.name in taken:
        problems.append(Problem(locate(("shaping", "name")), f"shaping.name: '{spec.name}' is already a reward term; "
                                                             "give the shaping term another name"))
        return []
    potential = attempt(path, spec.potential, "number")
    if potential is None:
        return []
    if potential.reads_prev:  # blamed on the first prev( or delta( written
        problems.append(located(locate, path, spec.potential, timed_calls(spec.potential)[0],
                                "shaping.potential: a potential is a function of the state alone; "
                                "it may not use prev() or delta()"))
        return []
    g, low, high = spec.gamma, float(potential.low), float(potential.high)
    # gamma * phi' - phi over phi, phi' in [low, high]
    f_low, f_high = min(g * low, g * high) - high, max(g * low, g * high) - low
    contract = TermContract(name=spec.name, title=spec.title, low=f_low, high=f_high, sign="mixed", timing="dense",
                            scope=_scope(potential, quantities),
                            description=(f"Potential-based shaping gamma * phi(s') - phi(s) with gamma = {g:g} and "
                                         f"phi = {potential.source}; it leaves the optimal policy unchanged."),
                            equation=f"{g:g} * phi(s') - phi(s),  phi = {potential.source}")
    return [ExpressionTerm(contract, potential, gamma=g)]


def event_names(ends_on: tuple[str, ...], events: Mapping[str, str]) -> tuple[str, ...]:
    """The entries of an ``ends_on`` list that name events (the others are expressions)."""
    return tuple(e for e in ends_on if e in events)


def with_expressions(compiled: Any, spec: Any, locate: Locate) -> Any:
    """``compiled`` with its expression terms, shaping and endings compiled against the vocabulary.

    The reward table's expression terms and its task's expression endings come first, located in
    the table's file; the scenario's follow, located in the scenario.
    """
    entry = compiled.entry
    table, in_table = entry.reward_table, entry.reward_table_file.locate
    terms = [(name, term, in_table) for name, term in (table.terms or {}).items()]
    terms += [(name, term, locate) for name, term in (spec.terms or {}).items()]
    task_ends = table.tasks[compiled.task_index].ends_on
    endings = [(("tasks", compiled.task_index, "ends_on", k), e, in_table) for k, e in enumerate(task_ends)
               if e not in entry.events]
    endings += [(path, e, locate) for path, e in split_ends_on(spec, entry.events)[1].items()]
    if not (terms or spec.shaping or endings):
        return compiled
    try:
        vocabulary = vocabulary_of(compiled.environment)
    except ModuleNotFoundError:
        vocabulary = None
    expressions = compile_expressions(compiled, vocabulary, terms, spec.shaping, endings, locate, entry.term_names)
    return dataclasses.replace(compiled, expressions=expressions)
