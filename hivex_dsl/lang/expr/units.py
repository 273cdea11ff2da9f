"""A small unit algebra: products and quotients of base symbols with integer exponents.

A unit is a sorted tuple of ``(symbol, exponent)`` pairs with non-zero exponents; ``()`` is
dimensionless. Its canonical text puts the positive exponents first, joined by ``*``, then every
negative one after its own ``/``: ``m``, ``m/s``, ``m/s^2``, ``kg*m/s^2``, ``1/s``, ``1``. The same
grammar is accepted on input (``*``, ``/`` and ``^`` with an optional minus sign, left to right),
so ``format_unit(parse_unit(text))`` is the canonical form of ``text``.
"""

from __future__ import annotations

import re
from fractions import Fraction

Unit = tuple[tuple[str, int], ...]

DIMENSIONLESS: Unit = ()
_FACTOR = re.compile(r"\s*(?:(1)|((?:[^\W\d_]|[%°])[\w%°]*)(?:\^(-?\d+))?)\s*")


def parse_unit(text: str) -> Unit:
    """The unit written as ``text`` (``""`` and ``"1"`` are dimensionless); ValueError if malformed."""
    if not text.strip():
        return DIMENSIONLESS
    exponents: dict[str, int] = {}
    position, sign = 0, 1
    while True:
        match = _FACTOR.match(text, position)
        if not match or match.end() == position:
            raise ValueError(f"malformed unit {text!r} at character {position}")
        if match.group(2):
            power = int(match.group(3) or 1)
            exponents[match.group(2)] = exponents.get(match.group(2), 0) + sign * power
        position = match.end()
        if position == len(text):
            return _normal(exponents)
        if text[position] not in "*/":
            raise ValueError(f"malformed unit {text!r} at character {position}")
        sign = 1 if text[position] == "*" else -1
        position += 1


def format_unit(unit: Unit) -> str:
    """The canonical text of ``unit`` (see the module docstring)."""
    if not unit:
        return "1"
    up = "*".join(_power(symbol, e) for symbol, e in unit if e > 0) or "1"
    return up + "".join("/" + _power(symbol, -e) for symbol, e in unit if e < 0)


def multiply(a: Unit, b: Unit) -> Unit:
    exponents = dict(a)
    for symbol, e in b:
        exponents[symbol] = exponents.get(symbol, 0) + e
    return _normal(exponents)


def divide(a: Unit, b: Unit) -> Unit:
    return multiply(a, power(b, -1))


def power(unit: Unit, exponent: Fraction | int) -> Unit:
    """``unit`` raised to ``exponent``; ValueError when an exponent would not stay a whole number."""
    raised = {}
    for symbol, e in unit:
        value = Fraction(e) * Fraction(exponent)
        if value.denominator != 1:
            raise ValueError(f"{format_unit(unit)} to the power {exponent} has no whole unit")
        raised[symbol] = int(value)
    return _normal(raised)


def _normal(exponents: dict[str, int]) -> Unit:
    return tuple(sorted((symbol, e) for symbol, e in exponents.items() if e != 0))


def _power(symbol: str, e: int) -> str:
    return symbol if e == 1 else f"{symbol}^{e}"
