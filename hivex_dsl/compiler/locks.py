"""Lock files: one resolved scenario with everything derived from it, checked field by field on load.

The fingerprint covers the resolved scenario (its name aside), the ending events and the term
contracts; every other field of the lock (task index, ending events, term contracts, spaces,
sweep point) is recomputed from the scenario and must match what is stored, so no edit of a
lock goes unnoticed. The one exception is the scenario's name, a label left out of the
fingerprint so that equal content has one fingerprint; a sweep point's name must still end
with its ``[field=value,...]``. A lock holds exactly one scenario: a ``sweep`` inside it is an error.
"""

from __future__ import annotations

import copy
import dataclasses
import json
import re
from types import MappingProxyType
from typing import Any

from ..base.errors import Problem, ScenarioError, did_you_mean, show
from ..lang.blame import MISSING as _MISSING, get as _get
from ..lang.loader import Loaded, PathKey, load_text
from . import registry
from .scenario import LOCK_VERSION, CompiledScenario, compile_scenario

LOCK_KEYS = ("hivex_lock", "fingerprint", "scenario", "task_index", "ends_on", "sweep_point",
             "term_contracts", "spaces")
_DERIVED = ("task_index", "ends_on", "term_contracts", "spaces")
_EDITED = "the lock was edited, or this version's reward terms differ from the ones it was made with"


def compile_lock(loaded: Loaded) -> CompiledScenario:
    """The scenario a lock file holds, with its sweep point; a located error for any edit."""
    data = loaded.data
    for key in data:
        if key not in LOCK_KEYS:
            _fail(loaded, (key,), f"unknown key '{key}' in a lock file{did_you_mean(key, LOCK_KEYS)}", key=True)
    if data.get("hivex_lock") != LOCK_VERSION or isinstance(data.get("hivex_lock"), bool):
        _fail(loaded, ("hivex_lock",), f"hivex_lock: {show(data.get('hivex_lock'))} is not supported: expected {LOCK_VERSION}")
    missing = [key for key in LOCK_KEYS if key not in data]
    if missing:
        _fail(loaded, (), f"missing required key '{missing[0]}' in a lock file; a lock holds {', '.join(LOCK_KEYS)}")
    scenario = data["scenario"]
    if not isinstance(scenario, dict):
        _fail(loaded, ("scenario",), "a lock file needs the resolved scenario under 'scenario'")
    if "sweep" in scenario:
        _fail(loaded, ("scenario", "sweep"), "a lock holds one resolved scenario; 'sweep' is not allowed in it "
                                             "(lock each point: `hivex compile FILE -o DIR`)", key=True)
    point = _sweep_point(loaded, scenario)
    inner = Loaded(loaded.source, as_written(_without_point_suffix(scenario, point)),
                   {path[1:]: loc for path, loc in loaded.marks.items() if path[:1] == ("scenario",)},
                   {path[1:]: loc for path, loc in loaded.key_marks.items() if path[:1] == ("scenario",)})
    compiled = dataclasses.replace(written(compile_scenario(inner)[0], scenario), sweep_point=MappingProxyType(point))
    stored = data["fingerprint"]
    if stored != compiled.fingerprint:
        _fail(loaded, ("fingerprint",), f"fingerprint {show(stored)} does not match the content ({compiled.fingerprint}): "
              + _EDITED)
    _check_point_values(loaded, scenario, compiled)
    expected = compiled.to_lock()
    problems = [Problem(loaded.locate((key,)), f"{key}: the stored value does not match what the scenario compiles "
                                                f"to ({_compact(expected[key])}); {_EDITED}")
                for key in _DERIVED if not _same(data[key], expected[key])]
    if problems:
        raise ScenarioError(problems)
    return compiled


def as_written(scenario: Any) -> Any:
    """A resolved scenario (a lock's or a checkpoint's, every param written out) read as it meant when written:
    a param added since (its params model's ``ADDED_FIELDS``) that it lacks takes the value that does what was
    done then. Anything else, or a scenario this cannot place, is returned as is for the compiler to judge."""
    if not isinstance(scenario, dict) or not isinstance(scenario.get("params"), dict):
        return scenario
    environment = scenario.get("environment")
    entry = registry.environments().get(environment) if isinstance(environment, str) else None
    if entry is None:  # no environment this can place (a list, a misspelt name): the compiler says what is wrong
        return scenario
    missing = {name: before for name, before in entry.params_model.added_fields().items()
               if name not in scenario["params"]}
    return {**scenario, "params": {**scenario["params"], **missing}} if missing else scenario


def written(compiled: CompiledScenario, scenario: Any) -> CompiledScenario:
    """``compiled`` (from ``as_written(scenario)``) under the fingerprint ``scenario`` was written with: one that
    hashes only the params it holds. A param added since is then no change of content (a lock or checkpoint from
    before it, not edited, keeps matching its stored fingerprint), while any value it holds, edited, added or
    deleted, still changes the hash."""
    params = scenario.get("params") if isinstance(scenario, dict) else None
    return dataclasses.replace(compiled, written_params=frozenset(params)) if isinstance(params, dict) else compiled


def _sweep_point(loaded: Loaded, scenario: dict) -> dict[str, Any]:
    """The lock's sweep point: each field must be one the locked scenario sets, and the name must end with it."""
    point = loaded.data["sweep_point"]
    if not isinstance(point, dict):
        _fail(loaded, ("sweep_point",), f"sweep_point: expected a mapping of field -> value, got {show(point)}")
    for key in point:
        if _get(scenario, tuple(key.split("."))) is _MISSING:
            _fail(loaded, ("sweep_point", key), f"sweep_point: '{key}' is not a field of the locked scenario", key=True)
    suffix = f"[{','.join(f'{k}={v}' for k, v in point.items())}]"
    name = scenario.get("name")
    if not point and _named_for_a_point(scenario):
        _fail(loaded, ("sweep_point",), f"sweep_point: {{}} but the scenario's name {show(name)} ends with a sweep "
                                        f"point; {_EDITED}")
    if point and not (isinstance(name, str) and name.endswith(suffix) and name != suffix):
        _fail(loaded, ("scenario", "name"), f"name: {show(name)} does not end with its sweep point '{suffix}'; {_EDITED}")
    return dict(point)


def _named_for_a_point(scenario: dict) -> bool:
    """Whether the name ends with ``[field=value,...]`` over fields the scenario sets, as a sweep point's does."""
    match = re.search(r"\[([^\[\]]+)\]$", str(scenario.get("name", "")))
    if not match:
        return False
    pairs = [item.partition("=") for item in match.group(1).split(",")]
    return all(sep and _get(scenario, tuple(key.split("."))) is not _MISSING for key, sep, _ in pairs)


def _check_point_values(loaded: Loaded, scenario: dict, compiled: CompiledScenario) -> None:
    """Each swept value, written into the scenario, must compile to the same scenario (so 'task: 0' matches
    the resolved task name, and an edited value does not)."""
    for key, value in compiled.sweep_point.items():
        variant = copy.deepcopy(scenario)
        path = key.split(".")
        _get(variant, tuple(path[:-1]))[path[-1]] = value
        try:
            same = compile_scenario(Loaded(loaded.source, variant))[0].fingerprint == compiled.fingerprint
        except ScenarioError:
            same = False
        if not same:
            _fail(loaded, ("sweep_point", key), f"sweep_point.{key}: {show(value)} is not the locked scenario's "
                                                f"value; {_EDITED}")


def _without_point_suffix(scenario: dict, point: dict) -> dict:
    """The scenario with ``[field=value,...]`` taken off its name: compiling adds it back from the sweep point."""
    if not point:
        return scenario
    suffix = f"[{','.join(f'{k}={v}' for k, v in point.items())}]"
    return {**scenario, "name": scenario["name"][: -len(suffix)]}


def _same(stored: Any, expected: Any) -> bool:
    """Equal as the loader reads JSON (so 1 and 1.0, or a tuple and a list, compare as written)."""
    return _typed(stored) == _typed(load_text(json.dumps({"v": expected})).data["v"])


def _typed(value: Any) -> Any:
    if isinstance(value, dict):
        return {k: _typed(v) for k, v in value.items()}
    if isinstance(value, list):
        return [_typed(v) for v in value]
    return (type(value) is bool, value)


def _compact(value: Any) -> str:
    text = json.dumps(value, separators=(",", ":"))
    return text if len(text) <= 80 else text[:77] + "..."


def _fail(loaded: Loaded, path: PathKey, message: str, key: bool = False):
    raise ScenarioError([Problem(loaded.locate(path, key=key), message)])

