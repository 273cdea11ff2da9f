"""The evaluation plan: a checked tree fused into nested closures of NumPy calls.

An operand is one of ``("c", value)`` (a constant, folded at compile time), ``("n", name)`` (a
quantity after the step), ``("p", name)`` (a quantity before the step) or ``("f", fn)`` with
``fn(now, before) -> array``. Combinators specialise on their operands' modes so that a name or a
constant operand costs no Python call of its own: ``x * 2`` runs as one closure that does
``multiply(now["x"], c)`` and ``delta(x)`` as ``subtract(now["x"], before["x"])``. Operations run
exactly as written, in the written order; nothing is reassociated, so a formula re-expressed here
gives the bits of the same NumPy calls written by hand.
Number constants are 0-d float64 arrays, which promote like a Python float on float64 operands
and skip NumPy's per-call resolution of Python scalars (see :mod:`hivex_dsl.base.numeric`).
"""

from __future__ import annotations

from typing import Any, Callable

import numpy as np

from ...base.numeric import constant

Op = tuple[str, Any]
Fn = Callable[[Any, Any], Any]


def const(value) -> Op:
    if isinstance(value, (bool, np.bool_)):
        return ("c", np.bool_(value))
    if isinstance(value, (int, float, np.floating)) or np.ndim(value) == 0:
        return ("c", constant(float(value)))
    return ("c", value)


def read(name: str, before: bool) -> Op:
    return ("p" if before else "n", name)


def function(op: Op) -> Fn:
    """``op`` as a closure ``fn(now, before)``."""
    mode, value = op
    if mode == "f":
        return value
    if mode == "n":
        return lambda now, before: now[value]
    if mode == "p":
        return lambda now, before: before[value]
    return lambda now, before: value


def result(op: Op) -> Fn:
    """The closure of a whole expression; a bare read is copied so the caller never aliases its input."""
    mode, value = op
    if mode == "n":
        return lambda now, before: now[value].copy()
    if mode == "p":
        return lambda now, before: before[value].copy()
    return function(op)


def expand(op: Op) -> Op:
    """A per-world operand, (batch,), as (batch, 1) to broadcast over the agents of its world."""
    mode, value = op
    if mode == "c":
        return op
    if mode == "n":
        return ("f", lambda now, before: now[value][:, None])
    if mode == "p":
        return ("f", lambda now, before: before[value][:, None])
    return ("f", lambda now, before: value(now, before)[:, None])


def apply1(f: Callable, a: Op) -> Op:
    mode, x = a
    if mode == "c":
        return const(f(x))
    if mode == "n":
        return ("f", lambda now, before: f(now[x]))
    if mode == "p":
        return ("f", lambda now, before: f(before[x]))
    return ("f", lambda now, before: f(x(now, before)))


def apply2(f: Callable, a: Op, b: Op) -> Op:
    (ma, x), (mb, y) = a, b
    if ma == "c" and mb == "c":
        return const(f(x, y))
    return ("f", _BINARY[ma, mb](f, x, y))


_BINARY: dict[tuple[str, str], Callable[[Callable, Any, Any], Fn]] = {
    ("n", "c"): lambda f, x, y: lambda now, before: f(now[x], y),
    ("c", "n"): lambda f, x, y: lambda now, before: f(x, now[y]),
    ("n", "n"): lambda f, x, y: lambda now, before: f(now[x], now[y]),
    ("f", "c"): lambda f, x, y: lambda now, before: f(x(now, before), y),
    ("c", "f"): lambda f, x, y: lambda now, before: f(x, y(now, before)),
    ("f", "n"): lambda f, x, y: lambda now, before: f(x(now, before), now[y]),
    ("n", "f"): lambda f, x, y: lambda now, before: f(now[x], y(now, before)),
    ("f", "f"): lambda f, x, y: lambda now, before: f(x(now, before), y(now, before)),
    ("p", "c"): lambda f, x, y: lambda now, before: f(before[x], y),
    ("c", "p"): lambda f, x, y: lambda now, before: f(x, before[y]),
    ("n", "p"): lambda f, x, y: lambda now, before: f(now[x], before[y]),
    ("p", "n"): lambda f, x, y: lambda now, before: f(before[x], now[y]),
    ("p", "p"): lambda f, x, y: lambda now, before: f(before[x], before[y]),
    ("f", "p"): lambda f, x, y: lambda now, before: f(x(now, before), before[y]),
    ("p", "f"): lambda f, x, y: lambda now, before: f(before[x], y(now, before)),
}


def select(condition: Op, a: Op, b: Op) -> Op:
    """``np.where(condition, a, b)``; both branches are evaluated, as NumPy does."""
    c = function(condition)
    if a[0] == "c" and b[0] == "c":
        x, y = a[1], b[1]
        return ("f", lambda now, before: np.where(c(now, before), x, y))
    fa, fb = function(a), function(b)
    return ("f", lambda now, before: np.where(c(now, before), fa(now, before), fb(now, before)))


def clip(x: Op, low: Op, high: Op) -> Op:
    """``minimum(maximum(x, low), high)``, in one closure when both bounds are constants."""
    if low[0] != "c" or high[0] != "c" or x[0] == "c":
        return apply2(np.minimum, apply2(np.maximum, x, low), high)
    lo, hi, maximum, minimum = low[1], high[1], np.maximum, np.minimum
    if x[0] == "n":
        name = x[1]
        return ("f", lambda now, before: minimum(maximum(now[name], lo), hi))
    fn = function(x)
    return ("f", lambda now, before: minimum(maximum(fn(now, before), lo), hi))


def reduce(f: Callable, a: Op) -> Op:
    """``f.reduce`` over the agent axis of a (batch, agents) operand."""
    reduce_ = f.reduce
    if a[0] == "n":
        name = a[1]
        return ("f", lambda now, before: reduce_(now[name], 1))
    fn = function(a)
    return ("f", lambda now, before: reduce_(fn(now, before), 1))


def mean(a: Op) -> Op:
    """The mean over the agent axis: the bits of ``x.mean(axis=1)`` (a sum, then one division by the count)."""
    add = np.add.reduce
    if a[0] == "n":
        name = a[1]
        return ("f", lambda now, before: add(now[name], 1) / now[name].shape[1])
    fn = function(a)
    return ("f", lambda now, before: add(x := fn(now, before), 1) / x.shape[1])
