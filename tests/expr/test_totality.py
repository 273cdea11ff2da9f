"""Totality, property-tested: random expressions over random vocabularies either are refused at
compile time or, for any inputs inside their quantities' ranges, evaluate without a floating-point
error (overflow, invalid, divide; NumPy set to raise) to values inside the inferred interval."""

from __future__ import annotations

import numpy as np
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from hivex_dsl.lang.expr import ExpressionError, Quantity, compile_expression

AGENTS = 3
LITERALS = ("0", "0.5", "1", "2", "3", "10", "0.001", "1000", "1e-300", "1e200")
EXPONENTS = ("2", "3", "-1", "-2", "0.5", "1.5", "0")
ENDS = (-1e150, -1000.0, -2.0, -1.0, -0.1, -1e-300, 0.0, 1e-300, 0.1, 0.5, 0.7, 1.0, 3.0, 700.0, 1e150)


@st.composite
def vocabularies(draw):
    quantities = []
    for i in range(draw(st.integers(2, 5))):
        low, high = sorted((draw(st.sampled_from(ENDS)), draw(st.sampled_from(ENDS))))
        quantities.append(Quantity(f"q{i}", draw(st.sampled_from(("agent", "world"))), "number", "1", low, high, ""))
    quantities.append(Quantity("flag", draw(st.sampled_from(("agent", "world"))), "bool", "", 0.0, 1.0, ""))
    return {q.name: q for q in quantities}


def numbers(draw, names, depth):
    if depth <= 0 or draw(st.integers(0, 3)) == 0:
        return draw(st.sampled_from(names + LITERALS))
    a = lambda: numbers(draw, names, depth - 1)  # noqa: E731
    form = draw(st.integers(0, 12))
    if form == 0:
        return f"-{a()}"
    if form <= 3:
        return f"({a()} {draw(st.sampled_from('+-*/'))} {a()})"
    if form == 4:
        return f"({a()}) ** {draw(st.sampled_from(EXPONENTS))}"
    if form == 5:
        return f"{draw(st.sampled_from(('min', 'max')))}({a()}, {a()})"
    if form == 6:
        return f"{draw(st.sampled_from(('abs', 'exp', 'log', 'sqrt', 'prev', 'delta')))}({a()})"
    if form == 7:
        return f"clip({a()}, {a()}, {a()})"
    if form == 8:
        return f"where({conditions(draw, names, depth - 1)}, {a()}, {a()})"
    if form == 9:
        return f"{draw(st.sampled_from(('team_mean', 'team_min', 'team_max', 'team_sum')))}({a()})"
    return f"({a()} {draw(st.sampled_from(('+', '*')))} {a()})"


def conditions(draw, names, depth):
    form = draw(st.integers(0, 3))
    if depth <= 0 or form == 0:
        return "flag"
    if form == 1:
        return f"({numbers(draw, names, depth - 1)} {draw(st.sampled_from(('<', '<=', '>', '>=', '==', '!=')))} " \
               f"{numbers(draw, names, depth - 1)})"
    if form == 2:
        return f"not {conditions(draw, names, depth - 1)}"
    return f"({conditions(draw, names, depth - 1)} {draw(st.sampled_from(('and', 'or')))} " \
           f"{conditions(draw, names, depth - 1)})"


@st.composite
def cases(draw):
    vocabulary = draw(vocabularies())
    names = tuple(name for name in vocabulary if name != "flag")
    source = numbers(draw, names, draw(st.integers(1, 4)))
    return vocabulary, source, draw(st.integers(0, 2**32 - 1)), draw(st.integers(1, AGENTS))


def inputs(vocabulary, rng, agents, batch=5):
    """Values inside every range, its ends and zero (where inside) included."""
    values = {}
    for q in vocabulary.values():
        shape = (batch, agents) if q.per == "agent" else (batch,)
        if q.kind == "bool":
            values[q.name] = rng.random(shape) < 0.5
            continue
        candidates = np.array([q.low, q.high, min(max(0.0, q.low), q.high)])
        mixed = np.where(rng.random(shape) < 0.5, rng.choice(candidates, shape), rng.uniform(q.low, q.high, shape))
        values[q.name] = np.clip(mixed, q.low, q.high)
    return values


@settings(max_examples=200, deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
@given(cases())
def test_an_expression_that_compiles_is_total_and_inside_its_interval(case):
    vocabulary, source, seed, agents = case
    try:
        expression = compile_expression(source, vocabulary, agents=AGENTS)
    except ExpressionError:
        assume(False)
    rng = np.random.default_rng(seed)
    now, before = inputs(vocabulary, rng, agents), inputs(vocabulary, rng, agents)
    kept = {name: array.copy() for name, array in now.items()}
    with np.errstate(over="raise", invalid="raise", divide="raise", under="ignore"):
        value = expression.evaluate(now, before)
    assert value.dtype == np.float64
    assert value.shape == ((5, agents) if expression.per == "agent" else (5,))
    assert np.isfinite(value).all()
    assert all(np.array_equal(now[name], kept[name]) for name in now), "an input was modified"
    assert not any(np.shares_memory(value, array) for array in (*now.values(), *before.values()))
    assert expression.low <= value.min() and value.max() <= expression.high, (source, expression, value)


CUTS = ("-2", "-1", "-0.5", "0", "0.5", "1", "2", "3")
BRANCHES = ("q", "-q", "q * 2", "q ** 2", "1", "abs(q)", "q - 1")
CONDITIONS = ("q {op} {c}", "{c} {op} q", "not (q {op} {c})", "{c} < q <= {d}", "q > {c} and q < {d}",
              "q < {c} or q >= {d}", "(q {op} {c}) and flag", "not (q < {c} or q > {d})")


@settings(max_examples=300, deadline=None)
@given(st.sampled_from(ENDS[1:-1]), st.sampled_from(ENDS[1:-1]), st.sampled_from(CONDITIONS),
       st.sampled_from(("<", "<=", ">", ">=", "==", "!=")), st.sampled_from(CUTS), st.sampled_from(CUTS),
       st.sampled_from(BRANCHES), st.sampled_from(BRANCHES), st.integers(0, 2**32 - 1))
def test_where_narrows_each_branch_to_where_it_is_chosen_soundly(end_a, end_b, condition, op, c, d, a, b, seed):
    low, high = sorted((end_a, end_b))
    vocabulary = {"q": Quantity("q", "agent", "number", "1", low, high, ""),
                  "flag": Quantity("flag", "agent", "bool", "", 0.0, 1.0, "")}
    source = f"where({condition.format(op=op, c=c, d=d)}, {a}, {b})"
    try:
        expression = compile_expression(source, vocabulary)
    except ExpressionError:
        assume(False)
    rng = np.random.default_rng(seed)
    cuts = np.array([float(c), float(d)])
    near = np.concatenate([cuts, np.nextafter(cuts, np.inf), np.nextafter(cuts, -np.inf), [low, high, 0.0]])
    values = np.clip(np.concatenate([near, rng.uniform(low, high, 16)]), low, high)[None, :]
    now = {"q": values, "flag": rng.random(values.shape) < 0.5}
    result = expression.evaluate(now, now)
    assert expression.low <= result.min() and result.max() <= expression.high, (source, expression, result)
