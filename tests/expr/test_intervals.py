"""Interval inference: hand-computed ranges of typical expressions, and the rounding cases where a
naive bound would be exceeded by the computed values."""

from __future__ import annotations

import numpy as np
import pytest

from hivex_dsl.lang.expr import Quantity, compile_expression

from .conftest import AGENTS, VOCABULARY


@pytest.mark.parametrize("source, low, high", [
    ("distance_m / 1000", 0.0, 1.0),
    ("-speed_ms", -5.0, 5.0),
    ("speed_ms * wind_ms", -100.0, 100.0),
    ("speed_ms * speed_ms", 0.0, 25.0),  # the same subtree twice: a square
    ("(speed_ms - 1) * (speed_ms -1)", 0.0, 36.0),
    ("speed_ms * prev(speed_ms)", -25.0, 25.0),  # not the same values
    ("speed_ms ** 2", 0.0, 25.0),
    ("abs(speed_ms)", 0.0, 5.0),
    ("abs(speed_ms - 6)", 1.0, 11.0),
    ("speed_ms - wind_ms", -25.0, 5.0),
    ("1 / (water + 1)", 0.5, 1.0),
    ("(speed_ms - 10) / (water + 1)", -15.0, -2.5),
    ("min(speed_ms, wind_ms)", -5.0, 5.0),
    ("max(speed_ms, wind_ms)", 0.0, 20.0),
    ("clip(speed_ms, -1, 2)", -1.0, 2.0),
    ("clip(speed_ms, water * 1{m/s}, 2)", 0.0, 2.0),
    ("where(dropped, wind_ms, speed_ms)", -5.0, 20.0),
    ("sqrt(distance_m / 1{m})", 0.0, float(np.sqrt(1000.0))),
    ("delta(water)", -1.0, 1.0),
    ("team_min(speed_ms)", -5.0, 5.0),
    ("water ** 0", 1.0, 1.0),
])
def test_inferred_ranges_match_hand_computed_ones(source, low, high):
    e = compile_expression(source, VOCABULARY, agents=AGENTS, per=None)
    assert (e.low, e.high) == (low, high)


@pytest.mark.parametrize("source, low, high", [
    ("exp(-water)", np.exp(-1.0), 1.0),
    ("log(water + 1)", 0.0, np.log(2.0)),
    ("water ** 3", 0.0, 1.0),
    ("team_mean(water)", 0.0, 1.0),
    ("team_sum(water)", 0.0, 3.0),
    ("team_sum(speed_ms)", -15.0, 15.0),
])
def test_transcendental_and_reduced_ranges_are_widened_only_a_little(source, low, high):
    e = compile_expression(source, VOCABULARY, agents=AGENTS)
    assert e.low <= low and e.high >= high
    assert e.low == pytest.approx(low, abs=1e-12) and e.high == pytest.approx(high, abs=1e-12)
    if low >= 0.0:
        assert e.low >= 0.0, "a range that cannot go negative is not widened below zero"


@pytest.mark.parametrize("source, low, high", [
    ("team_mean(water)", 0.0, 1.0),  # 1 + 1 + 1 is exact in any order: no allowance needed
    ("team_sum(water)", 0.0, 3.0),
    ("team_sum(speed_ms)", -15.0, 15.0),
    ("exp(-water)", pytest.approx(np.exp(-1.0)), 1.0),  # exp(0) is 1 exactly
    ("exp(water)", 1.0, pytest.approx(np.exp(1.0))),
    ("water ** 3", 0.0, 1.0),  # 1 ** 3 is 1 exactly, and x ** 3 < 1 below it
    ("water ** 1.5", 0.0, 1.0),
    ("(water + 1) ** -1", pytest.approx(0.5), 1.0),
])
def test_ranges_that_reach_an_exact_value_are_not_widened_past_it(source, low, high):
    e = compile_expression(source, VOCABULARY, agents=AGENTS)
    assert (e.low, e.high) == (low, high)  # exact where a plain number is given, else approximately


@pytest.mark.parametrize("source, low, high", [
    ("where(heading_deg <= 90, heading_deg / 90, 2 - heading_deg / 90)", -2.0, 1.0),  # heading reaches 360
    ("where(heading_deg <= 90, heading_deg / 90, 4 - heading_deg / 90)", 0.0, 3.0),
    ("where(speed_ms > 0, speed_ms, 0)", 0.0, 5.0),
    ("where(speed_ms < 0, -speed_ms, speed_ms)", 0.0, 5.0),
    ("where(-1 <= speed_ms <= 2, speed_ms, 0)", -1.0, 2.0),
    ("where(speed_ms > 1 and dropped, speed_ms, 1)", 1.0, 5.0),
    ("where(not (speed_ms > 1), speed_ms, 1)", -5.0, 1.0),
    ("where(speed_ms < -1 or speed_ms > 1, abs(speed_ms), 1)", 0.0, 5.0),  # one interval per quantity: the hull
    ("where(speed_ms > 10, speed_ms * 100, 0)", 0.0, 0.0),  # the first branch is never chosen
    ("where(speed_ms > 0, team_max(speed_ms), 0)", -5.0, 5.0),  # other agents' speeds are not narrowed
    ("where(prev(speed_ms) > 0, speed_ms, 0)", -5.0, 5.0),  # a condition before the step says nothing after it
    ("prev(where(speed_ms > 0, speed_ms, 0))", 0.0, 5.0),
])
def test_a_where_branch_ranges_only_over_where_it_is_chosen(source, low, high):
    e = compile_expression(source, VOCABULARY, agents=AGENTS)
    assert (e.low, e.high) == (low, high)


def test_a_mean_of_equal_values_can_round_above_them_and_stays_inside_its_range():
    vocabulary = {"x": Quantity("x", "agent", "number", "1", 0.0, 0.1, "")}
    now = {"x": np.full((1, 3), 0.1)}
    value = compile_expression("team_mean(x)", vocabulary, agents=3).evaluate(now, now)
    assert value[0] > 0.1  # (0.1 + 0.1 + 0.1) / 3 rounds up
    assert value[0] <= compile_expression("team_mean(x)", vocabulary, agents=3).high


def test_team_sum_covers_every_agent_count_up_to_the_given_one():
    vocabulary = {"x": Quantity("x", "agent", "number", "1", 0.1, 1.0, "")}
    e = compile_expression("team_sum(x)", vocabulary, agents=4)
    assert e.low == 0.1 and 4.0 <= e.high < 4.0 + 1e-12
    for agents in (1, 2, 4):
        value = e.evaluate({"x": np.full((1, agents), 0.1)}, {})
        assert e.low <= value[0] <= e.high


def test_an_interval_touching_zero_is_a_refused_divisor_but_a_positive_one_is_not():
    positive = {"x": Quantity("x", "agent", "number", "1", 1e-3, 1.0, "")}
    assert compile_expression("1 / x", positive).high == 1000.0
    assert compile_expression("1 / max(x, 0.5)", positive).high == 2.0


def test_nested_wheres_refine_a_bounded_number_of_times():
    # every where() re-checks its branches to narrow them; unbounded, 40 levels would take 2**40 checks
    source = "water"
    for level in range(40):
        source = f"where(speed_ms > {level % 5 - 2}, {source}, water)"
    e = compile_expression(source, VOCABULARY)
    assert (e.low, e.high) == (0.0, 1.0)
