"""Reading any action input as a NumPy array: the one conversion behind every adapter's action checks.

``np.asarray`` alone does two wrong things with actions:

- it raises whatever a foreign object's conversion raises: torch's ``RuntimeError`` for a tensor that
  requires grad, its ``TypeError`` for a tensor on a GPU (or the meta device), anything at all from a
  user's ``__array__``;
- it promotes a boolean among numbers to a number: ``[True, 0, 0]`` becomes ``[1, 0, 0]``, which a
  Discrete space reads as action 1.

:func:`as_array` does neither: it raises only :class:`Unreadable` (whose message says what the input
is), and it hands back nested lists that hide a boolean as an object array, booleans intact, which
every check refuses by its dtype and whose culprit it can then name.

A torch tensor that requires grad is refused, not detached: a policy's output still attached to its
graph is almost always a mistake (acting should run under ``torch.no_grad()``), and detaching in
secret would hide it. The message says to call ``.detach()``. A tensor without grad on the CPU (and
any other object NumPy reads, such as a JAX array) is read as NumPy reads it.
"""

from __future__ import annotations

import operator
from itertools import chain
from typing import Any

import numpy as np

NUMBER_KINDS = "iuf"  # the dtype kinds of actions: booleans, strings, complex numbers and objects are refused
_SEQUENCES = frozenset({list, tuple})
_PLAIN_NUMBERS = frozenset({int, float})
_BOOLEANS = frozenset({bool, np.bool_})
_dtype = operator.attrgetter("dtype")


class Unreadable(ValueError):
    """An input that cannot be read as an array at all; the message says what it is, e.g.
    ``ragged ([[0.0], 0.0])`` or ``a tensor that requires grad; call .detach() on it first``."""


def as_array(value: Any) -> np.ndarray:
    """Any action input -> an ndarray shaped as NumPy reads it (an ndarray itself is returned as it is).

    Nested lists and tuples that hold a boolean among numbers come back as an object array (the
    booleans kept as booleans), so that a dtype check refuses them. Raises :class:`Unreadable` for a
    tensor that requires grad, a ragged nesting, and any input whose conversion raises.
    """
    if type(value) is np.ndarray:
        return value
    try:
        if getattr(value, "requires_grad", False) is True:
            raise Unreadable("a tensor that requires grad; call .detach() on it first "
                             "(acting needs no gradient: run the policy under torch.no_grad())")
        array = np.asarray(value)
        if array.dtype.kind in NUMBER_KINDS and type(value) in _SEQUENCES and holds_a_boolean(value):
            return np.asarray(value, dtype=object)
        return array
    except Unreadable:
        raise
    except Exception as exc:  # a foreign object's conversion may raise anything: none of it is the caller's bug
        raise Unreadable(_why_unreadable(value, exc)) from None


def holds_a_boolean(value: Any) -> bool:
    """Whether ``value`` (a scalar, an array or nested lists and tuples of them) holds a boolean: a
    Python or NumPy bool, or an array or tensor of a boolean dtype.

    One ``set(map(...))`` pass per nesting level; items are visited one by one only when a level mixes
    lists with other values (then the input is ragged or mixed, and about to be refused anyway).
    """
    leaves = _leaves([value])
    types = set(map(type, leaves))
    if types <= _PLAIN_NUMBERS:
        return False
    if not types.isdisjoint(_BOOLEANS):
        return True
    if all(issubclass(kind, np.generic) for kind in types):  # NumPy scalars, none of them np.bool_
        return False
    arrays = leaves if types.isdisjoint(_PLAIN_NUMBERS) else [x for x in leaves if type(x) not in _PLAIN_NUMBERS]
    try:
        dtypes = set(map(_dtype, arrays))
    except AttributeError:  # something without a dtype: a number NumPy reads, or an object it refuses
        dtypes = {getattr(x, "dtype", None) for x in arrays}
    return any(map(_is_boolean_dtype, dtypes))


def _is_boolean_dtype(dtype: Any) -> bool:
    """NumPy's (and JAX's) bool dtype, or torch.bool."""
    return dtype.kind == "b" if isinstance(dtype, np.dtype) else str(dtype).endswith(".bool")


def _leaves(level: list) -> list:
    """The items of nested lists and tuples that are neither, level by level."""
    while level:
        types = set(map(type, level))
        if types <= _SEQUENCES:
            level = list(chain.from_iterable(level))
        elif types.isdisjoint(_SEQUENCES):
            return level
        else:  # lists mixed with other values at one level
            level = list(chain.from_iterable(x if type(x) in _SEQUENCES else (x,) for x in level))
    return level


def _why_unreadable(value: Any, exc: Exception) -> str:
    if type(value) in _SEQUENCES and isinstance(exc, ValueError):
        return f"ragged ({short(value)})"
    reason = " ".join(str(exc).split()) or "no reason given"
    return f"not readable as an array ({type(exc).__name__}: {reason})"


def short(value: Any) -> str:
    """``repr`` of a value (of an array: of its list), cut to 60 characters."""
    try:
        text = repr(value.tolist() if isinstance(value, np.ndarray) else value)
    except Exception:  # a user's object whose repr fails is still named by its type
        text = f"<{type(value).__name__} object>"
    text = " ".join(text.split())
    return text if len(text) <= 60 else text[:57] + "..."
