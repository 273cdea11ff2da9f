"""Base model and shared field types of the scenario language."""

from __future__ import annotations

from typing import Any, ClassVar

from pydantic import BaseModel, ConfigDict

SCHEMA_VERSION = 1
NAME_PATTERN = r"^[A-Za-z0-9][A-Za-z0-9_.\-\[\]=,]*$"
NAME_EXPECTED = "a name made of letters, digits and the characters '_.-[]=,', starting with a letter or digit"
MAX_WEIGHT = 1.0e6
MAX_SEED = 2**32 - 1


class _AsDefault:
    """The earlier value of an added field that its default already does (StrictModel.ADDED_FIELDS)."""

    def __repr__(self) -> str:
        return "AS_DEFAULT"


AS_DEFAULT = _AsDefault()


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
    # Params added after scenarios were locked or trained, each with the value that does what was done before it
    # (AS_DEFAULT where the default does; write the value out before changing such a default, or older locks and
    # checkpoints would play the new one). A resolved scenario written without one (a lock's, a checkpoint's) is read
    # with that value (hivex_dsl.compiler.locks.as_written), and the fingerprint leaves the field out while it holds
    # it, so a scenario file that does what it did before keeps its fingerprint and the records trained on it stay
    # matched to it. A model's entries add to its bases' (added_fields).
    ADDED_FIELDS: ClassVar[dict[str, Any]] = {}

    @classmethod
    def added_fields(cls) -> dict[str, Any]:
        """Every added field of this model and its bases -> the JSON value that does what was done before it."""
        merged: dict[str, Any] = {}
        for klass in reversed(cls.__mro__):
            merged.update(vars(klass).get("ADDED_FIELDS", {}))
        return {name: cls.model_fields[name].default if before is AS_DEFAULT else before
                for name, before in merged.items()}
