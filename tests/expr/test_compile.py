"""compile_expression end to end: kinds, shapes, units, ranges and values of typical expressions."""

from __future__ import annotations

import pickle

import numpy as np
import pytest

from hivex_dsl.lang.expr import ExpressionError, Quantity, compile_expression

from .conftest import AGENTS, VOCABULARY


def compiled(source, **kw):
    kw.setdefault("agents", AGENTS)
    return compile_expression(source, VOCABULARY, **kw)


def test_a_proximity_reward_has_its_kind_shape_unit_and_range(states):
    now, before = states
    e = compiled("clip(1 - distance_m / 500{m}, 0, 1)")
    assert (e.kind, e.per, e.unit, e.low, e.high) == ("number", "agent", "1", 0.0, 1.0)
    assert e.reads == {"distance_m"} and e.reads_prev == frozenset()
    expected = np.minimum(np.maximum(1 - now["distance_m"] / 500, 0), 1)
    np.testing.assert_array_equal(e.evaluate(now, before), expected)


def test_a_per_world_value_broadcasts_over_the_agents_of_its_world(states):
    now, before = states
    e = compiled("speed_ms + wind_ms")
    assert e.per == "agent" and e.unit == "m/s" and (e.low, e.high) == (-5.0, 25.0)
    np.testing.assert_array_equal(e.evaluate(now, before), now["speed_ms"] + now["wind_ms"][:, None])


def test_reductions_give_one_value_per_world(states):
    now, before = states
    for name, expected in [("team_mean", now["water"].mean(axis=1)), ("team_min", now["water"].min(axis=1)),
                           ("team_max", now["water"].max(axis=1)), ("team_sum", now["water"].sum(axis=1))]:
        e = compiled(f"{name}(water)")
        assert e.per == "world"
        np.testing.assert_array_equal(e.evaluate(now, before), expected)
    assert compiled("team_sum(water)").high >= AGENTS and compiled("team_sum(water)").low == 0.0


def test_prev_and_delta_read_the_state_before_the_step(states):
    now, before = states
    e = compiled("delta(distance_m)")
    assert e.reads == {"distance_m"} and e.reads_prev == {"distance_m"}
    assert (e.low, e.high) == (-1000.0, 1000.0)
    np.testing.assert_array_equal(e.evaluate(now, before), now["distance_m"] - before["distance_m"])
    p = compiled("prev(water) * 2")
    assert p.reads == frozenset() and p.reads_prev == {"water"}
    np.testing.assert_array_equal(p.evaluate(now, before), before["water"] * 2)


def test_conditions_are_booleans_and_become_numbers_only_through_where(states):
    now, before = states
    e = compiled("dropped and not raining", want="bool")
    assert e.kind == "bool" and e.unit == ""
    result = e.evaluate(now, before)
    assert result.dtype == bool
    np.testing.assert_array_equal(result, now["dropped"] & ~now["raining"][:, None])
    n = compiled("where(0 < distance_m < 100, 1, 0)")
    d = now["distance_m"]
    np.testing.assert_array_equal(n.evaluate(now, before), np.where((d > 0) & (d < 100), 1.0, 0.0))


def test_a_bare_quantity_is_copied_not_aliased(states):
    now, before = states
    result = compiled("water").evaluate(now, before)
    np.testing.assert_array_equal(result, now["water"])
    assert not np.shares_memory(result, now["water"])


def test_want_and_per_are_enforced_over_the_whole_source():
    with pytest.raises(ExpressionError, match="expected a boolean") as error:
        compiled("water + 1", want="bool")
    assert (error.value.offset, error.value.length) == (0, 9)
    with pytest.raises(ExpressionError, match="per-world"):
        compiled("water", per="world")
    assert compiled("team_mean(water)", per="world").per == "world"
    with pytest.raises(ExpressionError, match="expected a per-agent value, got a per-world one"):
        compiled("wind_ms * 2", per="agent")
    assert compiled("wind_ms * water", per="agent").per == "agent"


def test_an_expression_pickles_by_its_source_and_vocabulary(states):
    now, before = states
    e = compiled("max(delta(distance_m), 0{m}) + team_sum(water) * 1{m}")
    again = pickle.loads(pickle.dumps(e))
    assert again == e
    np.testing.assert_array_equal(again.evaluate(now, before), e.evaluate(now, before))


def test_an_error_knows_its_line_and_column_in_a_multi_line_source():
    source = "clip(\n  water +\n  distnce_m, 0, 1)"
    with pytest.raises(ExpressionError) as caught:
        compiled(source)
    assert caught.value.line_column(source) == (3, 3)
    assert caught.value.pointer(source) == "  distnce_m, 0, 1)\n  ^^^^^^^^^"


@pytest.mark.parametrize("name", ["if", "a b", "__x", "1x", ""])
def test_a_quantity_needs_a_name_the_language_can_write(name):
    with pytest.raises(ValueError, match="must be an identifier"):
        Quantity(name, "agent", "number", "m", 0.0, 1.0, "")


@pytest.mark.parametrize("low, high", [(1.0, 0.0), (0.0, float("inf")), (float("nan"), 1.0), (-1e301, 0.0)])
def test_a_quantity_needs_a_finite_range(low, high):
    with pytest.raises(ValueError, match="not a finite interval"):
        Quantity("x", "agent", "number", "m", low, high, "")


def test_a_vocabulary_key_must_be_its_quantity_name_and_agents_positive():
    with pytest.raises(ValueError, match="holds quantity"):
        compile_expression("y", {"y": VOCABULARY["water"]})
    with pytest.raises(ValueError, match="agents must be a positive integer"):
        compile_expression("water", VOCABULARY, agents=0)
    with pytest.raises(ValueError, match="want must be"):
        compile_expression("water", VOCABULARY, want="float")
    with pytest.raises(ValueError, match="low and high must be numbers"):
        Quantity("x", "agent", "number", "m", "zero", 1.0, "")
    assert Quantity("x", "agent", "number", "m", 0, 1, "").high == 1.0 and isinstance(
        Quantity("x", "agent", "number", "m", 0, 1, "").low, float)


def test_a_reduction_combined_with_its_own_agents_broadcasts_back(states):
    now, before = states
    e = compiled("water - team_mean(water)")
    assert e.per == "agent" and e.unit == "1"
    np.testing.assert_array_equal(e.evaluate(now, before), now["water"] - now["water"].mean(axis=1)[:, None])
    world = compiled("where(raining, team_max(distance_m), prev(distance_m))")
    expected = np.where(now["raining"][:, None], now["distance_m"].max(axis=1)[:, None], before["distance_m"])
    np.testing.assert_array_equal(world.evaluate(now, before), expected)


def test_input_problems_names_each_input_that_voids_the_guarantees(states):
    from hivex_dsl.lang.expr import input_problems

    now, _ = states
    assert input_problems(VOCABULARY, now) == []
    bad = dict(now, water=now["water"] + 2.0, wind_ms=now["wind_ms"].astype(np.float32),
               dropped=now["dropped"][:2], burning=np.full(4, np.nan), extra=now["water"])
    problems = input_problems(VOCABULARY, bad)
    assert problems[0].startswith("water: values in [") and problems[0].endswith("outside its range [0, 1]")
    assert "wind_ms: expected float64 with 1 axes, got float32 with 1 axes" in problems
    assert "dropped: shape (2, 3) disagrees with the other quantities" in problems
    assert any(p.startswith("burning: values in [nan") for p in problems)
    assert "extra: not in the vocabulary" in problems


def test_true_and_false_are_the_boolean_constants_the_grammar_names(states):
    """They were 'unknown quantity' though the grammar lists them beside numbers and names."""
    now, before = states
    e = compiled("where(water > 0.5, true, false)", want="bool")
    np.testing.assert_array_equal(e.evaluate(now, before), now["water"] > 0.5)
    e = compiled("where(false or water > 0.5, 1, 0)")
    np.testing.assert_array_equal(e.evaluate(now, before), np.where(now["water"] > 0.5, 1.0, 0.0))
    assert (e.low, e.high) == (0.0, 1.0)
