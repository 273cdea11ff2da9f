"""Models of what a task author writes in YAML instead of Python: expression terms, shaping, schedules.

A scenario (or a reward table) declares ``terms:`` (name -> expression and an optional contract),
``shaping:`` (a potential and a discount) and extra ``ends_on:`` entries; a weight may be a
:class:`WeightSchedule`. The expressions themselves are checked by :mod:`hivex_dsl.lang.expr` when the
scenario compiles (see :mod:`hivex_dsl.sim.reward.expressions`); these models check the shape around them.
"""

from __future__ import annotations

import math
from typing import Annotated, Any, Literal, Optional, Union

from pydantic import (BeforeValidator, Field, PlainValidator, ValidationError, WithJsonSchema, field_validator,
                      model_validator)

from ...base.errors import ItemValueError, got, show
from .common import MAX_WEIGHT, StrictModel

SNAKE = r"^[a-z][a-z0-9_]*$"
MAX_EXPRESSION_CHARS = 2_000
MAX_SCHEDULE_STEPS = 10**12

Expression = Annotated[str, Field(min_length=1, max_length=MAX_EXPRESSION_CHARS)]


class ExpressionTermSpec(StrictModel):
    """A reward term written as an expression over the environment's vocabulary.

    The contract fields left out are inferred: the range from the vocabulary's ranges by interval
    arithmetic, the sign from the range, the scope from the expression's shape (per agent: agent,
    per world: global); timing defaults to dense. A declared range must contain the inferred one.
    """

    expr: Expression = Field(description=(
        "The term's value each step: a number per agent or per world. `name: EXPR` is short for `name: {expr: EXPR}`."))
    title: str = Field("", max_length=120, description="A title for the docs; the name in words when empty.")
    description: str = Field("", max_length=2000, description="What the term rewards, for people.")
    range: Optional[tuple[float, float]] = Field(None, description=(
        "[low, high] every value lies in; inferred from the vocabulary when left out, checked when given."))
    sign: Optional[Literal["bonus", "penalty", "mixed"]] = Field(None, description="Inferred from the range when left out.")
    timing: Literal["dense", "event", "terminal"] = Field("dense", description="When the term pays (documentation).")
    scope: Optional[Literal["agent", "team", "global"]] = Field(None, description=(
        "Inferred when left out: agent for a per-agent expression, global for a per-world one."))

    @model_validator(mode="before")
    @classmethod
    def _shorthand(cls, value):
        """``name: EXPR`` is short for ``name: {expr: EXPR}``."""
        return {"expr": value} if isinstance(value, str) else value

    @field_validator("range", mode="before")
    @classmethod
    def _list_to_tuple(cls, value):
        if isinstance(value, list):
            if len(value) != 2:
                raise ValueError(f"expected [low, high], two numbers, got {len(value)} values")
            return tuple(value)
        return value

    @field_validator("range")
    @classmethod
    def _ordered(cls, value):
        if value is not None and not value[0] <= value[1]:
            raise ValueError(f"[{value[0]:g}, {value[1]:g}] is empty: expected low <= high")
        return value


class ShapingSpec(StrictModel):
    """Potential-based shaping (Ng, Harada and Russell, 1999): gamma * phi(s') - phi(s), its own term."""

    potential: Expression = Field(description="phi(s): a number per agent or per world, without prev() or delta().")
    gamma: float = Field(0.99, ge=0.0, le=1.0, description="The discount of the learner; F = gamma * phi(s') - phi(s).")
    name: str = Field("shaping", pattern=SNAKE, max_length=60, description="The reported term's name.")
    title: str = Field("Potential-based shaping", max_length=120, description="A title for the docs.")


class WeightSchedule(StrictModel):
    """A weight that moves from ``from`` to ``to`` over ``over_steps`` environment steps.

    linear: from + (to - from) * min(1, steps / over_steps); step: from until over_steps, then to.
    ``steps`` is the environment-step clock of the env (see BatchedEnv.env_steps): physics steps of all worlds
    together, k per world and decision with a scenario's ``decision_period`` k.
    """

    start: float = Field(alias="from", ge=-MAX_WEIGHT, le=MAX_WEIGHT, description="The weight at step 0.")
    end: float = Field(alias="to", ge=-MAX_WEIGHT, le=MAX_WEIGHT, description="The weight from over_steps on.")
    over_steps: int = Field(ge=1, le=MAX_SCHEDULE_STEPS, description="Environment steps the change takes.")
    kind: Literal["linear", "step"] = Field("linear", description="linear ramp, or one step at over_steps.")

    def at(self, steps: int) -> float:
        """The weight after ``steps`` environment steps."""
        if self.kind == "step":
            return self.end if steps >= self.over_steps else self.start
        share = min(1.0, max(0, steps) / self.over_steps)
        return self.start + (self.end - self.start) * share

    def as_dict(self) -> dict[str, Any]:
        return {"from": self.start, "to": self.end, "over_steps": self.over_steps, "kind": self.kind}


def _check_weight(value: Any) -> Union[float, WeightSchedule, None]:
    if value is None:
        return None
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        if not math.isfinite(value):
            raise ValueError(f"{show(value)} is not allowed: expected a finite number")
        if abs(value) > MAX_WEIGHT:
            raise ValueError(f"{show(value)} is out of range: expected a number from {-MAX_WEIGHT} to {MAX_WEIGHT}")
        return float(value)
    if isinstance(value, dict) and set(value) & {"from", "to", "over_steps"}:  # meant as a schedule
        try:
            return WeightSchedule.model_validate(value)
        except ValidationError as exc:
            errors = exc.errors(include_url=False)
            first = next((e for e in errors if e["type"] == "extra_forbidden"), errors[0])  # a misspelt key first
            at = tuple(first["loc"][:1])
            if first["type"] == "extra_forbidden":
                raise ItemValueError(f"unknown key '{at[0]}' in a schedule; expected from, to, over_steps, kind", at) from None
            if first["type"] == "missing":
                raise ValueError(f"a schedule needs '{at[0]}' (from, to, over_steps and optionally kind)") from None
            cause = (first.get("ctx") or {}).get("error") or f"{first['msg'][:1].lower()}{first['msg'][1:]}"
            raise ItemValueError(f"{show(first.get('input'))} is not allowed: {cause}", at) from None
    raise ValueError(f"expected a weight (a number) or a schedule {{from, to, over_steps, kind}}, got {got(value)}")


WEIGHT_SCHEMA = {"anyOf": [{"type": "number", "minimum": -MAX_WEIGHT, "maximum": MAX_WEIGHT},
                           WeightSchedule.model_json_schema(by_alias=True), {"type": "null"}]}
Weight = Annotated[Optional[Union[float, WeightSchedule]], PlainValidator(_check_weight), WithJsonSchema(WEIGHT_SCHEMA)]

_TERM_SCHEMA = {"anyOf": [{"type": "string", "minLength": 1, "maxLength": MAX_EXPRESSION_CHARS},
                          ExpressionTermSpec.model_json_schema()]}
TermsMapping = Optional[dict[Annotated[str, Field(pattern=SNAKE, max_length=60)],
                             Annotated[ExpressionTermSpec, WithJsonSchema(_TERM_SCHEMA)]]]
EndsOn = Annotated[tuple[Expression, ...], BeforeValidator(lambda v: tuple(v) if isinstance(v, list) else v)]
