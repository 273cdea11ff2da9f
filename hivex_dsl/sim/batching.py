"""Selecting and replacing worlds of batched states (dataclasses of arrays with a leading world axis).

One place for what every simulator's partial reset does: build fresh worlds, then put them where
the mask says. Nested dataclasses are handled field by field; fields that are not arrays (a step
counter, say) belong to the batch, not to a world, and are kept.
"""

from __future__ import annotations

from dataclasses import fields, is_dataclass, replace
from typing import Any, TypeVar

import numpy as np

S = TypeVar("S")


def put_worlds(old: np.ndarray, mask: np.ndarray, fresh: np.ndarray, axis: int = 0) -> np.ndarray:
    """A copy of ``old`` whose worlds where ``mask`` is true (along ``axis``) come from ``fresh``."""
    out = old.copy()
    out[(slice(None),) * axis + (mask,)] = fresh
    return out


def replace_worlds(old: S, mask: np.ndarray, fresh: S) -> S:
    """``old`` with the worlds where ``mask`` (B,) is true taken from ``fresh`` (which holds only those worlds)."""
    changes = {}
    for item in fields(old):
        a, b = getattr(old, item.name), getattr(fresh, item.name)
        if is_dataclass(a):
            changes[item.name] = replace_worlds(a, mask, b)
        elif isinstance(a, np.ndarray):
            changes[item.name] = put_worlds(a, mask, b)
    return replace(old, **changes)


def select_worlds(state: S, index: Any) -> S:
    """The worlds of ``state`` selected by ``index`` (a slice, mask or index array on the world axis)."""
    return replace(state, **{f.name: getattr(state, f.name)[index] for f in fields(state)})


def assemble(cls: type[S], **fields: Any) -> S:
    """``cls(**fields)`` for a frozen dataclass that a step builds from values valid by construction.

    Every field must be given. The instance's ``__dict__`` is filled at once, without the frozen
    ``__init__``'s ``object.__setattr__`` per field or ``__post_init__``'s checks: on a one-world batch
    those cost more than much of the step. Hand-made states go through the normal constructor.
    """
    state = object.__new__(cls)
    state.__dict__.update(fields)
    return state


def evolve(state: S, **changes: Any) -> S:
    """``dataclasses.replace(state, **changes)`` by :func:`assemble`: the same result, without the checks."""
    return assemble(type(state), **{**state.__dict__, **changes})


def read_only(array: np.ndarray) -> np.ndarray:
    """A read-only view of ``array``: for observations a simulator also keeps (e.g. as the older stack
    of the next frame), so an in-place edit by a caller raises instead of corrupting the next step."""
    view = array.view()
    view.flags.writeable = False
    return view


def pad_by_world(world: np.ndarray, batch: int) -> tuple[np.ndarray, int]:
    """Where each of N items of worlds ``world`` (N,) int, ascending, goes in a (B, width) padded array: its slot
    (N,) int64 within its world's row, and the width (the most items of one world; at least 1).
    ``padded[world, slot]`` then holds the items, the rest of each row is padding."""
    count = np.bincount(world, minlength=batch)
    slot = np.arange(len(world)) - (np.cumsum(count) - count)[world]
    return slot, max(int(count.max()) if len(world) else 0, 1)
