"""The grammar: tokens, precedence and associativity, checked through the values they compute."""

from __future__ import annotations

import numpy as np
import pytest

from hivex_dsl.lang.expr import ExpressionError, compile_expression, timed_calls
from hivex_dsl.lang.expr.syntax import Binary, Call, Compare, Name, Number, Unary, parse

from .conftest import AGENTS, VOCABULARY


def value(source, states, **kw):
    now, before = states
    return compile_expression(source, VOCABULARY, agents=AGENTS, **kw).evaluate(now, before)


@pytest.mark.parametrize("text, number", [("1", 1.0), ("2.5", 2.5), (".5", 0.5), ("1.", 1.0), ("1e3", 1000.0),
                                          ("2.5E-3", 0.0025), ("7e+2", 700.0)])
def test_number_literals(text, number):
    assert parse(text) == Number(0, len(text), number)


def test_a_number_may_carry_a_unit_in_braces():
    assert parse("5 {m/s}") == Number(0, 7, 5.0, "m/s")
    assert parse("(5{m})") == Number(1, 4, 5.0, "m")


def test_nodes_span_their_source():
    tree = parse("where(a < b, -c, d ** 2)")
    assert isinstance(tree, Call) and (tree.offset, tree.length) == (0, 24)
    condition, negated, power = tree.args
    assert isinstance(condition, Compare) and (condition.offset, condition.length) == (6, 5)
    assert isinstance(negated, Unary) and (negated.offset, negated.length) == (13, 2)
    assert isinstance(power, Binary) and power.op.text == "**" and (power.offset, power.length) == (17, 6)


def test_power_binds_tighter_than_unary_minus_and_is_right_associative():
    minus = parse("-a ** 2")
    assert isinstance(minus, Unary) and isinstance(minus.operand, Binary)
    right = parse("a ** 2 ** 3")
    assert isinstance(right.right, Binary) and right.right.op.text == "**"
    negative_exponent = parse("a ** -1")
    assert isinstance(negative_exponent.right, Unary)


def test_precedence_and_associativity_compute_as_python_does(states):
    now, _ = states
    w, s, d = now["water"], now["speed_ms"], now["distance_m"]
    np.testing.assert_array_equal(value("-water ** 2", states), -(w**2))
    np.testing.assert_array_equal(value("water - water / 2 - 1", states), w - w / 2 - 1)
    np.testing.assert_array_equal(value("water / 2 / (water + 1)", states), w / 2 / (w + 1))
    np.testing.assert_array_equal(value("speed_ms * 2 + speed_ms * 3", states), s * 2 + s * 3)
    np.testing.assert_array_equal(value("(water + 1) ** -2", states), (w + 1) ** -2)
    np.testing.assert_array_equal(value("2 ** 3 * water", states), 2**3 * w)
    np.testing.assert_array_equal(value("0 < distance_m / 2 <= 200 < 300", states, want="bool"),
                                  (0 < d / 2) & (d / 2 <= 200))


def test_boolean_operators_follow_python_precedence(states):
    now, _ = states
    dropped, raining, w = now["dropped"], now["raining"][:, None], now["water"]
    np.testing.assert_array_equal(value("not dropped and raining or water > 0.5", states, want="bool"),
                                  ((~dropped) & raining) | (w > 0.5))
    np.testing.assert_array_equal(value("not (dropped or raining)", states, want="bool"), ~(dropped | raining))
    np.testing.assert_array_equal(value("dropped != raining", states, want="bool"), dropped != raining)


def test_whitespace_and_line_breaks_are_free(states):
    np.testing.assert_array_equal(value("clip(\n  water,\n  0.25,\n  0.75\n)", states),
                                  value("clip(water,0.25,0.75)", states))


def test_offsets_are_characters_not_bytes():
    with pytest.raises(ExpressionError) as caught:
        compile_expression("water + ü", VOCABULARY)
    assert (caught.value.offset, caught.value.length, caught.value.message) == (8, 1, "unexpected character 'ü'")


def test_names_are_identifiers():
    assert parse("team_mean") == Name(0, 9, "team_mean")


def test_timed_calls_are_found_where_they_are_written_in_every_kind_of_node():
    source = "where(x > 1 and -delta(y) < 2, prev(x), 0) + abs(x) * delta(prev(y))"
    assert timed_calls(source) == tuple(source.index(word) for word in ("delta(y)", "prev(x)", "delta(prev", "prev(y)"))
    assert timed_calls("team_mean(x) + 1") == ()
