"""The scenario model, built per environment so every bound and name is that environment's own.

One factory, :func:`scenario_model`, makes the model for any environment from its catalogue
entry, params model, task names, reward-term names and level names; the JSON Schema that a YAML
language server uses for completion comes from the same models.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Annotated, Any, Literal, Mapping, Optional, Union

from pydantic import ConfigDict, Field, PlainValidator, WithJsonSchema, create_model

from ...base.errors import ItemValueError, did_you_mean, got, one_of, show
from .catalogue import LEVEL_FIELDS, EnvironmentInfo
from .common import MAX_SEED, NAME_EXPECTED, NAME_PATTERN, SCHEMA_VERSION, StrictModel
from .expressions import WEIGHT_SCHEMA, EndsOn, ShapingSpec, TermsMapping, Weight

MAX_SEEDS_PER_SPLIT = 10_000
TERRAIN_LEVELS = (1, 10)
MAX_EPISODE_LENGTH = 1_000_000
MAX_DECISION_PERIOD = 100
DECISION_PERIOD_DESCRIPTION = (
    "Physics steps per decision, as ML-Agents' DecisionRequester's DecisionPeriod: the policy acts on every "
    "k-th step, its action is held in between, the rewards and term values of the k steps are summed into the "
    "decision's, and an agent whose episode ends inside the period ends on that decision. episode_length stays "
    "in physics steps and must be a multiple of it (an episode holds episode_length / decision_period "
    "decisions); every step budget of training (max_steps, --steps, checkpoints, curves) counts decisions. "
    "prev(), delta(), weight schedules and statistics tick per physics step. The default is the "
    "environment's own, what the original's Episode Length panels show (its reward table's notes).")

# Fields a sweep may range over; "params.<name>", "weights.<term>" and "seeds.<split>" too.
SWEEPABLE_FIELDS = ("task", "pattern", "terrain_level", "agents", "episode_length", "decision_period")
SWEEPABLE_PREFIXES = ("params", "weights", "seeds")


@dataclass(frozen=True)
class ScenarioVocabulary:
    """What the model needs to know about one environment, as plain names."""

    info: EnvironmentInfo
    params_model: type[StrictModel]
    task_names: tuple[str, ...]
    term_names: tuple[str, ...]
    level_names: tuple[str, ...] = ()
    generators: Mapping[str, type[StrictModel]] = field(default_factory=dict)
    # level field -> ids of the environments that have it (for the hint on a level field this one lacks)
    level_field_owners: Mapping[str, tuple[str, ...]] = field(default_factory=dict)


def _is_int(value: Any) -> bool:
    return isinstance(value, int) and not isinstance(value, bool)


def _check_seed(value: Any, at: tuple = ()) -> int:
    if not _is_int(value):
        raise ItemValueError(f"expected a seed (an integer from 0 to {MAX_SEED}), got {got(value)}", at)
    if not 0 <= value <= MAX_SEED:
        raise ItemValueError(f"{value} is out of range: expected a seed, an integer from 0 to {MAX_SEED}", at)
    return value


def _check_seed_set(value: Any) -> Union[int, tuple[int, ...]]:
    if isinstance(value, (list, tuple)):
        if not 1 <= len(value) <= MAX_SEEDS_PER_SPLIT:
            raise ValueError(f"expected 1 to {MAX_SEEDS_PER_SPLIT} seeds, got {len(value)}")
        seeds = tuple(_check_seed(v, (i,)) for i, v in enumerate(value))
        first: dict[int, int] = {}
        for i, seed in enumerate(seeds):
            if seed in first:
                raise ItemValueError(f"seed {seed} is listed twice (first at [{first[seed]}]); list each seed once", (i,))
            first[seed] = i
        return seeds
    if not _is_int(value):
        raise ValueError(f"expected a seed (an integer from 0 to {MAX_SEED}) or a list of seeds, got {got(value)}")
    return _check_seed(value)


SEED_SET_SCHEMA = {
    "anyOf": [
        {"type": "integer", "minimum": 0, "maximum": MAX_SEED},
        {"type": "array", "items": {"type": "integer", "minimum": 0, "maximum": MAX_SEED},
         "minItems": 1, "maxItems": MAX_SEEDS_PER_SPLIT, "uniqueItems": True},
    ]
}
SeedSet = Annotated[Union[int, tuple[int, ...]], PlainValidator(_check_seed_set), WithJsonSchema(SEED_SET_SCHEMA)]


class Seeds(StrictModel):
    """Seeds of the train and test splits (the paper trains on 5000 and tests on 6000).

    A single integer seeds one random stream that successive episodes continue; a list gives
    each episode its own seed in turn. The two splits may not share a seed.
    """

    train: SeedSet = Field(5000, description="Seed (or list of per-episode seeds) of the training split.")
    test: SeedSet = Field(6000, description="Seed (or list of per-episode seeds) of the test split; disjoint from train.")

    def overlap(self) -> list[int]:
        as_set = lambda s: {s} if isinstance(s, int) else set(s)  # noqa: E731
        return sorted(as_set(self.train) & as_set(self.test))


def _name_or_index(what: str, names: tuple[str, ...], index_base: int = 0):
    """A validator taking one of ``names`` or its index (``index_base`` .. ``index_base + n - 1``)."""
    listing = ", ".join(f"{i + index_base} '{n}'" for i, n in enumerate(names))

    def check(value: Any) -> Union[int, str]:
        if isinstance(value, str) and value in names:
            return value
        if _is_int(value) and index_base <= value < index_base + len(names):
            return value
        if isinstance(value, str):
            raise ValueError(f"unknown {what} {show(value)}{did_you_mean(value, names)}; expected a name or index: {listing}")
        if _is_int(value):
            raise ValueError(f"{value} is out of range: expected a name or index: {listing}")
        raise ValueError(f"expected a {what} name or index ({listing}), got {got(value)}")

    schema = {"anyOf": [{"enum": list(names)},
                        {"type": "integer", "minimum": index_base, "maximum": index_base + len(names) - 1}],
              "description": f"A {what}: {listing}."}
    return Annotated[Union[int, str], PlainValidator(check), WithJsonSchema(schema)]


class _Weights(StrictModel):
    """Closed for the compiler (it knows the scenario's own terms); open to a scenario's `terms:` in the schema."""

    model_config = ConfigDict(json_schema_extra={"additionalProperties": WEIGHT_SCHEMA})


def weights_model(env_id: str, term_names: tuple[str, ...]) -> type[StrictModel]:
    """A closed mapping term name -> optional weight, so unknown terms are located errors."""
    fields = {name: (Weight, Field(None, description=(
                  f"Weight of the '{name}' reward term (a number, or a schedule over environment steps); "
                  "overrides the task column.")))
              for name in term_names}
    model = create_model(f"{_camel(env_id)}Weights", __base__=_Weights, **fields)
    model.__hivex_key_noun__ = "reward term"  # 'unknown reward term ...' in error messages
    return model


def partial_model(model: type[StrictModel], name: str) -> type[StrictModel]:
    """``model`` with every field optional (default None) but keeping its type, bounds and description.

    A scenario's ``generators.<slot>`` names only the fields it changes; the compiler merges
    them over the preset and validates the whole spec again (cross-field rules included).
    """
    fields = {}
    for key, info in model.model_fields.items():
        kind = Annotated[tuple([Optional[info.annotation]] + list(info.metadata))] if info.metadata else Optional[info.annotation]
        fields[key] = (kind, Field(None, description=info.description))
    return create_model(name, __base__=StrictModel, __doc__=model.__doc__, **fields)


def generators_model(env_id: str, slots: Mapping[str, type[StrictModel]]) -> type[StrictModel]:
    """A closed mapping generator slot -> partial spec, so unknown slots and fields are located errors."""
    fields = {}
    for name, spec in slots.items():
        partial = partial_model(spec, f"{_camel(env_id)}{_camel(name)}Override")
        fields[name] = (partial, Field(default_factory=partial, description=(
            f"Fields of the '{name}' generator to change; the rest keep the preset's value for the scenario's level.")))
    model = create_model(f"{_camel(env_id)}Generators", __base__=StrictModel, **fields)
    model.__hivex_key_noun__ = "generator"
    return model


def scenario_model(vocab: ScenarioVocabulary) -> type[StrictModel]:
    """The pydantic model of a scenario for one environment."""
    info = vocab.info
    weights = weights_model(info.id, vocab.term_names)
    fields: dict[str, Any] = {
        "hivex": (Literal[SCHEMA_VERSION], Field(description="Version of the scenario language this file is written in.")),
        "name": (str, Field("scenario", pattern=NAME_PATTERN, max_length=200,
                            description="Short identifier used in logs, lock files and sweep point names.",
                            json_schema_extra={"x-expected": NAME_EXPECTED})),
        "description": (str, Field("", max_length=4000, description="Free text for people; ignored by the compiler.")),
        "environment": (Literal[info.id], Field(description=f"The environment: {info.title} ({info.abbreviation}).")),
        "task": (_name_or_index("task", vocab.task_names), Field(vocab.task_names[0],
                 description="A column of the environment's reward table, by name or the paper's 0-based task index.")),
    }
    if info.level_field == "pattern":
        fields["pattern"] = (_name_or_index("pattern", vocab.level_names), Field(0,
                             description="Turbine layout pattern, by name or the paper's index 0-8."))
    if info.level_field == "terrain_level":
        fields["terrain_level"] = (int, Field(1, ge=TERRAIN_LEVELS[0], le=TERRAIN_LEVELS[1],
                                   description="Terrain elevation level 1 (flat) to 10 (steepest)."))
    fields |= {
        "agents": (int, Field(info.default_agents, ge=info.min_agents, le=info.max_agents,
                              description=f"Number of {info.agent_name}s.")),
        "episode_length": (int, Field(info.default_episode_length, ge=1, le=MAX_EPISODE_LENGTH,
                                      description="Physics steps before an episode is truncated "
                                                  "(ML-Agents' MaxStep).")),
        "decision_period": (int, Field(info.default_decision_period, ge=1, le=MAX_DECISION_PERIOD,
                                       description=DECISION_PERIOD_DESCRIPTION)),
        "seeds": (Seeds, Field(default_factory=Seeds, description="Seeds of the train and test splits.")),
        "weights": (weights, Field(default_factory=weights,
                    description="Overrides of single cells of the task's reward column.")),
        "params": (vocab.params_model, Field(default_factory=vocab.params_model,
                   description="Physical constants of the simulator; each is bounded and documented.")),
        "terms": (TermsMapping, Field(None, description=(
            "New reward terms written as expressions over the environment's vocabulary (name -> {expr, ...}); "
            "weight them in `weights:`."))),
        "shaping": (Optional[ShapingSpec], Field(None, description=(
            "Potential-based shaping {potential, gamma}: gamma * phi(s') - phi(s), reported as its own term."))),
        "ends_on": (EndsOn, Field((), description=(
            "More endings besides the task's: event names or boolean expressions over the vocabulary."))),
    }
    if vocab.generators:
        generators = generators_model(info.id, vocab.generators)
        fields["generators"] = (generators, Field(default_factory=generators, description=(
            "Overrides of procedural generator fields (terrain, forest, weather ...); see the generators reference.")))
    fields |= {
        "sweep": (Optional[dict[str, list[Union[int, float, str]]]], Field(None, description=(
            "A grid: each key names a scalar field (task, agents, params.<name>, weights.<term> ...) and lists "
            "its values; the file compiles to one scenario per combination."),
            json_schema_extra={"propertyNames": {"anyOf": [{"enum": list(sweepable_fields(vocab))},
                                                            {"pattern": r"^(params|weights|seeds)\.[a-z_]+$"}]}})),
    }
    model = create_model(f"{_camel(info.id)}Scenario", __base__=StrictModel, **fields)
    model.__hivex_unknown_key_hint__ = staticmethod(_level_field_hint(vocab))
    return model


def sweepable_fields(vocab: ScenarioVocabulary) -> tuple[str, ...]:
    level = {"pattern", "terrain_level"} - ({vocab.info.level_field} if vocab.info.level_field else set())
    return tuple(f for f in SWEEPABLE_FIELDS if f not in level)


def _level_field_hint(vocab: ScenarioVocabulary):
    info = vocab.info

    def hint(key: str, parent: tuple) -> str | None:
        if not parent and key == "generators":  # only a model without the field gets here
            return f"unknown key 'generators': {info.id} builds its world without procedural generators"
        if parent or key not in LEVEL_FIELDS:
            return None
        owners = list(vocab.level_field_owners.get(key, ()))
        uses = f"; {info.id} uses '{info.level_field}'" if info.level_field else f"; {info.id} has no difficulty levels"
        having = f"only {one_of(owners)} have it" if owners else "no environment has it"
        return f"'{key}' does not apply to {info.id}: {having}{uses}"

    return hint


def _camel(env_id: str) -> str:
    return "".join(part.capitalize() for part in env_id.split("_"))
