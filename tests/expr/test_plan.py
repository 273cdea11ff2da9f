"""The fused plan (specialised closures, constant folding, broadcasting) computes the same bits
as a plain reference interpreter that walks the parsed tree with one NumPy call per node."""

from __future__ import annotations

import operator

import numpy as np
from hypothesis import HealthCheck, assume, given, settings

from hivex_dsl.base import portable
from hivex_dsl.lang.expr import ExpressionError, compile_expression
from hivex_dsl.lang.expr.syntax import Binary, Call, Compare, Name, Number, Unary, parse

from .test_totality import AGENTS, cases, inputs

_BINARY = {"+": operator.add, "-": operator.sub, "*": operator.mul, "/": operator.truediv,
           "and": np.logical_and, "or": np.logical_or}
_COMPARE = {"<": operator.lt, "<=": operator.le, ">": operator.gt, ">=": operator.ge, "==": operator.eq,
            "!=": operator.ne}
# exp, log and ** as the language defines them: the same bits on every processor (hivex_dsl.base.portable)
_CALLS = {"min": np.minimum, "max": np.maximum, "abs": np.abs, "exp": portable.exp, "log": portable.log,
          "sqrt": np.sqrt, "where": np.where, "clip": lambda x, lo, hi: np.minimum(np.maximum(x, lo), hi),
          "team_mean": lambda x: x.mean(axis=1, keepdims=True), "team_sum": lambda x: x.sum(axis=1, keepdims=True),
          "team_min": lambda x: x.min(axis=1, keepdims=True), "team_max": lambda x: x.max(axis=1, keepdims=True)}


def reference(node, now, before, vocabulary, then=False):
    """The value of ``node``, every per-world value kept as (batch, 1) so NumPy broadcasts it."""
    value = lambda child, at=then: reference(child, now, before, vocabulary, at)  # noqa: E731
    if isinstance(node, Number):
        return np.float64(node.value)
    if isinstance(node, Name):
        array = (before if then else now)[node.name]
        return array[:, None] if vocabulary[node.name].per == "world" else array
    if isinstance(node, Unary):
        return np.logical_not(value(node.operand)) if node.op.text == "not" else -value(node.operand)
    if isinstance(node, Binary) and node.op.text == "**":
        exponent = -node.right.operand.value if isinstance(node.right, Unary) else node.right.value
        base = value(node.left)
        return portable.power(base, exponent)
    if isinstance(node, Binary):
        return _BINARY[node.op.text](value(node.left), value(node.right))
    if isinstance(node, Compare):
        values = [value(operand) for operand in node.operands]
        pairs = [_COMPARE[op.text](a, b) for op, a, b in zip(node.ops, values, values[1:])]
        result = pairs[0]
        for pair in pairs[1:]:
            result = np.logical_and(result, pair)
        return result
    assert isinstance(node, Call)
    name = node.function.text
    if name == "prev":
        return value(node.args[0], True)
    if name == "delta":
        return value(node.args[0]) - value(node.args[0], True)
    return _CALLS[name](*(value(arg) for arg in node.args))


@settings(max_examples=200, deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
@given(cases())
def test_the_plan_gives_the_bits_of_a_node_by_node_interpretation(case):
    vocabulary, source, seed, agents = case
    try:
        expression = compile_expression(source, vocabulary, agents=AGENTS)
    except ExpressionError:
        assume(False)
    rng = np.random.default_rng(seed)
    now, before = inputs(vocabulary, rng, agents), inputs(vocabulary, rng, agents)
    got = expression.evaluate(now, before)
    expected = np.broadcast_to(reference(parse(source), now, before, vocabulary), (5, agents))
    expected = expected[:, 0] if expression.per == "world" else expected
    assert got.shape == expected.shape
    assert np.array_equal(got.view(np.uint64), np.ascontiguousarray(expected, dtype=np.float64).view(np.uint64)), \
        (source, got, expected)


# one operand of every mode the plan specialises on: constant, name now, name before, computed,
# and per-world names and values that are broadcast over the agents
OPERANDS = ("2", "q", "prev(q)", "abs(q)", "w", "prev(w)", "abs(w)", "team_max(q)")
TEMPLATES = ("{a} - {b}", "{a} / ({b} + 10)", "min({a}, {b})", "{a} < {b}", "where({a} < {b}, {a}, {b})",
             "clip({a}, {b}, 3)", "clip({a}, 0, {b})", "-{a}", "{a} ** 2", "team_mean({a})", "team_mean({a} * q)", "team_sum({a} - q)",
             "delta({a})", "sqrt({a} * {a})", "where({a} >= 1 and {b} < 1, 1, 0)")


def test_every_operand_mode_of_every_combinator_matches_the_reference():
    from hivex_dsl.lang.expr import Quantity

    vocabulary = {"q": Quantity("q", "agent", "number", "1", 0.0, 2.0, ""),
                  "w": Quantity("w", "world", "number", "1", 0.0, 2.0, "")}
    rng = np.random.default_rng(3)
    now = {"q": rng.uniform(0, 2, (4, 3)), "w": rng.uniform(0, 2, 4)}
    before = {"q": rng.uniform(0, 2, (4, 3)), "w": rng.uniform(0, 2, 4)}
    checked = 0
    for template in TEMPLATES:
        for a in OPERANDS:
            for b in OPERANDS:
                source = template.format(a=a, b=b)
                try:
                    expression = compile_expression(source, vocabulary, agents=3,
                                                    want="bool" if template == "{a} < {b}" else "number")
                except ExpressionError:
                    continue  # a constant, prev() of prev(), or a reduction of a per-world value
                got = expression.evaluate(now, before)
                expected = np.broadcast_to(reference(parse(source), now, before, vocabulary), (4, 3))
                expected = expected[:, 0] if expression.per == "world" else expected
                assert got.dtype == expected.dtype and np.array_equal(got, expected), source
                if got.dtype == np.float64:
                    bits = np.ascontiguousarray(expected).view(np.uint64)
                    assert np.array_equal(got.view(np.uint64), bits), source
                checked += 1
    assert checked > 300
