"""Pydantic models -> rows of documentation tables (type, bounds, default, description).

Types are read from the model's own JSON Schema (what a YAML language server sees), bounds from
the fields' metadata (ge/gt/le/lt, lengths, patterns), so the tables cannot drift from the models.
"""

from __future__ import annotations

from typing import Any

from pydantic import BaseModel
from pydantic_core import PydanticUndefined


def num(value: Any) -> str:
    """One number format for every page: ints as written, floats with up to 12 significant digits."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        text = format(value, ".12g")
        return "-0" if text == "-0" else text
    raise TypeError(f"not a number: {value!r}")


def show_value(value: Any) -> str:
    """A default or setting as it would be written in YAML."""
    if value is None:
        return "null"
    if isinstance(value, (bool, int, float)):
        return num(value)
    if isinstance(value, str):
        return f'"{value}"' if value == "" or not value.replace("_", "").replace("-", "").isalnum() else value
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(show_value(v) for v in value) + "]"
    if isinstance(value, dict):
        return "{" + ", ".join(f"{k}: {show_value(v)}" for k, v in value.items()) + "}"
    raise TypeError(f"cannot show {type(value).__name__} in the docs")


def bounds(metadata: list[Any]) -> str:
    """Interval notation from ge/gt/le/lt (``[0, 1)``), plus length and pattern limits."""
    low = high = None
    parts: list[str] = []
    for item in metadata:
        for attr, side in (("ge", "["), ("gt", "(")):
            if getattr(item, attr, None) is not None:
                low = (side, getattr(item, attr))
        for attr, side in (("le", "]"), ("lt", ")")):
            if getattr(item, attr, None) is not None:
                high = (side, getattr(item, attr))
    if low and high:
        parts.append(f"{low[0]}{num(low[1])}, {num(high[1])}{high[0]}")
    elif low:
        parts.append(f"{'≥' if low[0] == '[' else '>'} {num(low[1])}")
    elif high:
        parts.append(f"{'≤' if high[0] == ']' else '<'} {num(high[1])}")
    min_len = next((m.min_length for m in metadata if getattr(m, "min_length", None) is not None), None)
    max_len = next((m.max_length for m in metadata if getattr(m, "max_length", None) is not None), None)
    if min_len is not None and max_len is not None:
        parts.append(f"length {min_len} to {max_len}")
    elif max_len is not None:
        parts.append(f"length ≤ {max_len}")
    elif min_len is not None:
        parts.append(f"length ≥ {min_len}")
    pattern = next((m.pattern for m in metadata if getattr(m, "pattern", None)), None)
    if pattern:
        parts.append(f"matches `{pattern}`")
    return "; ".join(parts)


def schema_type(schema: dict[str, Any], defs: dict[str, Any], nested: bool = False) -> str:
    """A short English rendering of a JSON Schema type.

    Integer ranges are spelled out only inside unions and lists (a field's own range is in its bounds).
    """
    if "$ref" in schema:
        name = schema["$ref"].rsplit("/", 1)[-1]
        return f"mapping ({defs[name].get('title', name)})"
    if "const" in schema:
        return f"`{show_value(schema['const'])}`"
    if "enum" in schema:
        return "one of " + ", ".join(f"`{show_value(v)}`" for v in schema["enum"])
    if "anyOf" in schema:
        options = [schema_type(option, defs, nested=True) for option in schema["anyOf"]]
        text = ", ".join(options[:-1]) + " or " + options[-1] if len(options) > 1 else options[0]
        return f"({text})" if nested and len(options) > 1 else text
    kind = schema.get("type")
    if kind == "integer" and nested and "minimum" in schema and "maximum" in schema:
        return f"integer {num(schema['minimum'])} to {num(schema['maximum'])}"
    if kind == "array":
        items = schema.get("items")
        return f"list of {schema_type(items, defs, nested=True)}" if items else "list"
    if kind == "object" and isinstance(schema.get("additionalProperties"), dict):
        return f"mapping of name to {schema_type(schema['additionalProperties'], defs, nested=True)}"
    return {"integer": "integer", "number": "number", "string": "string", "boolean": "boolean",
            "object": "mapping", "null": "null"}.get(kind, "any")


def default_text(field: Any) -> str:
    if field.is_required():
        return "required"
    if field.default_factory is not None:
        made = field.default_factory()
        if isinstance(made, BaseModel):
            return "see below"
        return show_value(made)
    if field.default is PydanticUndefined:
        return "required"
    return show_value(field.default)


def field_rows(model: type[BaseModel]) -> list[dict[str, str]]:
    """One row per field of ``model``, in declaration order."""
    schema = model.model_json_schema()
    defs = schema.get("$defs", {})
    properties = schema.get("properties", {})
    rows = []
    for name, field in model.model_fields.items():
        rows.append({
            "name": name,
            "type": schema_type(properties.get(name, {}), defs),
            "bounds": bounds(list(field.metadata)),
            "default": default_text(field),
            "description": field.description or "",
        })
    return rows


def source_tag(description: str) -> tuple[str, str]:
    """``"[paper] text"`` -> ``("paper", "text")``; untagged descriptions give ``("", text)``."""
    if description.startswith("[") and "]" in description:
        tag, _, rest = description[1:].partition("]")
        return tag, rest.strip()
    return "", description
