"""The compiler's front door: a source (a path, a bundled scenario's name or a dict) into CompiledScenarios.

:func:`compile_loaded` is the one place that tells the two documents apart: a lock file goes to
:mod:`.locks`, anything else to the scenario compiler (:mod:`.scenario`). Neither of those imports
this module, and the scenario compiler never imports locks, so the three form no circle.
"""

from __future__ import annotations

import copy
from pathlib import Path
from typing import Any, Mapping, Union

from ..base.errors import Location, Problem, ScenarioError, got
from ..lang.loader import Loaded, PathKey, load_file
from ..lang.spec.validate import dotted
from . import registry
from .locks import compile_lock
from .scenario import CompiledScenario, compile_scenario

Source = Union[str, Path, Mapping[str, Any]]


def compile(source: Source) -> CompiledScenario:  # noqa: A001 - the public verb of this package
    """Compile a file (or dict) that describes exactly one scenario."""
    loaded = _load(source)
    if isinstance(loaded.data, dict) and loaded.data.get("sweep") is not None:
        raise ScenarioError([Problem(loaded.locate(("sweep",), key=True),
                                     "this file sweeps over a grid; use compile_all() (or `hivex compile`) to get every point")])
    return compile_loaded(loaded)[0]


def compile_all(source: Source) -> list[CompiledScenario]:
    """Compile a file (or dict) into one scenario per sweep grid point (one if it does not sweep)."""
    return compile_loaded(_load(source))


def _load(source: Source) -> Loaded:
    if isinstance(source, Mapping):
        return Loaded("<dict>", _plain_data(source, ()))
    if not isinstance(source, (str, Path)) or not str(source):
        raise ScenarioError([Problem(Location("<input>", 1, 1),
                                     f"expected a scenario file path or dict, got {source!r}")])
    return load_file(registry.resolve_scenario(str(source)))


def _plain_data(value: Any, path: PathKey) -> Any:
    """A copy of dict input as YAML would give it: string keys only, tuples as lists."""
    if isinstance(value, Mapping):
        for key in value:
            if not isinstance(key, str):
                raise ScenarioError([Problem(Location("<dict>", 1, 1), f"{dotted(path + (str(key),))}: "
                                             f"a key must be a name (a string), got {got(key)}")])
        return {key: _plain_data(item, path + (key,)) for key, item in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain_data(item, path + (i,)) for i, item in enumerate(value)]
    return copy.deepcopy(value)


def compile_loaded(loaded: Loaded) -> list[CompiledScenario]:
    """Loaded data into its scenarios: a lock's one, or one per sweep point of a scenario."""
    if isinstance(loaded.data, dict) and "hivex_lock" in loaded.data:
        return [compile_lock(loaded)]
    return compile_scenario(loaded)
