"""Registered environments: catalogue entry + params + reward terms + simulator factory.

Each environment package (a folder hivex_dsl/envs/<catalogue id>/) calls :func:`register` once
on import; :func:`get` loads every such package on first use so users never import them by hand.
It finds them by module name, as Gymnasium's entry-point strings name environments
(:data:`ENVIRONMENT_MODULES`, imported with ``importlib``): the registry, in the compiler layer, has
no import of the environments layer above it, which imports the registry to register.
"""

from __future__ import annotations

import importlib
from dataclasses import dataclass, field
from functools import cached_property
from typing import Any, Callable, Mapping

from ..base.errors import Problem, ScenarioError, did_you_mean
from ..base.resources import data_dir
from ..lang.loader import Loaded, load_file
from ..lang.spec.catalogue import CATALOGUE, EnvironmentInfo
from ..lang.spec.common import StrictModel
from ..lang.spec.reward_table import RewardTable, table_problems
from ..lang.spec.scenario import ScenarioVocabulary, scenario_model
from ..lang.spec.validate import validate_loaded
from ..sim.reward.terms import TermRegistry
from ..sim.statistics import StatisticSet

# Each catalogue environment's package, by module name; one this version does not have is "not available yet".
ENVIRONMENT_MODULES: dict[str, str] = {env_id: f"{__name__.split('.')[0]}.envs.{env_id}" for env_id in CATALOGUE}

# A CompiledScenario (compiler/scenario.py), named in the annotations below only: that module imports this one.
Compiled = Any

_REGISTRY: dict[str, "EnvironmentEntry"] = {}

# A compile-time check: resolved scenario -> [(path in the file, message)].
ScenarioCheck = Callable[[Compiled], list[tuple[tuple, str]]]


@dataclass(frozen=True)
class GeneratorSlot:
    """A procedural generator an environment uses, overridable under a scenario's ``generators:``.

    ``preset(level)`` gives the spec the environment uses at a difficulty level (``None`` for
    environments without levels); a scenario's overrides are merged over it and revalidated.
    """

    spec_model: type[StrictModel]
    preset: Callable[[int | None], StrictModel]
    description: str


@dataclass(frozen=True, eq=False)
class EnvironmentEntry:
    """Everything the compiler, adapters, CLI and docs need to know about one environment."""

    info: EnvironmentInfo
    params_model: type[StrictModel]
    terms: TermRegistry
    make_simulator: Callable[[Compiled], Any]
    scripted_policy: Callable[[Compiled], Callable[[Any], Any]]
    events: Mapping[str, str] = field(default_factory=dict)
    # events of the whole world (e.g. the fire went out): a task that ends on one restarts the world,
    # where the other events (and the simulator's own ``terminated``) end single agents' episodes
    world_events: frozenset[str] = frozenset()
    level_names: tuple[str, ...] = ()
    level_titles: tuple[str, ...] = ()
    checks: tuple[ScenarioCheck, ...] = ()
    notes: tuple[str, ...] = ()
    generators: Mapping[str, GeneratorSlot] = field(default_factory=dict)
    # the per-episode statistics the original logged (hivex_dsl.sim.statistics); None: it declares none
    statistics: StatisticSet | None = None

    @property
    def id(self) -> str:
        return self.info.id

    @cached_property
    def reward_table(self) -> RewardTable:
        return load_reward_table(self)

    @cached_property
    def reward_table_file(self) -> Loaded:
        """rewards/<env>.yaml as read, for locating problems of the table's expressions."""
        return load_file(data_dir("rewards") / f"{self.id}.yaml")

    @property
    def term_names(self) -> tuple[str, ...]:
        """The registered terms, then the reward table's expression terms."""
        return self.terms.names + tuple(self.reward_table.terms or ())

    @cached_property
    def vocabulary(self) -> ScenarioVocabulary:
        """The names and bounds a scenario of this environment may use."""
        return ScenarioVocabulary(info=self.info, params_model=self.params_model,
                                  task_names=self.reward_table.task_names, term_names=self.term_names,
                                  level_names=self.level_names,
                                  generators={name: slot.spec_model for name, slot in self.generators.items()})

    @cached_property
    def scenario_model(self) -> type[StrictModel]:
        return scenario_model(self.vocabulary)


def register(entry: EnvironmentEntry) -> EnvironmentEntry:
    if entry.id not in CATALOGUE:
        raise ValueError(f"{entry.id!r} is not in the catalogue of HIVEX environments")
    unknown = sorted(set(entry.world_events) - set(entry.events))
    if unknown:
        raise ValueError(f"{entry.id}: world events {unknown} are not among its events {sorted(entry.events)}")
    if entry.id in _REGISTRY:
        raise ValueError(f"environment {entry.id!r} registered twice")
    if entry.terms.environment != entry.id:
        raise ValueError(f"{entry.id}: its term registry belongs to {entry.terms.environment!r}")
    if entry.statistics is not None:
        problems = entry.statistics.problems(entry.terms.names)
        if problems or entry.statistics.environment != entry.id:
            raise ValueError("; ".join(problems) or f"{entry.id}: its statistics belong to {entry.statistics.environment!r}")
    _REGISTRY[entry.id] = entry
    return entry


def _load_all() -> None:
    """Import every package of :data:`ENVIRONMENT_MODULES` that this version has; each registers itself."""
    for module in ENVIRONMENT_MODULES.values():
        try:
            importlib.import_module(module)
        except ModuleNotFoundError as exc:
            if exc.name != module:  # the package is there, and something it imports is missing
                raise


def environments() -> dict[str, EnvironmentEntry]:
    """The available environments by id, in catalogue order."""
    _load_all()
    return {env_id: _REGISTRY[env_id] for env_id in CATALOGUE if env_id in _REGISTRY}


def get(env_id: str) -> EnvironmentEntry:
    available = environments()
    if env_id in available:
        return available[env_id]
    if env_id in CATALOGUE:
        raise KeyError(f"environment '{env_id}' is part of HIVEX but not available in this version yet; "
                       f"available: {', '.join(available)}")
    raise KeyError(f"unknown environment '{env_id}'{did_you_mean(env_id, CATALOGUE)}; expected one of: {', '.join(CATALOGUE)}")


def load_reward_table(entry: EnvironmentEntry) -> RewardTable:
    """Read and check rewards/<env>.yaml against the environment's registered terms and events."""
    loaded = entry.reward_table_file
    table = validate_loaded(RewardTable, loaded)
    problems = table_problems(table, entry.id, entry.terms.names, tuple(entry.events), _quantity_names(entry.id))
    if problems:
        raise ScenarioError([Problem(loaded.locate(path), message) for path, message in problems])
    return table


def _quantity_names(env_id: str) -> tuple[str, ...]:
    """Names an environment's expressions may read (none without a vocabulary module)."""
    from ..sim.reward.vocabulary import vocabulary_of

    try:
        return tuple(vocabulary_of(env_id).readers)
    except ModuleNotFoundError:
        return ()


__all__ = ["EnvironmentEntry", "GeneratorSlot", "register", "environments", "get"]
