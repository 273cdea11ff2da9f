"""Sound interval arithmetic in float64, as the evaluation computes it.

Each rule gives a closed ``(low, high)`` that holds every value NumPy computes for operands inside
their intervals. For ``+ - * /``, min, max, abs, sqrt and the comparisons this is exact: IEEE
rounding is monotone, so the rounded corners bound the rounded results. Functions whose NumPy
implementation is not guaranteed correctly rounded (exp, log, powers other than 2) and the
reductions over agents (whose summation order is NumPy's) are widened outwards a little.
A rule raises :class:`Refused` when an operand's interval allows a non-finite or undefined result.
"""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np

Interval = tuple[float, float]
LIMIT = 1e300  # the largest magnitude an expression's value may reach
EXP_LIMIT = math.log(LIMIT)
_EPS = float(np.finfo(np.float64).eps)
_ULPS = 4  # outward widening of results of functions that are not correctly rounded


class Refused(ValueError):
    """An operation whose operands' intervals allow division by zero, a domain error or overflow."""


def checked(interval: Interval, what: str) -> Interval:
    low, high = interval
    if not (-LIMIT <= low <= high <= LIMIT):
        raise Refused(f"{what} can overflow: its value can reach {_far(interval):g} (at most {LIMIT:g})")
    return interval


def _far(interval: Interval) -> float:
    return max(abs(interval[0]), abs(interval[1])) if all(map(math.isfinite, interval)) else math.inf


def widen(interval: Interval, ulps: int = _ULPS) -> Interval:
    """``interval`` a few ulps wider at each end, never across zero: the functions widened here
    (exp, log, powers) get the sign of their result exactly right even where the last bits are off."""
    low, high = interval
    for _ in range(ulps):
        low, high = float(np.nextafter(low, -np.inf)), float(np.nextafter(high, np.inf))
    return (max(low, 0.0) if interval[0] >= 0.0 else low), (min(high, 0.0) if interval[1] <= 0.0 else high)


def add(a: Interval, b: Interval) -> Interval:
    return a[0] + b[0], a[1] + b[1]


def subtract(a: Interval, b: Interval) -> Interval:
    return a[0] - b[1], a[1] - b[0]


def multiply(a: Interval, b: Interval) -> Interval:
    corners = (a[0] * b[0], a[0] * b[1], a[1] * b[0], a[1] * b[1])
    return min(corners), max(corners)


def divide(a: Interval, b: Interval) -> Interval:
    if b[0] <= 0.0 <= b[1]:
        raise Refused(f"'/' can divide by zero: the divisor ranges over {show(b)}; "
                      "keep it away from 0, e.g. with max(x, 0.001)")
    corners = (a[0] / b[0], a[0] / b[1], a[1] / b[0], a[1] / b[1])
    return min(corners), max(corners)


def negate(a: Interval) -> Interval:
    return -a[1], -a[0]


def absolute(a: Interval) -> Interval:
    if a[0] >= 0.0:
        return a
    if a[1] <= 0.0:
        return -a[1], -a[0]
    return 0.0, max(-a[0], a[1])


def minimum(a: Interval, b: Interval) -> Interval:
    return min(a[0], b[0]), min(a[1], b[1])


def maximum(a: Interval, b: Interval) -> Interval:
    return max(a[0], b[0]), max(a[1], b[1])


def hull(a: Interval, b: Interval) -> Interval:
    return min(a[0], b[0]), max(a[1], b[1])


def exp(a: Interval) -> Interval:
    if a[1] > EXP_LIMIT:
        raise Refused(f"exp can overflow: its argument reaches {a[1]:g} (at most {EXP_LIMIT:.4g})")
    low, high = widen((float(np.exp(a[0])), float(np.exp(a[1]))))
    return _around_one((low, high), a[0] >= 0.0, a[1] <= 0.0)


def _around_one(interval: Interval, at_least_one: bool, at_most_one: bool) -> Interval:
    """A widened range kept on its side of 1 where the function is 1 exactly at the boundary
    (exp(0), x ** n at x = 1) and monotone, so rounding cannot carry it across."""
    low, high = interval
    return (max(low, 1.0) if at_least_one else low), (min(high, 1.0) if at_most_one else high)


def log(a: Interval) -> Interval:
    if a[0] <= 0.0:
        raise Refused(f"log needs a positive argument, but it ranges over {show(a)}")
    return widen((float(np.log(a[0])), float(np.log(a[1]))))


def sqrt(a: Interval) -> Interval:
    if a[0] < 0.0:
        raise Refused(f"sqrt needs a non-negative argument, but it ranges over {show(a)}")
    return float(np.sqrt(a[0])), float(np.sqrt(a[1]))


def power(a: Interval, n: float) -> Interval:
    """``x ** n`` for a constant exponent ``n``."""
    if n == 0:
        return 1.0, 1.0
    if n == 1:
        return a
    if n != int(n):
        if a[0] < 0.0 or (n < 0 and a[0] == 0.0):
            need = "positive" if n < 0 else "non-negative"
            raise Refused(f"'**' with a fractional exponent needs a {need} base, but it ranges over {show(a)}")
        ends = (_pow(a[0], n), _pow(a[1], n))
        return _power_around_one(widen((min(ends), max(ends))), a, n)
    if n < 0 and a[0] <= 0.0 <= a[1]:
        raise Refused(f"'**' with a negative exponent can divide by zero: the base ranges over {show(a)}")
    magnitude = absolute(a) if n % 2 == 0 else a
    ends = (_pow(magnitude[0], n), _pow(magnitude[1], n))
    interval = (min(ends), max(ends))
    return interval if n == 2 else _power_around_one(widen(interval), magnitude, n)


def _power_around_one(interval: Interval, base: Interval, n: float) -> Interval:
    if base[0] < 0.0:
        return interval
    below, above = base[1] <= 1.0, base[0] >= 1.0  # base within [0, 1], or at least 1
    return _around_one(interval, above if n > 0 else below, below if n > 0 else above)


def _pow(x: float, n: float) -> float:
    try:
        return float(x) ** n
    except (OverflowError, ZeroDivisionError):
        return math.inf


def team_sum(a: Interval, agents: int) -> Interval:
    """A sum over 1..``agents`` values in ``a``, whatever NumPy's summation order.

    Rounding is monotone, so a computed sum is at most the computed sum of as many copies of the
    high end: exactly ``k * high`` when every partial sum ``j * high`` is a float64 (then any order
    is exact), else within a rounding allowance of it. The same holds for the low end.
    """
    low = a[0] if a[0] >= 0.0 else _copies_sum(a[0], agents, -1.0)
    high = a[1] if a[1] <= 0.0 else _copies_sum(a[1], agents, 1.0)
    return low, high


def team_mean(a: Interval, agents: int) -> Interval:
    """A mean over 1..``agents`` values in ``a``: the sum's bound divided back, see :func:`team_sum`."""
    low, high = (_copies_mean(end, agents, side) for end, side in ((a[0], -1.0), (a[1], 1.0)))
    return (max(low, 0.0) if a[0] >= 0.0 else low), (min(high, 0.0) if a[1] <= 0.0 else high)


def _copies_sum(x: float, agents: int, side: float) -> float:
    if _exact_multiples(x, agents):
        return x * agents
    return x * agents + side * 2.0 * agents * agents * _EPS * abs(x)


def _copies_mean(x: float, agents: int, side: float) -> float:
    if _exact_multiples(x, agents):
        return x
    return x + side * 2.0 * (agents + 1) * _EPS * abs(x)


def _exact_multiples(x: float, count: int) -> bool:
    """Whether ``j * x`` is a float64 for every j up to ``count``, so any sum of copies is exact."""
    exact = Fraction(x)
    return all(Fraction(float(exact * j)) == exact * j for j in range(2, count + 1))


def show(a: Interval) -> str:
    return f"[{a[0]:g}, {a[1]:g}]"
