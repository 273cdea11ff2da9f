"""Every class of mistake: its exact message and the offset and length of the token it blames."""

from __future__ import annotations

import pytest

from hivex_dsl.lang.expr import ExpressionError, compile_expression

from .conftest import AGENTS, VOCABULARY

CASES = [
    # (source, message, blamed text[, its offset where it is not the text's first occurrence])
    # names and functions
    ("distnce_m + 1", "unknown quantity 'distnce_m'; did you mean 'distance_m'?", "distnce_m"),
    ("1 + zzz", "unknown quantity 'zzz'", "zzz"),
    ("team_mena + 1", "unknown quantity 'team_mena'; did you mean the function team_mean(x)?", "team_mena"),
    ("sqr(water)", "unknown function 'sqr'; did you mean 'sqrt'?", "sqr"),
    ("team_avg(water)", "unknown function 'team_avg'; did you mean 'team_max'?", "team_avg"),
    ("water(1)", "'water' is a quantity, not a function", "water"),
    ("sqrt + 1", "'sqrt' is a function; call it as sqrt(x)", "sqrt"),
    ("clip(water, 0)", "clip(x, lo, hi) takes 3 arguments, got 2", "clip(water, 0)"),
    ("abs()", "abs(x) takes 1 argument, got 0", "abs()"),
    ("clip(water, 1, -1)", "clip's lower bound (1) is above its upper bound (-1): write clip(x, lo, hi) with lo <= hi",
     "clip(water, 1, -1)"),
    # syntax
    ("(water + 1", "unclosed '('", "("),
    ("water +", "expected a number, a name or '(', got end of expression", ""),
    ("water 2", "unexpected '2' after a complete expression", "2"),
    ("water * * 2", "expected a number, a name or '(', got '*'", "*", 8),
    ("min(water, 1))", "unexpected ')' after a complete expression", ")", 13),
    ("max(water 1)", "expected ')' or an operator, got '1'", "1"),
    ("2water", "malformed number '2water'", "2water"),
    ("water = 1", "use '==' to compare", "="),
    ("water ^ 2", "use '**' for powers", "^"),
    ("dropped && raining", "use 'and' to combine conditions", "&&"),
    ("+water", "unary '+' is not part of the expression language", "+"),
    ("water $ 1", "unexpected character '$'", "$"),
    ("", "empty expression", ""),
    # refused Python
    ("__import__('os')", "names with double underscores are not allowed ('__import__')", "__import__"),
    ("water.__class__", "attribute access ('.') is not allowed", ".__class__"),
    ("distance_m.real", "attribute access ('.') is not allowed", ".real"),
    ("water[0]", "subscripts ('[...]') are not allowed", "["),
    ("'water'", "strings are not allowed", "'water'"),
    ("lambda: 1", "'lambda' is not part of the expression language", "lambda"),
    ("import os", "'import' is not part of the expression language", "import"),
    ("water if dropped else 0", "'if' is not part of the expression language; use where(cond, a, b)", "if"),
    ("clip(water, lo=0, hi=1)", "keyword arguments are not allowed", "lo"),
    ("{1: 2}", "'{' is not part of the expression language", "{"),
    # shapes
    ("team_mean(wind_ms)", "team_mean needs a per-agent value, got a per-world value", "wind_ms"),
    ("team_sum(2)", "team_sum needs a per-agent value, got a constant", "2"),
    ("1 + 2", "the expression reads no quantity: it is a constant", "1 + 2"),
    ("prev(delta(water))", "delta() inside prev() or delta(): a value before the step has no value before it",
     "delta(water)"),
    # kinds
    ("dropped + distance_m", "'+' needs a number, got a boolean; turn a condition into a number with where(cond, 1, 0)",
     "dropped"),
    ("water and dropped", "and needs a boolean (a comparison such as x > 0), got a number", "water"),
    ("where(water, 1, 0)", "where's condition needs a boolean (a comparison such as x > 0), got a number", "water"),
    ("where(dropped, water, raining)", "where's branches must both be numbers or both be booleans", "raining"),
    ("dropped < raining", "'<' cannot compare a boolean; only == and != can", "dropped"),
    ("where(dropped == 1, water, 0)", "'==' cannot compare a boolean with a number; a boolean is a condition already: "
     "use it (or not it) as it is", "dropped"),
    # units
    ("distance_m + speed_ms", "'+' needs operands of the same unit, got m and m/s", "+"),
    ("max(distance_m, heading_deg)", "max needs operands of the same unit, got m and deg", "max"),
    ("distance_m < 5{m/s}", "'<' needs operands of the same unit, got m and m/s", "<"),
    ("where(dropped, distance_m, wind_ms)", "where's branches needs operands of the same unit, got m and m/s", "where"),
    ("exp(distance_m)", "exp needs a dimensionless argument, got m", "distance_m"),
    ("log(speed_ms * 1{s})", "log needs a dimensionless argument, got m", "speed_ms * 1{s}"),
    ("sqrt(distance_m)", "sqrt of m has no whole unit (an odd exponent)", "distance_m"),
    ("distance_m ** 0.5", "'**': m to the power 1/2 has no whole unit", "**"),
    ("water * 2{m/}", "malformed unit 'm/' at character 2", "2{m/}"),
    # ranges
    ("water / speed_ms", "'/' can divide by zero: the divisor ranges over [-5, 5]; keep it away from 0, "
     "e.g. with max(x, 0.001)", "/"),
    ("1 / (water - 0.5)", "'/' can divide by zero: the divisor ranges over [-0.5, 0.5]; keep it away from 0, "
     "e.g. with max(x, 0.001)", "/"),
    ("log(water)", "log needs a positive argument, but it ranges over [0, 1]", "log"),
    ("sqrt(water - 0.25)", "sqrt needs a non-negative argument, but it ranges over [-0.25, 0.75]", "sqrt"),
    ("exp(burning * 2)", "exp can overflow: its argument reaches 800 (at most 690.8)", "exp"),
    ("water ** -1", "'**' with a negative exponent can divide by zero: the base ranges over [0, 1]", "**"),
    ("(water - 1) ** 0.5", "'**' with a fractional exponent needs a non-negative base, but it ranges over [-1, 0]",
     "**"),
    ("burning * 1e299", "'*' can overflow: its value can reach 4e+301 (at most 1e+300)", "*"),
    ("water + 1e400", "number too large (at most 1e+300)", "1e400"),
    ("water ** 2000", "the exponent of '**' is too large (at most 1024 in size)", "2000"),
    ("water ** speed_ms", "the exponent of '**' must be a number written out, e.g. x ** 2", "speed_ms"),
    ("water ** 2{m}", "the exponent of '**' must be a number written out, e.g. x ** 2", "2{m}"),
    ("water * 2 ** 2 ** 3", "'**' groups to the right, so a ** b ** c is a ** (b ** c), and the exponent of '**' must "
     "be a number written out: write b ** c's value, e.g. 2 ** 3 as 8", "2 ** 3"),
]


@pytest.mark.parametrize("case", CASES, ids=[c[0] or "empty" for c in CASES])
def test_each_mistake_is_reported_at_its_token(case):
    source, message, blamed = case[:3]
    offset = case[3] if len(case) > 3 else (source.find(blamed) if blamed else len(source))
    with pytest.raises(ExpressionError) as caught:
        compile_expression(source, VOCABULARY, agents=AGENTS)
    error = caught.value
    assert error.message == message
    assert str(error) == message
    assert (error.offset, error.length) == (offset, len(blamed))


def test_blame_points_at_the_offending_operator_not_the_first_lookalike():
    with pytest.raises(ExpressionError) as caught:
        compile_expression("water / 2 + water / (water - 1)", VOCABULARY)
    assert (caught.value.offset, caught.value.length) == (18, 1)


def test_team_sum_needs_the_number_of_agents():
    with pytest.raises(ExpressionError, match="team_sum needs the number of agents"):
        compile_expression("team_sum(water)", VOCABULARY)


def test_deep_nesting_is_refused_not_a_recursion_error():
    with pytest.raises(ExpressionError, match="nested too deeply"):
        compile_expression("(" * 500 + "water" + ")" * 500, VOCABULARY)
    with pytest.raises(ExpressionError, match="nested too deeply"):
        compile_expression(" + ".join(["water"] * 500), VOCABULARY)
    for prefix in ("-", "not ", "abs("):
        with pytest.raises(ExpressionError, match="nested too deeply"):
            compile_expression(prefix * 2000 + "water", VOCABULARY)


def test_the_pointer_underlines_the_blamed_token():
    source = "distance_m + speed_ms"
    with pytest.raises(ExpressionError) as caught:
        compile_expression(source, VOCABULARY)
    assert caught.value.pointer(source) == "distance_m + speed_ms\n           ^"


def test_a_non_string_source_is_an_expression_error():
    with pytest.raises(ExpressionError, match="an expression is text, got int"):
        compile_expression(3, VOCABULARY)
