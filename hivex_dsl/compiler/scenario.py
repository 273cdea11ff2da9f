"""Scenario document -> validated spec -> CompiledScenario (frozen), one per sweep grid point.

Compilation is total: every check that could fail later (names, bounds, seeds, layouts that
must fit) runs here, so a scenario that compiles always resets and steps. Reading a source and
telling a lock from a scenario is :mod:`.dispatch`'s work.
"""

from __future__ import annotations

import copy
import dataclasses
import functools
import hashlib
import itertools
import json
from dataclasses import dataclass, field
from functools import cached_property
from types import MappingProxyType
from typing import Any, Mapping

from ..base.errors import Location, Problem, ScenarioError, did_you_mean, got, kind_of, one_of, show
from ..lang.blame import MISSING as _MISSING, culprit, get as _get
from ..lang.loader import Loaded, PathKey
from ..lang.spec.common import SCHEMA_VERSION, StrictModel
from ..lang.spec.expression_keys import (clashing_terms, declared_term_names, expression_keys, expression_term_names,
                                         split_ends_on)
from ..lang.spec.expressions import WeightSchedule
from ..lang.spec.scenario import SWEEPABLE_PREFIXES, Seeds, scenario_model, sweepable_fields
from ..lang.spec.validate import dotted, validate_model
from ..sim.reward.composer import return_bound_problem
from ..sim.reward.expressions import event_names, with_expressions
from . import registry

MAX_SWEEP_POINTS = 10_000
# A sweep's expression work: its points x the expressions its file writes, and x their characters. Each point
# checks them against its own vocabulary (shared where the vocabularies are the same) and keeps them: 10,000 points
# of 460 expressions of 2,000 characters took 108 s and 4.7 GB to validate; 210 points of them, 83 s.
MAX_SWEEP_EXPRESSIONS = 100_000
MAX_SWEEP_EXPRESSION_CHARS = 25_000_000
MAX_SWEEP_VALUES = 1_000
MAX_BLAME_TRIALS = 1_000  # recompilations a sweep may spend finding which written value causes a problem
LOCK_VERSION = 1


@dataclass(frozen=True, eq=False)
class CompiledScenario:
    """One fully resolved scenario: every value explicit, nothing left to fail at reset."""

    entry: "registry.EnvironmentEntry"
    spec: StrictModel
    source: str
    task_index: int
    level: int | None
    weights: Mapping[str, float]
    ends_on: tuple[str, ...]
    sweep_point: Mapping[str, Any] = field(default_factory=dict)
    generators: Mapping[str, StrictModel] = field(default_factory=dict)
    schedules: Mapping[str, WeightSchedule] = field(default_factory=dict)  # weights moving with env steps
    expressions: Any = None  # a reward.expressions.ScenarioExpressions when the scenario writes any
    unpaid: frozenset[str] = frozenset()  # weighted terms the task logs in its statistics but does not pay
    # the params a stored resolved scenario (a lock's, a checkpoint's) was written with, None for a scenario file:
    # its fingerprint hashes those alone, as it was hashed when written (hivex_dsl.compiler.locks.written)
    written_params: frozenset[str] | None = None

    @property
    def term_contracts(self) -> tuple:
        """Contracts of every term this scenario can weight: the environment's, then its expression terms."""
        own = self.expressions.contracts if self.expressions is not None else ()
        return tuple(term.contract for term in self.entry.terms) + own

    @property
    def environment(self) -> str:
        return self.entry.id

    @property
    def name(self) -> str:
        if not self.sweep_point:
            return self.spec.name
        return f"{self.spec.name}[{','.join(f'{k}={v}' for k, v in self.sweep_point.items())}]"

    @property
    def task_name(self) -> str:
        return self.entry.reward_table.tasks[self.task_index].name

    @property
    def agents(self) -> int:
        return self.spec.agents

    @property
    def episode_length(self) -> int:
        return self.spec.episode_length

    @property
    def decision_period(self) -> int:
        """Physics steps per decision (ML-Agents' DecisionPeriod): one ``step`` of an env runs this many."""
        return self.spec.decision_period

    @property
    def episode_decisions(self) -> int:
        """Decisions (policy steps) in an episode that runs to its length: episode_length / decision_period."""
        return self.spec.episode_length // self.spec.decision_period

    @property
    def seeds(self) -> Seeds:
        return self.spec.seeds

    @property
    def params(self) -> StrictModel:
        return self.spec.params

    @property
    def agent_names(self) -> tuple[str, ...]:
        return tuple(f"{self.entry.info.agent_name}_{i}" for i in range(self.agents))

    def resolved(self) -> dict[str, Any]:
        """The scenario in the language itself, with every value written out."""
        out: dict[str, Any] = {"hivex": SCHEMA_VERSION, "name": self.name, "environment": self.environment,
                               "task": self.task_name}
        if self.entry.info.level_field:
            out[self.entry.info.level_field] = self.level
        out |= {"agents": self.agents, "episode_length": self.episode_length}
        # written unless 1 and the environment's default, so the scenarios, locks and fingerprints of period 1 from
        # before stay, and those of an environment whose default is not 1 say their period
        if self.decision_period != 1 or self.entry.info.default_decision_period != 1:
            out["decision_period"] = self.decision_period
        out |= {"seeds": {"train": _plain(self.seeds.train), "test": _plain(self.seeds.test)},
                "weights": {name: self.schedules[name].as_dict() if name in self.schedules else weight
                            for name, weight in self.weights.items()},
                "params": self.params.model_dump(mode="json")}
        if self.generators:
            out["generators"] = {name: spec.model_dump(mode="json") for name, spec in self.generators.items()}
        return out | expression_keys(self.spec)

    @cached_property
    def fingerprint(self) -> str:
        """sha256 of what determines behaviour: resolved content (not name) and term contracts."""
        content = {key: value for key, value in self.resolved().items() if key != "name"}
        added = type(self.params).added_fields()  # at what was done before they came, they leave no trace
        content["params"] = {key: value for key, value in content["params"].items()
                             if not (key in added and value == added[key])
                             and (self.written_params is None or key in self.written_params)}
        content["ends_on"] = list(self.ends_on)
        content["term_contracts"] = [contract.as_dict() for contract in self.term_contracts]
        if self.unpaid:  # only then: every scenario without one keeps its fingerprint
            content["unpaid"] = sorted(self.unpaid)
        canonical = json.dumps(content, sort_keys=True, separators=(",", ":"), allow_nan=False)
        return "sha256:" + hashlib.sha256(canonical.encode()).hexdigest()

    def to_lock(self) -> dict[str, Any]:
        from ..sim.spaces import describe_space

        simulator = self.entry.make_simulator(self)
        return {
            "hivex_lock": LOCK_VERSION,
            "fingerprint": self.fingerprint,
            "scenario": self.resolved(),
            "task_index": self.task_index,
            "ends_on": list(self.ends_on),
            "sweep_point": dict(self.sweep_point),
            "term_contracts": {contract.name: contract.as_dict() for contract in self.term_contracts},
            "spaces": {"observation": describe_space(simulator.observation_space),
                       "action": describe_space(simulator.action_space)},
        }


def _plain(seeds: Any) -> Any:
    return list(seeds) if isinstance(seeds, tuple) else seeds


def compile_scenario(loaded: Loaded) -> list[CompiledScenario]:
    """A scenario document (not a lock: :mod:`.dispatch` sends those to :mod:`.locks`), one per sweep point."""
    data = loaded.data
    if not isinstance(data, dict):
        _fail(loaded, (), f"the top level must be a mapping of keys such as 'hivex' and 'environment', got {got(data)}")
    entry = _environment(loaded)
    points = _sweep_points(loaded, entry)
    compiled, problems, budget = [], [], [MAX_BLAME_TRIALS]
    for assignment in points:
        try:
            compiled.append(_compile_point(loaded, entry, assignment, budget))
        except ScenarioError as exc:
            problems.extend(p for p in exc.problems if p not in problems)
    if problems:
        raise ScenarioError(problems)
    return compiled


def _fail(loaded: Loaded, path: PathKey, message: str, key: bool = False):
    raise ScenarioError([Problem(loaded.locate(path, key=key), message)])


def _environment(loaded: Loaded) -> "registry.EnvironmentEntry":
    data = loaded.data
    version = data.get("hivex")
    if "hivex" not in data:
        _fail(loaded, (), f"missing required key 'hivex' (the language version; write 'hivex: {SCHEMA_VERSION}')")
    if version != SCHEMA_VERSION or isinstance(version, bool):
        _fail(loaded, ("hivex",), f"hivex: {show(version)} is not a version this toolkit reads: expected {SCHEMA_VERSION}")
    if "environment" not in data:
        _fail(loaded, (), f"missing required key 'environment'; expected one of: {', '.join(registry.environments())}")
    env_id = data["environment"]
    if not isinstance(env_id, str):
        _fail(loaded, ("environment",), f"environment: expected a name, got {got(env_id)}")
    try:
        return registry.get(env_id)
    except KeyError as exc:
        _fail(loaded, ("environment",), f"environment: {exc.args[0]}")


Assignment = tuple[tuple[PathKey, Any, PathKey], ...]  # (field path, value, where the value is written)


def _sweep_points(loaded: Loaded, entry) -> list[Assignment]:
    sweep = loaded.data.get("sweep")
    if sweep is None:
        return [()]
    if not isinstance(sweep, dict):
        _fail(loaded, ("sweep",), f"sweep: expected a mapping of field -> list of values, got {got(sweep)}")
    if not sweep:
        _fail(loaded, ("sweep",), "sweep: the mapping is empty; expected at least one field -> list of values "
                                  "(or no 'sweep' key)")
    axes = []
    for key, values in sweep.items():
        target = _sweep_target(loaded, entry, key)
        where = ("sweep", key)
        if not isinstance(values, list) or not values:
            _fail(loaded, where, f"sweep.{key}: expected a non-empty list of values, got {got(values)}")
        if len(values) > MAX_SWEEP_VALUES:
            _fail(loaded, where, f"sweep.{key}: {len(values)} values; at most {MAX_SWEEP_VALUES} are allowed")
        first_at: dict[tuple, int] = {}
        for i, value in enumerate(values):
            if isinstance(value, (dict, list)) or value is None:
                _fail(loaded, where + (i,), f"sweep.{key}[{i}]: expected a single value, got {kind_of(value)}")
            same = (isinstance(value, bool), isinstance(value, str), value)  # true is not 1, '1' is not 1
            if same in first_at:
                _fail(loaded, where + (i,), f"sweep.{key}[{i}]: {show(value)} is listed twice "
                                            f"(first at [{first_at[same]}]); list each value once")
            first_at[same] = i
        axes.append([(target, value, where + (i,)) for i, value in enumerate(values)])
    total = 1
    for axis in axes:
        total *= len(axis)
    if total > MAX_SWEEP_POINTS:
        _fail(loaded, ("sweep",), f"sweep makes {total:,} scenarios; at most {MAX_SWEEP_POINTS:,} are allowed", key=True)
    _check_expression_work(loaded, total)
    return [tuple(point) for point in itertools.product(*axes)]


def _check_expression_work(loaded: Loaded, points: int) -> None:
    """Refuse a sweep whose points x written expressions (or x their characters) pass the caps, before compiling."""
    texts = written_expressions(loaded.data)
    count, chars = len(texts), sum(len(text) for text in texts)
    for work, cap, what in ((points * count, MAX_SWEEP_EXPRESSIONS, f"the {count:,} expressions"),
                            (points * chars, MAX_SWEEP_EXPRESSION_CHARS, f"the {chars:,} expression characters")):
        if work > cap:
            _fail(loaded, ("sweep",), f"sweep makes {points:,} scenarios, each compiling {what} this file writes: "
                                      f"{work:,} in all, at most {cap:,} are allowed; sweep fewer points or write "
                                      "fewer or shorter expressions", key=True)


def written_expressions(data: dict) -> list[str]:
    """The expressions a scenario file writes, read before anything is validated: its terms' ``expr``, its
    shaping's ``potential`` and its ``ends_on`` entries (an event's name among them counts too: an upper bound)."""
    terms, shaping, ends_on = data.get("terms"), data.get("shaping"), data.get("ends_on")
    texts = [t.get("expr") if isinstance(t, dict) else t for t in terms.values()] if isinstance(terms, dict) else []
    texts += [shaping.get("potential")] if isinstance(shaping, dict) else []
    texts += ends_on if isinstance(ends_on, list) else []
    return [text for text in texts if isinstance(text, str)]


def _sweep_target(loaded: Loaded, entry, key: str) -> PathKey:
    vocab = entry.vocabulary
    fields = sweepable_fields(vocab)
    nested = {"params": tuple(entry.params_model.model_fields), "weights": entry.term_names + expression_term_names(loaded.data),
              "seeds": tuple(Seeds.model_fields)}
    options = list(fields) + [f"{p}.{n}" for p in SWEEPABLE_PREFIXES for n in nested[p]]
    generator_fields = [f"generators.{name}.{f}" for name, slot in entry.generators.items()
                        for f in slot.spec_model.model_fields]
    options += generator_fields
    head, _, tail = key.partition(".")
    if key in fields or (head in nested and tail in nested[head]) or key in generator_fields:
        target = tuple(key.split("."))
        if _get(loaded.data, target) is not _MISSING:
            _fail(loaded, ("sweep", key), f"'{key}' is both set in the file and swept; keep only one", key=True)
        return target
    hint = did_you_mean(key, options)
    _fail(loaded, ("sweep", key), f"cannot sweep over '{key}'{hint}; expected one of: {', '.join(fields)}, "
          f"params.<name>, weights.<term>, seeds.train or seeds.test"
          f"{', generators.<generator>.<field>' if generator_fields else ''}", key=True)


def _compile_point(loaded: Loaded, entry, assignment: Assignment, budget: list[int]) -> CompiledScenario:
    data = {k: v for k, v in copy.deepcopy(loaded.data).items() if k != "sweep"}
    redirects = {}
    for target, value, where in assignment:
        parent = data
        for part in target[:-1]:
            parent = parent.setdefault(part, {}) if isinstance(parent, dict) else parent
        if isinstance(parent, dict):
            parent[target[-1]] = value
        redirects[target] = where

    def locate(path: PathKey, key: bool = False) -> Location:
        for target, where in redirects.items():
            if tuple(path[: len(target)]) == target:
                return loaded.locate(where)
        return loaded.locate(path, key=key)

    point = {".".join(t): v for t, v, _ in assignment}
    compiled = _validated(entry, data, loaded.source, point, locate)
    swept = [target for target, _, _ in assignment]
    found = _semantic_problems(compiled, swept)
    if found:
        def recheck(variant: dict) -> list[tuple[PathKey, str]]:
            return _semantic_problems(_validated(entry, variant, loaded.source, {}, locate), swept)

        raise ScenarioError([Problem(culprit(loaded, data, assignment, locate, path, budget, recheck), message)
                             for path, message in found])
    return compiled


def _resolve(entry, spec: StrictModel, source: str, point: dict[str, Any], locate) -> CompiledScenario:
    table = entry.reward_table
    task = spec.task if isinstance(spec.task, int) else table.task_names.index(spec.task)
    weights = table.column(task)
    weights.update({name: 1.0 for name in declared_term_names(spec)})  # a declared term counts unless weighted
    written = {name: getattr(spec.weights, name) for name in type(spec.weights).model_fields}
    schedules = {name: w for name, w in written.items() if isinstance(w, WeightSchedule)}
    weights.update({name: w.start if name in schedules else w for name, w in written.items() if w is not None})
    level = None
    if entry.info.level_field == "pattern":
        level = spec.pattern if isinstance(spec.pattern, int) else entry.level_names.index(spec.pattern)
    elif entry.info.level_field == "terrain_level":
        level = spec.terrain_level
    return CompiledScenario(entry=entry, spec=spec, source=source, task_index=task, level=level,
                            weights=MappingProxyType(weights), schedules=MappingProxyType(schedules),
                            unpaid=frozenset(t for t in table.tasks[task].unpaid if weights.get(t, 0.0) != 0.0),
                            ends_on=(event_names(table.tasks[task].ends_on, entry.events)
                                     + split_ends_on(spec, entry.events)[0]),
                            sweep_point=MappingProxyType(point),
                            generators=MappingProxyType(_generator_specs(entry, spec, level, locate)))


def _validated(entry, data: dict, source: str, point: dict, locate) -> CompiledScenario:
    """The scenario ``data`` validated, resolved and with its expressions compiled (no semantic checks yet)."""
    clashes = clashing_terms(data, entry.term_names)
    if clashes:
        raise ScenarioError([Problem(locate(path, key=True), message) for path, message in clashes])
    spec = validate_model(_scenario_model(entry, expression_term_names(data)), data, locate)
    return with_expressions(_resolve(entry, spec, source, point, locate), spec, locate)


@functools.lru_cache(maxsize=64)
def _scenario_model(entry, extra_terms: tuple[str, ...]) -> type[StrictModel]:
    """The environment's scenario model, its weights also naming the scenario's expression terms."""
    if not extra_terms:
        return entry.scenario_model
    vocab = entry.vocabulary
    return scenario_model(dataclasses.replace(vocab, term_names=vocab.term_names + extra_terms))


def _generator_specs(entry, spec: StrictModel, level: int | None, locate) -> dict[str, StrictModel]:
    """Every generator slot's preset for ``level`` with the scenario's overrides merged and revalidated."""
    overrides = getattr(spec, "generators", None)
    merged, problems = {}, []
    for name, slot in entry.generators.items():
        override = getattr(overrides, name)
        changes = override.model_dump(include=override.model_fields_set)
        if not changes:
            merged[name] = slot.preset(level)
            continue
        data = slot.preset(level).model_dump() | changes
        prefix = ("generators", name)
        try:
            merged[name] = validate_model(slot.spec_model, data, lambda path, key=False: locate(prefix + tuple(path), key))
        except ScenarioError as exc:
            problems.extend(Problem(p.location, _prefixed(p.message, prefix)) for p in exc.problems)
    if problems:
        raise ScenarioError(problems)
    return merged


def _prefixed(message: str, prefix: PathKey) -> str:
    """A nested model's message names its field from the top of the scenario ('generators.terrain.x: ...')."""
    top = dotted(())
    if message.startswith(f"{top}: "):
        return f"{dotted(prefix)}: {message[len(top) + 2:]}"
    return f"{dotted(prefix)}.{message}" if ":" in message.split(" ")[0] else f"{dotted(prefix)}: {message}"


def _semantic_problems(compiled: CompiledScenario, swept: list[PathKey] = ()) -> list[tuple[PathKey, str]]:
    problems: list[tuple[PathKey, str]] = []
    shared = compiled.seeds.overlap()
    if shared:  # blamed on the test split, unless only the train split is swept (the sweep value collides)
        split = "train" if ("seeds", "train") in swept and ("seeds", "test") not in swept else "test"
        seeds = getattr(compiled.seeds, split)
        where = ("seeds", split) if isinstance(seeds, int) else ("seeds", split, min(seeds.index(s) for s in shared))
        problems.append((where, f"seeds: train and test share {one_of(shared[:5])}; "
                                "the test split must hold seeds never used in training"))
    period, length = compiled.decision_period, compiled.episode_length
    if length % period:
        fits = " or ".join(map(str, sorted({max(period, length - length % period), length - length % period + period})))
        problems.append((("decision_period",), f"decision_period: episode_length {length} is not a multiple of "
                         f"decision_period {period}: an episode ends on a decision; write episode_length {fits}, "
                         "or a decision_period that divides it"))
    for check in compiled.entry.checks:
        problems.extend((path, f"{dotted(path)}: {message}") for path, message in check(compiled))
    too_large = return_bound_problem(compiled.term_contracts, compiled.weights, compiled.schedules,
                                     compiled.episode_length)
    if too_large:
        term, why = too_large
        problems.append((("weights", term), f"weights.{term}: {why}"))
    return problems
