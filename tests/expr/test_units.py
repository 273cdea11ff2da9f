"""The unit algebra: canonical forms, products, quotients, powers; and how expressions use it."""

from __future__ import annotations

from fractions import Fraction

import pytest

from hivex_dsl.lang.expr import compile_expression
from hivex_dsl.lang.expr.units import divide, format_unit, multiply, parse_unit, power

from .conftest import VOCABULARY


@pytest.mark.parametrize("text, canonical", [
    ("m", "m"), ("m/s", "m/s"), ("m/s^2", "m/s^2"), ("s^-2*m", "m/s^2"), ("kg*m/s^2", "kg*m/s^2"),
    ("m*kg/s/s", "kg*m/s^2"), ("1/s", "1/s"), ("s^-1", "1/s"), ("1", "1"), ("", "1"), ("m/m", "1"),
    ("m * m", "m^2"), ("%", "%"), ("deg", "deg"), ("°C", "°C"), ("trees/km^2", "trees/km^2"),
])
def test_units_have_one_canonical_text(text, canonical):
    assert format_unit(parse_unit(text)) == canonical
    assert format_unit(parse_unit(canonical)) == canonical


@pytest.mark.parametrize("bad", ["m/", "*m", "m^", "m^x", "2m", "m s", "m^1.5"])
def test_malformed_units_are_refused(bad):
    with pytest.raises(ValueError, match="malformed unit"):
        parse_unit(bad)


def test_products_quotients_and_powers_combine_exponents():
    m, s = parse_unit("m"), parse_unit("s")
    assert format_unit(multiply(m, m)) == "m^2"
    assert format_unit(divide(m, multiply(s, s))) == "m/s^2"
    assert format_unit(divide(m, m)) == "1"
    assert format_unit(power(parse_unit("m^2/s^4"), Fraction(1, 2))) == "m/s^2"
    with pytest.raises(ValueError, match="no whole unit"):
        power(m, Fraction(1, 2))


@pytest.mark.parametrize("source, unit", [
    ("distance_m * 2", "m"),
    ("2 * distance_m", "m"),
    ("distance_m / 2", "m"),
    ("2 / (speed_ms ** 2 + 1{m^2/s^2})", "s^2/m^2"),
    ("distance_m / 10{s}", "m/s"),
    ("distance_m / (speed_ms ** 2 + 1)", "s^2/m"),
    ("distance_m * speed_ms", "m^2/s"),
    ("sqrt(distance_m * distance_m + 1)", "m"),
    ("distance_m - 1", "m"),
    ("max(distance_m, 50)", "m"),
    ("clip(speed_ms, -1, wind_ms)", "m/s"),
    ("where(dropped, heading_deg, 0)", "deg"),
    ("distance_m / 100{m}", "1"),
    ("exp(-distance_m / 100{m})", "1"),
    ("log(1 + water)", "1"),
    ("abs(speed_ms) ** 3", "m^3/s^3"),
    ("delta(heading_deg)", "deg"),
    ("team_mean(speed_ms) - wind_ms", "m/s"),
    ("water ** 0.5", "1"),
])
def test_expressions_carry_the_unit_of_their_formula(source, unit):
    assert compile_expression(source, VOCABULARY).unit == unit


def test_a_plain_number_adapts_to_the_other_side_of_a_comparison():
    assert compile_expression("distance_m < 100", VOCABULARY, want="bool").unit == ""
    assert compile_expression("100 < distance_m", VOCABULARY, want="bool").reads == {"distance_m"}
