"""Small numeric helpers for the hot paths of one-world steps, where NumPy's per-call cost dominates.

On arrays of a few values a ufunc call costs ~0.3 us, and a Python float operand adds ~0.2 us
more: NumPy 2 treats Python scalars as "weak" and resolves their type on every call. Constants
used on float64 arrays in a step are therefore kept as 0-d float64 arrays (:func:`constant`). They
promote exactly like the Python float for float64 operands, so results are bit-identical; for
float32 operands they would not (a 0-d float64 array is "strong" and gives float64), so use them
only where the other operand is float64.
"""

from __future__ import annotations

import numpy as np


def constant(value: float) -> np.ndarray:
    """A read-only 0-d float64 array holding ``value``: a cheaper operand than a Python float (see above)."""
    array = np.array(value, dtype=np.float64)
    array.flags.writeable = False
    return array


def clamp(values: np.ndarray, low, high) -> np.ndarray:
    """``np.clip`` for arrays, without its Python-level dispatch (several times faster on small arrays)."""
    return np.minimum(np.maximum(values, low), high)


def and_not(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """``a & ~b`` of bool arrays in one NumPy call (True > False is the only true comparison)."""
    return np.greater(a, b)


def all_true(mask: np.ndarray) -> bool:
    """``mask.all()`` for a bool array; np.count_nonzero is the cheapest test on the few values of a step."""
    return np.count_nonzero(mask) == mask.size
