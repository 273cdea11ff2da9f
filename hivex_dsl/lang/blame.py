"""Which value the user wrote causes a semantic problem: the search behind located compile errors.

A cross-field problem (a layout that cannot fit, seeds that overlap) is found on the resolved
scenario, far from any one value; it is blamed on the first written value whose removal makes it go
away, found by recompiling variants of the scenario with one value removed.
"""

from __future__ import annotations

import copy
from typing import Any, Callable

from ..base.errors import Location, ScenarioError
from .loader import Loaded, PathKey

MISSING = object()
_NOT_CAUSES = ("hivex", "environment", "name", "description", "seeds")

# variant data -> its semantic problems [(path, message)]; raises ScenarioError if the variant is invalid
Recheck = Callable[[dict], list[tuple[PathKey, str]]]


def get(data: Any, path: PathKey) -> Any:
    """The value at ``path`` in nested mappings, or :data:`MISSING`."""
    for part in path:
        if not isinstance(data, dict) or part not in data:
            return MISSING
        data = data[part]
    return data


def culprit(loaded: Loaded, data: dict, assignment, locate, path: PathKey, budget: list[int],
            recheck: Recheck) -> Location:
    """Where the user wrote what makes the semantic problem at ``path``: the first written value whose
    removal makes the problem go away (``path`` itself first, then sweep values, then the file's
    values in order: a params value that makes a layout impossible); else the value at ``path``
    when the file sets (or sweeps) it; else this point's first sweep value. ``assignment`` holds the
    point's (target, value, where) sweep triples; ``budget`` ([trials left]) bounds the recompilations
    of a whole sweep."""
    swept = {target: where for target, _, where in assignment}
    written = path in loaded.marks or any(path[: len(t)] == t for t in swept)
    candidates = [] if path[:1] == ("seeds",) else ([path] if written else []) + _written_leaves(data, swept)
    for leaf in candidates:
        if get(data, leaf) is MISSING or budget[0] <= 0:
            continue
        budget[0] -= 1
        variant = copy.deepcopy(data)
        parent = get(variant, leaf[:-1])
        del parent[leaf[-1]]
        try:
            remaining = recheck(variant)
        except ScenarioError:
            continue
        if all(p != path for p, _ in remaining):
            return locate(leaf)
    return locate(path) if written or not swept else loaded.locate(next(iter(swept.values())))


def _written_leaves(data: dict, swept: dict) -> list[PathKey]:
    """Paths of the single values a scenario sets (swept ones first), at most 64 of them."""
    leaves = list(swept)

    def walk(value: Any, path: PathKey) -> None:
        if isinstance(value, dict):
            for key, item in value.items():
                walk(item, path + (key,))
        elif path and path[0] not in _NOT_CAUSES and path not in leaves:
            leaves.append(path)

    walk(data, ())
    return leaves[:64]
