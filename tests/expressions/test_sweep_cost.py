"""A sweep compiles each distinct expression once: points share the compiled expression and its description,
so a file under the size limit compiles in time and memory that grow with its points, not with points x text."""

from __future__ import annotations

import tracemalloc

import hivex_dsl
from hivex_dsl.lang.expr import checker

TERMS = 10
POINTS = 1_000  # 10 seeds x 100 episode lengths


def _long_terms() -> dict:
    """``TERMS`` distinct expressions of about 1,950 characters each (the limit is 2,000)."""
    return {f"t{i}": {"expr": " + ".join([f"clip(alignment * 0.{i + 1}, 0, 1)"] * 60)} for i in range(TERMS)}


def _sweep(terms: dict) -> dict:
    return {"hivex": 1, "environment": "wind_farm_control", "terms": terms,
            "weights": {name: 0.001 for name in terms},
            "sweep": {"seeds.train": list(range(10)), "episode_length": list(range(10, 110))}}


def test_each_distinct_expression_is_checked_once_across_the_sweep(monkeypatch):
    import hivex_dsl.lang.expr as expr

    checked = []

    class Counting(checker.Checker):
        def __init__(self, *args):
            checked.append(args)
            super().__init__(*args)

    monkeypatch.setattr(expr, "Checker", Counting)
    expr._compiled.cache_clear()  # earlier tests may have compiled these texts
    terms = {name: {"expr": term["expr"] + " + 0 * performance"} for name, term in _long_terms().items()}
    points = hivex_dsl.compile_all(_sweep(terms))
    assert len(points) == POINTS
    # WFC's vocabulary is the same at every point of this sweep (performance's range depends on the episode
    # length only without drag), so each of the 10 texts is checked once, not once per point (10,000)
    assert len(checked) == TERMS
    first, last = points[0].expressions.terms, points[-1].expressions.terms
    assert all(a.expression is b.expression and a.contract.description is b.contract.description
               for a, b in zip(first, last))


def test_a_sweep_of_long_expressions_stays_within_its_memory_bound():
    """Before, 10,000 points of one 2,000-character term took 1.2 GB, and of 50 terms more than 3.6 GB: each
    point held its own compiled expressions and descriptions. 1,000 points x 10 terms now hold well under
    30 KB per point (the scenario models themselves)."""
    tracemalloc.start()
    try:
        points = hivex_dsl.compile_all(_sweep(_long_terms()))
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert len(points) == POINTS
    assert peak < 30_000 * POINTS, f"{peak / 1e6:.0f} MB"


def _refused(data: dict, monkeypatch) -> str:
    """The error compiling ``data`` raises; asserts no expression was compiled on the way."""
    import pytest

    import hivex_dsl.sim.reward.expressions as expressions

    compiled = []
    monkeypatch.setattr(expressions, "compile_expression", lambda *a, **k: compiled.append(a))
    with pytest.raises(hivex_dsl.ScenarioError) as refused:
        hivex_dsl.compile_all(data)
    assert compiled == []  # refused from the file's text, before any work
    return str(refused.value)


def test_a_sweep_of_too_many_expressions_is_refused_before_compiling_any(monkeypatch):
    # issue 54 item 13: 10,000 points x 460 expressions of 2,000 characters (a 0.9 MB file, within the size caps)
    # took 108 s and 4.7 GB to validate; 210 points of them, 83 s. Here 1,001 points x 100 short terms: 100,100.
    terms = {f"t{i}": {"expr": f"alignment * {i}"} for i in range(100)}
    data = _sweep(terms) | {"sweep": {"seeds.train": list(range(7)), "episode_length": list(range(10, 153))}}
    message = _refused(data, monkeypatch)
    assert "sweep makes 1,001 scenarios, each compiling the 100 expressions this file writes: 100,100 in all, " \
           "at most 100,000 are allowed" in message


def test_a_sweep_of_too_many_expression_characters_is_refused_before_compiling_any(monkeypatch):
    # 1,400 points x 10 terms of 1,803 characters: 25,242,000 characters (the 1,000 points above compile)
    data = _sweep(_long_terms()) | {"sweep": {"seeds.train": list(range(14)), "episode_length": list(range(10, 110))}}
    assert sum(len(term["expr"]) for term in _long_terms().values()) == 18_030
    message = _refused(data, monkeypatch)
    assert "sweep makes 1,400 scenarios, each compiling the 18,030 expression characters this file writes: " \
           "25,242,000 in all, at most 25,000,000 are allowed" in message
