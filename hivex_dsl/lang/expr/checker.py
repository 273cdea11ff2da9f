"""The checker: walks the parsed tree once, inferring kind, shape, unit and range of every node
and building its evaluation plan, and refuses a node at its own source span when it is wrong."""

from __future__ import annotations

import difflib
from dataclasses import dataclass
from fractions import Fraction
from typing import Mapping

import numpy as np

from ...base import portable
from ...base.errors import did_you_mean
from . import intervals, narrowing, plan, units
from .errors import ExpressionError
from .grammar import FUNCTIONS
from .intervals import Interval, Refused
from .syntax import Binary, Call, Compare, Name, Node, Number, Token, Unary, written_number

_COMPARE = {"<": np.less, "<=": np.less_equal, ">": np.greater, ">=": np.greater_equal,
            "==": np.equal, "!=": np.not_equal}
_ARITHMETIC = {"+": (np.add, intervals.add), "-": (np.subtract, intervals.subtract),
               "*": (np.multiply, intervals.multiply), "/": (np.true_divide, intervals.divide)}
_REDUCTIONS = {"team_min": np.minimum, "team_max": np.maximum, "team_sum": np.add}
_BOOL = (0.0, 1.0)
_BOOLEAN_CONSTANTS = {"true": True, "false": False}
MAX_EXPONENT = 1024
_REFINEMENTS = 64


@dataclass(frozen=True)
class Typed:
    """What the checker knows of a node: ``per`` None and ``unit`` None mark a constant that adapts."""

    kind: str
    per: str | None
    unit: units.Unit | None
    interval: Interval
    op: plan.Op


class Checker:
    def __init__(self, vocabulary: Mapping, agents: int | None, mean_agents: int):
        self.vocabulary = vocabulary
        self.agents = agents  # bounds team_sum; None refuses it
        self.mean_agents = mean_agents  # bounds the rounding of team_mean
        self.region: narrowing.Region = {}  # what the where() conditions around the current node guarantee
        self.refinements = _REFINEMENTS  # re-checks of where() branches left, so nesting stays linear
        self.reads: set[str] = set()
        self.reads_prev: set[str] = set()

    def check(self, node: Node, before: bool = False) -> Typed:
        if isinstance(node, Number):
            return self.number(node)
        if isinstance(node, Name):
            return self.name(node, before)
        if isinstance(node, Unary):
            return self.unary(node, before)
        if isinstance(node, Binary):
            return self.binary(node, before)
        if isinstance(node, Compare):
            return self.compare(node, before)
        return self.call(node, before)

    def number(self, node: Number) -> Typed:
        if not node.value <= intervals.LIMIT:
            raise ExpressionError(f"number too large (at most {intervals.LIMIT:g})", node.offset, node.length)
        unit = None
        if node.unit is not None:
            try:
                unit = units.parse_unit(node.unit)
            except ValueError as error:
                raise ExpressionError(str(error), node.offset, node.length) from None
        return Typed("number", None, unit, (node.value, node.value), plan.const(node.value))

    def name(self, node: Name, before: bool) -> Typed:
        quantity = self.vocabulary.get(node.name)
        if quantity is None and node.name in _BOOLEAN_CONSTANTS:  # the grammar's `true` and `false`
            value = _BOOLEAN_CONSTANTS[node.name]
            return Typed("bool", None, None, (float(value), float(value)), plan.const(value))
        if quantity is None:
            if node.name in FUNCTIONS:
                raise ExpressionError(f"{node.name!r} is a function; call it as {FUNCTIONS[node.name].signature}",
                                      node.offset, node.length)
            hint = did_you_mean(node.name, self.vocabulary) or _function_hint(node.name)
            raise ExpressionError(f"unknown quantity {node.name!r}{hint}", node.offset, node.length)
        (self.reads_prev if before else self.reads).add(node.name)
        unit = None if quantity.kind == "bool" else units.parse_unit(quantity.unit)
        interval = _BOOL if quantity.kind == "bool" else (float(quantity.low), float(quantity.high))
        if quantity.kind == "number":
            interval = narrowing.within(self.region, (node.name, before), interval)
        return Typed(quantity.kind, quantity.per, unit, interval, plan.read(node.name, before))

    def unary(self, node: Unary, before: bool) -> Typed:
        a = self.check(node.operand, before)
        if node.op.text == "not":
            self.need_bool(node.op.text, a, node.operand)
            return Typed("bool", a.per, None, _BOOL, plan.apply1(np.logical_not, a.op))
        self.need_number("'-'", a, node.operand)
        return Typed("number", a.per, a.unit, intervals.negate(a.interval), plan.apply1(np.negative, a.op))

    def binary(self, node: Binary, before: bool) -> Typed:
        op = node.op.text
        if op == "**":
            return self.power(node, before)
        a, b = self.check(node.left, before), self.check(node.right, before)
        per, (x, y) = _aligned(a, b)
        if op in ("and", "or"):
            self.need_bool(op, a, node.left)
            self.need_bool(op, b, node.right)
            ufunc = np.logical_and if op == "and" else np.logical_or
            return Typed("bool", per, None, _BOOL, plan.apply2(ufunc, x, y))
        self.need_number(f"{op!r}", a, node.left)
        self.need_number(f"{op!r}", b, node.right)
        ufunc, rule = _ARITHMETIC[op]
        if op in "+-":
            unit = _same_unit(f"{op!r}", node.op, a, b)
        elif a.unit is None and b.unit is None:
            unit = None
        else:
            combine = units.multiply if op == "*" else units.divide
            unit = combine(a.unit or units.DIMENSIONLESS, b.unit or units.DIMENSIONLESS)
        if op == "*" and _same_tree(node.left, node.right):
            rule = lambda x_range, _: intervals.power(x_range, 2)  # noqa: E731 (x * x is x ** 2's bits: never negative)
        interval = _refusing(node.op, lambda: intervals.checked(rule(a.interval, b.interval), f"{op!r}"))
        return Typed("number", per, unit, interval, plan.apply2(ufunc, x, y))

    def power(self, node: Binary, before: bool) -> Typed:
        base = self.check(node.left, before)
        self.need_number("'**'", base, node.left)
        exponent = written_number(node.right)
        if isinstance(node.right, Binary) and node.right.op.text == "**":
            raise ExpressionError("'**' groups to the right, so a ** b ** c is a ** (b ** c), and the exponent of "
                                  "'**' must be a number written out: write b ** c's value, e.g. 2 ** 3 as 8",
                                  node.right.offset, node.right.length)
        if exponent is None or _unit_written(node.right):
            raise ExpressionError("the exponent of '**' must be a number written out, e.g. x ** 2",
                                  node.right.offset, node.right.length)
        if abs(exponent) > MAX_EXPONENT:
            raise ExpressionError(f"the exponent of '**' is too large (at most {MAX_EXPONENT} in size)",
                                  node.right.offset, node.right.length)
        unit = base.unit
        if unit is not None:
            try:
                unit = units.power(unit, Fraction(exponent))
            except ValueError as error:
                raise ExpressionError(f"'**': {error}", node.op.offset, len(node.op.text)) from None
        interval = _refusing(node.op, lambda: intervals.checked(intervals.power(base.interval, exponent), "'**'"))
        n = int(exponent) if exponent.is_integer() else exponent
        return Typed("number", base.per, unit, interval, plan.apply2(portable.power, base.op, ("c", n)))

    def compare(self, node: Compare, before: bool) -> Typed:
        operands = [self.check(operand, before) for operand in node.operands]
        per, aligned = _aligned(*operands)
        result = None
        for i, token in enumerate(node.ops):
            a, b = operands[i], operands[i + 1]
            if a.kind == "bool" or b.kind == "bool":
                if token.text not in ("==", "!=") or a.kind != b.kind:
                    blame = node.operands[i] if a.kind == "bool" else node.operands[i + 1]
                    why = ("; only == and != can" if token.text not in ("==", "!=") else
                           " with a number; a boolean is a condition already: use it (or not it) as it is")
                    raise ExpressionError(f"{token.text!r} cannot compare a boolean{why}", blame.offset, blame.length)
            else:
                _same_unit(f"{token.text!r}", token, a, b)
            step = plan.apply2(_COMPARE[token.text], aligned[i], aligned[i + 1])
            result = step if result is None else plan.apply2(np.logical_and, result, step)
        return Typed("bool", per, None, _BOOL, result)

    def call(self, node: Call, before: bool) -> Typed:
        name, token = node.function.text, node.function
        entry = FUNCTIONS.get(name)
        if entry is None:
            if name in self.vocabulary:
                raise ExpressionError(f"{name!r} is a quantity, not a function", token.offset, len(name))
            raise ExpressionError(f"unknown function {name!r}{did_you_mean(name, FUNCTIONS)}", token.offset, len(name))
        if len(node.args) != entry.arity:
            s = "" if entry.arity == 1 else "s"
            raise ExpressionError(f"{entry.signature} takes {entry.arity} argument{s}, got {len(node.args)}",
                                  node.offset, node.length)
        if name in ("prev", "delta"):
            return self.timed(node, before)
        if name.startswith("team_"):  # a reduction reads every agent: no condition on one agent holds for all
            return self.reduction(node, self.within({}, node.args[0], before))
        args = [self.check(arg, before) for arg in node.args]
        if name == "where":
            return self.where(node, args, before)
        for arg, source in zip(args, node.args):
            self.need_number(name, arg, source)
        per, ops = _aligned(*args)
        a = args[0]
        if name in ("min", "max", "clip"):
            unit = _same_unit(name, token, *args)
            ufunc, rule = (np.minimum, intervals.minimum) if name == "min" else (np.maximum, intervals.maximum)
            if name == "clip":
                low, high = args[1].interval, args[2].interval
                if low[0] > high[1]:  # lo above hi everywhere: the result would be hi whatever x is
                    raise ExpressionError(f"clip's lower bound ({_bounds(low)}) is above its upper bound "
                                          f"({_bounds(high)}): write clip(x, lo, hi) with lo <= hi",
                                          node.offset, node.length)
                interval = intervals.minimum(intervals.maximum(a.interval, args[1].interval), args[2].interval)
                return Typed("number", per, unit, interval, plan.clip(*ops))
            return Typed("number", per, unit, rule(a.interval, args[1].interval), plan.apply2(ufunc, *ops))
        if name == "abs":
            return Typed("number", per, a.unit, intervals.absolute(a.interval), plan.apply1(np.absolute, a.op))
        if name == "sqrt":
            try:
                unit = None if a.unit is None else units.power(a.unit, Fraction(1, 2))
            except ValueError:
                raise ExpressionError(f"sqrt of {units.format_unit(a.unit)} has no whole unit (an odd exponent)",
                                      node.args[0].offset, node.args[0].length) from None
            interval = _refusing(token, lambda: intervals.sqrt(a.interval))
            return Typed("number", per, unit, interval, plan.apply1(np.sqrt, a.op))
        if a.unit:
            raise ExpressionError(f"{name} needs a dimensionless argument, got {units.format_unit(a.unit)}",
                                  node.args[0].offset, node.args[0].length)
        rule, ufunc = (intervals.exp, portable.exp) if name == "exp" else (intervals.log, portable.log)
        interval = _refusing(token, lambda: intervals.checked(rule(a.interval), name))
        return Typed("number", per, a.unit, interval, plan.apply1(ufunc, a.op))

    def timed(self, node: Call, before: bool) -> Typed:
        name, arg = node.function.text, node.args[0]
        if before:
            raise ExpressionError(f"{name}() inside prev() or delta(): a value before the step has no value before it",
                                  node.offset, node.length)
        then = self.check(arg, True)
        if name == "prev":
            return then
        now = self.check(arg, False)
        self.need_number("delta", now, arg)
        interval = intervals.checked(intervals.subtract(now.interval, then.interval), "delta")
        return Typed("number", now.per, now.unit, interval, plan.apply2(np.subtract, now.op, then.op))

    def reduction(self, node: Call, a: Typed) -> Typed:
        name, arg = node.function.text, node.args[0]
        self.need_number(name, a, arg)
        if a.per != "agent":
            got = "a per-world value" if a.per == "world" else "a constant"
            raise ExpressionError(f"{name} needs a per-agent value, got {got}", arg.offset, arg.length)
        if name == "team_mean":
            interval, op = intervals.team_mean(a.interval, self.mean_agents), plan.mean(a.op)
        elif name == "team_sum":
            if self.agents is None:
                raise ExpressionError("team_sum needs the number of agents per world (compile with agents=N)",
                                      node.offset, node.length)
            interval, op = intervals.team_sum(a.interval, self.agents), plan.reduce(np.add, a.op)
        else:
            interval, op = a.interval, plan.reduce(_REDUCTIONS[name], a.op)
        interval = _refusing(node.function, lambda: intervals.checked(interval, name))
        return Typed("number", "world", a.unit, interval, op)

    def within(self, region: narrowing.Region, node: Node, before: bool) -> Typed:
        """``node`` checked with the quantities narrowed to ``region`` (and nothing else)."""
        outer, self.region = self.region, region
        try:
            return self.check(node, before)
        finally:
            self.region = outer

    def chosen_range(self, node: Call, a: Typed, b: Typed, before: bool) -> Interval:
        """The hull of each branch's range where it is the one chosen (see :mod:`.narrowing`)."""
        if self.refinements <= 0:
            return intervals.hull(a.interval, b.interval)
        self.refinements -= 1
        number = lambda name: self.vocabulary[name].kind == "number"  # noqa: E731
        held, failed = narrowing.regions(node.args[0], before, number)
        ranges = []
        for branch, region in ((node.args[1], held), (node.args[2], failed)):
            region = narrowing.both(self.region, region)
            if any(_empty(narrowing.within(region, key, self.full_range(key[0]))) for key in region):
                continue  # this branch is never chosen
            ranges.append(self.within(region, branch, before).interval)
        return ranges[0] if len(ranges) == 1 else intervals.hull(*ranges)

    def full_range(self, name: str) -> Interval:
        quantity = self.vocabulary[name]
        return float(quantity.low), float(quantity.high)

    def where(self, node: Call, args: list[Typed], before: bool) -> Typed:
        condition, a, b = args
        self.need_bool("where's condition", condition, node.args[0])
        if a.kind != b.kind:
            raise ExpressionError("where's branches must both be numbers or both be booleans",
                                  node.args[2].offset, node.args[2].length)
        unit = _same_unit("where's branches", node.function, a, b) if a.kind == "number" else None
        per, ops = _aligned(condition, a, b)
        interval = self.chosen_range(node, a, b, before) if a.kind == "number" else _BOOL
        return Typed(a.kind, per, unit, interval, plan.select(*ops))

    @staticmethod
    def need_number(what: str, typed: Typed, node: Node) -> None:
        if typed.kind != "number":
            raise ExpressionError(f"{what} needs a number, got a boolean; "
                                  "turn a condition into a number with where(cond, 1, 0)", node.offset, node.length)

    @staticmethod
    def need_bool(what: str, typed: Typed, node: Node) -> None:
        if typed.kind != "bool":
            raise ExpressionError(f"{what!s} needs a boolean (a comparison such as x > 0), got a number",
                                  node.offset, node.length)


def _aligned(*typed: Typed) -> tuple[str | None, list[plan.Op]]:
    """The shape of a combination and its operands' plans, per-world ones expanded if any is per-agent."""
    pers = {t.per for t in typed}
    per = "agent" if "agent" in pers else ("world" if "world" in pers else None)
    ops = [plan.expand(t.op) if per == "agent" and t.per == "world" else t.op for t in typed]
    return per, ops


def _same_unit(what: str, token: Token, *typed: Typed) -> units.Unit | None:
    found = [t.unit for t in typed if t.unit is not None]
    for unit in found[1:]:
        if unit != found[0]:
            raise ExpressionError(f"{what} needs operands of the same unit, got "
                                  f"{units.format_unit(found[0])} and {units.format_unit(unit)}",
                                  token.offset, len(token.text))
    return found[0] if found else None


def _same_tree(a: Node, b: Node) -> bool:
    """Whether two subtrees are written alike (wherever they stand), so they compute the same values."""
    if type(a) is not type(b):
        return False
    if isinstance(a, Number):
        return (a.value, a.unit) == (b.value, b.unit)
    if isinstance(a, Name):
        return a.name == b.name
    if isinstance(a, Unary):
        return a.op.text == b.op.text and _same_tree(a.operand, b.operand)
    if isinstance(a, Binary):
        return a.op.text == b.op.text and _same_tree(a.left, b.left) and _same_tree(a.right, b.right)
    if isinstance(a, Compare):
        return [t.text for t in a.ops] == [t.text for t in b.ops] and all(map(_same_tree, a.operands, b.operands))
    return (a.function.text == b.function.text and len(a.args) == len(b.args)
            and all(map(_same_tree, a.args, b.args)))


def _empty(interval: Interval) -> bool:
    return interval[0] > interval[1]


def _function_hint(name: str) -> str:
    close = difflib.get_close_matches(name, list(FUNCTIONS), n=1, cutoff=0.6)  # did_you_mean's cutoff
    return f"; did you mean the function {FUNCTIONS[close[0]].signature}?" if close else ""


def _unit_written(node: Node) -> bool:
    return (node.operand if isinstance(node, Unary) else node).unit is not None


def _refusing(token: Token, rule):
    try:
        return rule()
    except Refused as error:
        raise ExpressionError(str(error), token.offset, len(token.text)) from None


def _bounds(interval: Interval) -> str:
    """``(1.0, 1.0)`` -> ``1``; ``(0.0, 2.5)`` -> ``0 to 2.5``."""
    low, high = interval
    return f"{low:g}" if low == high else f"{low:g} to {high:g}"
