"""Registered environments: identity + params + reward terms + simulator factory, found without a list of ids.

The catalogue is open. Each environment calls :func:`register` once, on import, with its
:class:`EnvironmentEntry` (the whole contract an environment fulfils, simulator included, is
:mod:`hivex_dsl.runtime.contract`). :func:`environments` imports, on first use, every environment there is:

- every package under ``hivex_dsl/envs/`` (the five HIVEX environments, and any folder dropped there);
- every entry point of the group ``hivex.environments`` (:data:`ENTRY_POINT_GROUP`) of the installed
  distributions, as Gymnasium finds its plugins: a lab ships its environment as a package of its own whose
  ``pyproject.toml`` says ``[project.entry-points."hivex.environments"] bees = "bees_env"`` (a module that
  registers on import, or ``"bees_env:ENTRY"``, an entry to register);
- the modules named in the environment variable ``HIVEX_ENVIRONMENTS`` (:data:`ENVIRONMENTS_VARIABLE`, names
  separated by commas), which is how one asks for an environment that is not installed, such as the tests'
  example environment.

Packages are imported by name with ``importlib``: the registry, in the compiler layer, has no import of the
environments layer above it, which imports the registry to register.
"""

from __future__ import annotations

import importlib
import os
import pkgutil
import warnings
from dataclasses import dataclass, field
from functools import cached_property
from importlib import metadata
from pathlib import Path
from typing import Any, Callable, Mapping

from ..base.errors import Problem, ScenarioError, did_you_mean
from ..base.resources import data_dir, resolve_scenario_path
from ..lang.loader import Loaded, load_file
from ..lang.spec.catalogue import LEVEL_FIELDS, PAPER_ENVIRONMENTS, EnvironmentInfo, listing_key
from ..lang.spec.common import StrictModel
from ..lang.spec.reward_table import RewardTable, table_problems
from ..lang.spec.scenario import ScenarioVocabulary, scenario_model
from ..lang.spec.validate import validate_loaded
from ..sim.reward.terms import TermRegistry
from ..sim.reward.vocabulary import Vocabulary, register_vocabulary
from ..sim.statistics import StatisticSet

ENVIRONMENTS_PACKAGE = f"{__name__.split('.')[0]}.envs"
ENTRY_POINT_GROUP = "hivex.environments"
ENVIRONMENTS_VARIABLE = "HIVEX_ENVIRONMENTS"

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


def _doc(text: str) -> dict[str, str]:
    """A field's description (``dataclasses.field(metadata=...)``), which the "Adding an environment" page lists."""
    return {"doc": " ".join(text.split())}


@dataclass(frozen=True, eq=False)
class EnvironmentEntry:
    """Everything the compiler, adapters, CLI and docs need to know about one environment."""

    info: EnvironmentInfo = field(metadata=_doc(
        "Identity (id, title, abbreviation, agent name), agent bounds, default episode length and difficulty "
        "axis (`level_field`: `pattern`, `terrain_level` or None)."))
    params_model: type[StrictModel] = field(metadata=_doc(
        "The pydantic model (a `StrictModel`) of the scenario's `params:`; every field bounded and described."))
    terms: TermRegistry = field(metadata=_doc(
        "The reward terms (`TermRegistry(<id>)`, one `@terms.term(...)` per term): "
        "`fn(prev, state, actions, params) -> (batch, agents) float64`, with its contract (range, sign, timing)."))
    make_simulator: Callable[[Compiled], Any] = field(metadata=_doc(
        "`make_simulator(compiled) -> Simulator`: the batched simulator of a compiled scenario (see `Simulator`)."))
    scripted_policy: Callable[[Compiled], Callable[[Any], Any]] = field(metadata=_doc(
        "`scripted_policy(compiled) -> act`, `act(observations (batch, agents, ...)) -> actions (batch, agents, "
        "...)`: a hand-written policy that `hivex run`, `hivex audit` and the tests run."))
    events: Mapping[str, str] = field(default_factory=dict, metadata=_doc(
        "Event name -> meaning: the `(batch, agents)` bool arrays of `StepOutcome.events`, which a task's "
        "`ends_on` may name."))
    world_events: frozenset[str] = field(default=frozenset(), metadata=_doc(
        "Events of the whole world (the fire went out): a task that ends on one ends every agent's episode of "
        "the world, where the other events (and `terminated`) end single agents' episodes."))
    level_names: tuple[str, ...] = field(default=(), metadata=_doc(
        "The names of the `pattern` levels (a scenario may give a pattern by name)."))
    level_titles: tuple[str, ...] = field(default=(), metadata=_doc("The titles of the `pattern` levels."))
    checks: tuple[ScenarioCheck, ...] = field(default=(), metadata=_doc(
        "Compile-time checks, `check(compiled) -> [(path in the file, message)]`: what the params model alone "
        "cannot say (the turbines fit the farm)."))
    notes: tuple[str, ...] = field(default=(), metadata=_doc(
        "How the paper was read where it is ambiguous; listed on the environment's docs page."))
    generators: Mapping[str, GeneratorSlot] = field(default_factory=dict, metadata=_doc(
        "Procedural generators a scenario may override under `generators:` (see `GeneratorSlot`)."))
    statistics: StatisticSet | None = field(default=None, metadata=_doc(
        "The per-episode statistics the environment logs (`StatisticSet(<id>, prefix)`); None: none."))
    quantities: Vocabulary | None = field(default=None, metadata=_doc(
        "The quantities expressions may read (`Vocabulary`: declared ranges and one reader each). None: "
        "`VOCABULARY` of the package's `vocabulary` module if it has one (the five HIVEX environments), else "
        "the reward table's terms and expressions read none."))
    content_dir: Path | None = field(default=None, metadata=_doc(
        "The folder holding the environment's reward table (`rewards.yaml`) and bundled scenarios "
        "(`scenarios/*.yaml`), usually `Path(__file__).parent`. None: the bundled content, "
        "`rewards/<id>.yaml` and `scenarios/<id>/` of the repository (the five HIVEX environments)."))
    state_facts: Callable[[Any, Any, Any], Mapping[str, Any]] | None = field(default=None, metadata=_doc(
        "For the test suite: `state_facts(simulator, state, params) -> {global-state component: values of "
        "world 0}`, some world facts computed straight from the state, independently of `world_state`, which "
        "the tests compare with the global state. None: the tests check the global state's layout and bounds "
        "only."))

    @property
    def id(self) -> str:
        return self.info.id

    @cached_property
    def reward_table(self) -> RewardTable:
        return load_reward_table(self)

    @property
    def reward_table_path(self) -> Path:
        """``rewards.yaml`` of :attr:`content_dir`, else the bundled ``rewards/<id>.yaml``."""
        return self.content_dir / "rewards.yaml" if self.content_dir else data_dir("rewards") / f"{self.id}.yaml"

    @property
    def scenario_dir(self) -> Path:
        """The folder of the environment's bundled scenarios."""
        return self.content_dir / "scenarios" if self.content_dir else data_dir("scenarios") / self.id

    def scenario_files(self) -> list[Path]:
        """The environment's bundled scenario files, sorted."""
        return sorted(self.scenario_dir.glob("*.yaml"))

    @cached_property
    def reward_table_file(self) -> Loaded:
        """The reward table as read, for locating problems of the table's expressions."""
        return load_file(self.reward_table_path)

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
                                  generators={name: slot.spec_model for name, slot in self.generators.items()},
                                  level_field_owners=level_field_owners())

    @cached_property
    def scenario_model(self) -> type[StrictModel]:
        return scenario_model(self.vocabulary)


def register(entry: EnvironmentEntry) -> EnvironmentEntry:
    """Add ``entry`` to the catalogue (an environment package calls this once, on import)."""
    if not isinstance(entry, EnvironmentEntry):
        raise TypeError(f"register() takes an EnvironmentEntry, got {type(entry).__name__}")
    problems = entry_problems(entry)
    if problems:
        raise ValueError(f"{entry.id}: " + "; ".join(problems))
    _REGISTRY[entry.id] = entry
    if entry.quantities is not None:
        register_vocabulary(entry.quantities)
    return entry


def entry_problems(entry: EnvironmentEntry) -> list[str]:
    """What keeps ``entry`` out of the catalogue (empty when it may register)."""
    problems = []
    if not entry.id.isidentifier() or entry.id != entry.id.lower() or entry.id.startswith("_"):
        problems.append("an environment id is a lower-case Python name (letters, digits, underscores)")
    if entry.id in _REGISTRY:
        problems.append(f"environment {entry.id!r} registered twice")
    if entry.id in PAPER_ENVIRONMENTS and entry.info != PAPER_ENVIRONMENTS[entry.id]:
        problems.append("its info differs from the paper's (lang.spec.catalogue.PAPER_ENVIRONMENTS)")
    if entry.info.level_field is not None and entry.info.level_field not in LEVEL_FIELDS:
        problems.append(f"level_field {entry.info.level_field!r} is not one of {', '.join(LEVEL_FIELDS)}")
    unknown = sorted(set(entry.world_events) - set(entry.events))
    if unknown:
        problems.append(f"world events {unknown} are not among its events {sorted(entry.events)}")
    if entry.terms.environment != entry.id:
        problems.append(f"its term registry belongs to {entry.terms.environment!r}")
    if entry.statistics is not None:
        problems += entry.statistics.problems(entry.terms.names)
        if entry.statistics.environment != entry.id:
            problems.append(f"its statistics belong to {entry.statistics.environment!r}")
    if entry.quantities is not None and entry.quantities.environment != entry.id:
        problems.append(f"its quantities belong to {entry.quantities.environment!r}")
    if entry.content_dir is not None and not (Path(entry.content_dir) / "rewards.yaml").is_file():
        problems.append(f"its content_dir {entry.content_dir} holds no rewards.yaml")
    return problems


def package_modules() -> list[str]:
    """The environment packages under hivex_dsl/envs/, by module name."""
    package = importlib.import_module(ENVIRONMENTS_PACKAGE)
    return [f"{ENVIRONMENTS_PACKAGE}.{module.name}" for module in pkgutil.iter_modules(package.__path__)
            if module.ispkg and not module.name.startswith("_")]


def asked_modules() -> list[str]:
    """The modules ``HIVEX_ENVIRONMENTS`` names."""
    return [name.strip() for name in os.environ.get(ENVIRONMENTS_VARIABLE, "").split(",") if name.strip()]


_discovered = False  # hivex_dsl/envs/ and the entry points are looked through once a process


def _load_all() -> None:
    """Import every environment package, entry point and asked-for module (each registers itself)."""
    global _discovered
    if not _discovered:
        for module in package_modules():
            importlib.import_module(module)
        for point in metadata.entry_points(group=ENTRY_POINT_GROUP):
            _load_entry_point(point)
        _discovered = True
    for module in asked_modules():  # read every time: a test or a session may ask for one later
        importlib.import_module(module)


def _load_entry_point(point: metadata.EntryPoint) -> None:
    """Load one plugin: a module registers on import, an EnvironmentEntry is registered here. A plugin that fails
    is named in a warning, as Gymnasium does, so one broken package does not take every environment down."""
    try:
        loaded = point.load()
    except Exception as exc:  # noqa: BLE001 - any error of someone else's package
        warnings.warn(f"environment plugin {point.name!r} ({point.value}) of group {ENTRY_POINT_GROUP} "
                      f"failed to load: {type(exc).__name__}: {exc}", RuntimeWarning, stacklevel=3)
        return
    if isinstance(loaded, EnvironmentEntry) and _REGISTRY.get(loaded.id) is not loaded:
        register(loaded)


def environments() -> dict[str, EnvironmentEntry]:
    """The available environments by id: the paper's five in the paper's order, then the others by id."""
    _load_all()
    return {env_id: _REGISTRY[env_id] for env_id in sorted(_REGISTRY, key=listing_key)}


def level_field_owners() -> dict[str, tuple[str, ...]]:
    """Level field -> ids of the available environments that have it."""
    return {name: tuple(env_id for env_id, entry in environments().items() if entry.info.level_field == name)
            for name in LEVEL_FIELDS}


def get(env_id: str) -> EnvironmentEntry:
    available = environments()
    if env_id in available:
        return available[env_id]
    if env_id in PAPER_ENVIRONMENTS:
        raise KeyError(f"environment '{env_id}' is part of HIVEX but not available in this version yet; "
                       f"available: {', '.join(available)}")
    raise KeyError(f"unknown environment '{env_id}'{did_you_mean(env_id, available)}; expected one of: "
                   f"{', '.join(available)}")


def resolve_scenario(text: str) -> Path:
    """A user's path as given if it exists, else the bundled scenario it names (``<env>/<name>[.yaml]``, also
    ``scenarios/<env>/<name>``), an environment's own content included."""
    path = resolve_scenario_path(text)
    if path.exists():
        return path
    parts = path.parts[1:] if path.parts[:1] == ("scenarios",) else path.parts
    if len(parts) == 2 and parts[0] in environments():
        candidate = environments()[parts[0]].scenario_dir / parts[1]
        for option in (candidate, candidate.with_suffix(".yaml")):
            if option.is_file():
                return option
    return path


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


__all__ = ["EnvironmentEntry", "GeneratorSlot", "register", "environments", "get", "resolve_scenario",
           "ENTRY_POINT_GROUP", "ENVIRONMENTS_VARIABLE"]
