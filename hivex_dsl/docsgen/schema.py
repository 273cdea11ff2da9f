"""The JSON Schema of the scenario language (docs/hivex.schema.json, `hivex schema`)."""

from __future__ import annotations

import json
from typing import Annotated, Any, Sequence, Union

from pydantic import BaseModel, Field, TypeAdapter

from ..compiler import registry

SCHEMA_DIALECT = "https://json-schema.org/draft/2020-12/schema"
SCHEMA_TITLE = "hivex-dsl scenario"


def schema_of(models: Sequence[type[BaseModel]]) -> dict[str, Any]:
    """One model's schema, or a union of several discriminated by their `environment` field."""
    if not models:
        raise ValueError("no environment is available, so there is no scenario schema")
    if len(models) == 1:
        schema = models[0].model_json_schema()
    else:
        union = Annotated[Union[tuple(models)], Field(discriminator="environment")]
        schema = TypeAdapter(union).json_schema()
    return {"$schema": SCHEMA_DIALECT, **schema, "title": SCHEMA_TITLE}


def scenario_json_schema() -> dict[str, Any]:
    """The schema of a scenario of any available environment."""
    return schema_of([entry.scenario_model for entry in registry.environments().values()])


def schema_text() -> str:
    """The schema serialised exactly as docs/hivex.schema.json holds it."""
    return json.dumps(scenario_json_schema(), indent=2, sort_keys=True) + "\n"
