"""Base model and shared field types of the scenario language."""

from __future__ import annotations

from typing import Any, ClassVar

from pydantic import BaseModel, ConfigDict

SCHEMA_VERSION = 1
NAME_PATTERN = r"^[A-Za-z0-9][A-Za-z0-9_.\-\[\]=,]*$"
NAME_EXPECTED = "a name made of letters, digits and the characters '_.-[]=,', starting with a letter or digit"
MAX_WEIGHT = 1.0e6
MAX_SEED = 2**32 - 1


class StrictModel(BaseModel):
    """Frozen, closed, strictly typed: nothing a user wrote is coerced or dropped.

    ``strict`` means ``agents: "8"`` is an error, not an 8; ``extra="forbid"`` means a
    misspelt key is an error, not ignored; ``frozen`` means a validated config never changes.
    """

    model_config = ConfigDict(
        extra="forbid",
        frozen=True,
        strict=True,
        allow_inf_nan=False,
        validate_default=True,
        use_attribute_docstrings=False,
    )
    # params added after scenarios were locked or trained, each with the value that does what was done before it,
    # where the default does otherwise: a resolved scenario written without one (a lock's, a checkpoint's) is read
    # with that value, and the fingerprint leaves the field out while it holds it, so such a scenario keeps its
    # fingerprint (hivex_dsl.compiler.locks.as_written). Fields whose default does what was done before need no
    # entry: a model's LATE_FIELDS leave them out of its fingerprint at their defaults.
    ADDED_FIELDS: ClassVar[dict[str, Any]] = {}
