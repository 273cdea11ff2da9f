"""What a where() condition says about the quantities it compares, to narrow its branches' ranges.

``where(theta <= 90, theta / 90, 2 - theta / 90)`` is computed over every theta (both branches
are), but a value of the first branch is only *chosen* where theta <= 90, so the result's range is
the hull of ``theta / 90`` over theta in [low, 90] and ``2 - theta / 90`` over [90, high]: [0, 1]
rather than [0, 2]. Conditions understood: a quantity compared with a written number (either
side, chains included), and ``and``, ``or`` and ``not`` of those; anything else constrains nothing.
Regions are closed (``x < 90`` gives x <= 90), which only ever widens them, so they stay sound.
"""

from __future__ import annotations

import math
from typing import Callable

from .intervals import Interval
from .syntax import Binary, Compare, Name, Node, Unary, written_number

Key = tuple[str, bool]  # (quantity, read before the step)
Region = dict[Key, Interval]  # ranges of the quantities where a condition holds; absent: unconstrained

_EVERYTHING = (-math.inf, math.inf)
_FLIPPED = {"<": ">", "<=": ">=", ">": "<", ">=": "<=", "==": "==", "!=": "!="}
_NEGATED = {"<": ">=", "<=": ">", ">": "<=", ">=": "<", "==": "!=", "!=": "=="}


def regions(condition: Node, before: bool, is_number: Callable[[str], bool]) -> tuple[Region, Region]:
    """(where ``condition`` holds, where it does not), as constraints on the quantities it reads."""
    if isinstance(condition, Unary) and condition.op.text == "not":
        held, failed = regions(condition.operand, before, is_number)
        return failed, held
    if isinstance(condition, Binary) and condition.op.text in ("and", "or"):
        (held_a, failed_a), (held_b, failed_b) = (regions(side, before, is_number)
                                                  for side in (condition.left, condition.right))
        if condition.op.text == "and":
            return both(held_a, held_b), _either(failed_a, failed_b)
        return _either(held_a, held_b), both(failed_a, failed_b)
    if isinstance(condition, Compare):
        pairs = [_compared(condition.operands[i], op.text, condition.operands[i + 1], before, is_number)
                 for i, op in enumerate(condition.ops)]
        held: Region = {}
        for key, op, value in filter(None, pairs):
            held = both(held, {key: _satisfying(op, value)})
        failed = {}
        if len(pairs) == 1 and pairs[0] is not None:
            key, op, value = pairs[0]
            failed = {key: _satisfying(_NEGATED[op], value)}
        return held, failed
    return {}, {}


def within(region: Region, key: Key, interval: Interval) -> Interval:
    """``interval`` cut to what ``region`` allows for ``key`` (empty when low > high)."""
    allowed = region.get(key, _EVERYTHING)
    return max(interval[0], allowed[0]), min(interval[1], allowed[1])


def _compared(left: Node, op: str, right: Node, before: bool, is_number):
    """(key, op, number) for ``quantity op number``, flipped for ``number op quantity``; else None."""
    if isinstance(right, Name) and not isinstance(left, Name):
        left, op, right = right, _FLIPPED[op], left
    value = written_number(right)
    if isinstance(left, Name) and value is not None and is_number(left.name):
        return (left.name, before), op, value
    return None


def _satisfying(op: str, value: float) -> Interval:
    if op in ("<", "<="):
        return -math.inf, value
    if op in (">", ">="):
        return value, math.inf
    return (value, value) if op == "==" else _EVERYTHING


def both(a: Region, b: Region) -> Region:
    joined = dict(a)
    for key, (low, high) in b.items():
        known = joined.get(key, _EVERYTHING)
        joined[key] = max(known[0], low), min(known[1], high)
    return joined


def _either(a: Region, b: Region) -> Region:
    return {key: (min(a[key][0], b[key][0]), max(a[key][1], b[key][1])) for key in a.keys() & b.keys()}
