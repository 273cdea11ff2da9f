"""Validate plain data against a model and turn pydantic's errors into located, readable problems."""

from __future__ import annotations

import types
import typing
from typing import Any, Callable, Literal, Sequence, TypeVar, Union

import annotated_types as at
from pydantic import BaseModel, ValidationError
from pydantic.fields import FieldInfo

from ...base.errors import ItemValueError, Location, Problem, ScenarioError, did_you_mean, got, one_of, show
from ..loader import Loaded, PathKey

M = TypeVar("M", bound=BaseModel)
Locate = Callable[[PathKey, bool], Location]


def validate_model(model: type[M], data: Any, locate: Locate, context: dict | None = None) -> M:
    """``model.model_validate(data)`` or a :class:`ScenarioError` naming every problem's place."""
    try:
        return model.model_validate(data, context=context)
    except ValidationError as exc:
        raise ScenarioError(problems_from(exc, model, locate, data)) from None


def validate_loaded(model: type[M], loaded: "Loaded", context: dict | None = None) -> M:
    """Validate a whole loaded file, locating problems in it."""
    return validate_model(model, loaded.data, lambda path, key=False: loaded.locate(path, key=key), context)


def problems_from(exc: ValidationError, model: type[BaseModel], locate: Locate, data: Any = None) -> list[Problem]:
    problems = []
    for err in exc.errors(include_url=False):
        loc = _user_loc(err["loc"], data)
        cause = (err.get("ctx") or {}).get("error")
        if isinstance(cause, ItemValueError):
            loc += cause.at
        message, at_key = describe(err, loc, model)
        problems.append(Problem(locate(loc, at_key), message))
    return _dedupe(problems)


def describe(err: dict, loc: PathKey, model: type[BaseModel]) -> tuple[str, bool]:
    """(message, whether it points at the key rather than the value)."""
    kind, value = err["type"], err.get("input")
    where = dotted(loc)
    if kind == "extra_forbidden":
        return _unknown_key(loc, model), True
    if kind == "missing":
        parent = f" in '{dotted(loc[:-1])}'" if len(loc) > 1 else ""
        return f"missing required key '{loc[-1]}'{parent}", False
    if kind in ("value_error", "assertion_error"):
        return f"{where}: {err['ctx']['error']}", False
    field = field_at(model, loc)
    expected = expected_of(field) if field is not None else None
    if kind in ("greater_than", "greater_than_equal", "less_than", "less_than_equal"):
        return f"{where}: {show(value)} is out of range: expected {expected}", False
    if kind == "literal_error":
        return f"{where}: {show(value)} is not allowed: expected {err['ctx']['expected']}", False
    if kind in ("finite_number",):
        return f"{where}: {show(value)} is not allowed: expected a finite number", False
    if kind == "string_pattern_mismatch":
        wanted = expected if expected and expected != "a string" else f"a string matching {err['ctx']['pattern']}"
        return f"{where}: {show(value)} is not allowed: expected {wanted}", False
    if kind in ("string_too_long", "string_too_short", "too_long", "too_short"):
        return f"{where}: {show(value)} is not allowed: {err['msg'][:1].lower()}{err['msg'][1:]}", False
    if expected:
        return f"{where}: expected {expected}, got {got(value)}", False
    return f"{where}: {err['msg']}", False


def _unknown_key(loc: PathKey, model: type[BaseModel]) -> str:
    key, parent = loc[-1], loc[:-1]
    allowed = field_names(model, parent)
    place = f" in '{dotted(parent)}'" if parent else ""
    hint = getattr(model, "__hivex_unknown_key_hint__", None)
    special = hint(key, parent) if hint else None
    if special:
        return special
    listing = f"; expected one of: {', '.join(allowed)}" if allowed else ""
    target = model if not parent else _model_of(field_at(model, parent))
    noun = getattr(target, "__hivex_key_noun__", "key")
    return f"unknown {noun} '{key}'{place}{did_you_mean(key, allowed)}{listing}"


def dotted(loc: PathKey) -> str:
    text = ""
    for part in loc:
        text += f"[{part}]" if isinstance(part, int) else (f".{part}" if text else str(part))
    return text or "(top level)"


def field_names(model: type[BaseModel], loc: PathKey) -> list[str]:
    """The keys allowed in the mapping at ``loc`` (empty when it is not a model)."""
    target = model if not loc else _model_of(field_at(model, loc))
    return list(target.model_fields) if target is not None else []


def field_at(model: type[BaseModel], loc: PathKey) -> FieldInfo | None:
    """The FieldInfo reached by following ``loc`` through nested models, list items skipped."""
    current: type[BaseModel] | None = model
    field = None
    for part in loc:
        if isinstance(part, int):
            continue
        if current is None or part not in current.model_fields:
            return None
        field = current.model_fields[part]
        current = _model_of(field)
    return field


def _model_of(field: FieldInfo | None) -> type[BaseModel] | None:
    if field is None:
        return None
    for candidate in _flatten(field.annotation):
        if isinstance(candidate, type) and issubclass(candidate, BaseModel):
            return candidate
    return None


def expected_of(field: FieldInfo) -> str | None:
    """'an integer from 1 to 16', 'a number >= 0', "'a' or 'b'" ... from the annotation and bounds."""
    custom = (field.json_schema_extra or {}).get("x-expected") if isinstance(field.json_schema_extra, dict) else None
    if custom:
        return str(custom)
    kinds = [_kind_name(t) for t in _flatten(field.annotation) if t is not type(None)]
    kinds = [k for k in kinds if k]
    if not kinds:
        return None
    base = " or ".join(dict.fromkeys(kinds))
    low = high = None
    for meta in field.metadata:
        if isinstance(meta, (at.Ge, at.Gt)):
            low = (meta.ge if isinstance(meta, at.Ge) else meta.gt, isinstance(meta, at.Ge))
        if isinstance(meta, (at.Le, at.Lt)):
            high = (meta.le if isinstance(meta, at.Le) else meta.lt, isinstance(meta, at.Le))
    if low and high and low[1] and high[1]:
        return f"{base} from {low[0]} to {high[0]}"
    bounds = []
    if low:
        bounds.append(f"{'>=' if low[1] else '>'} {low[0]}")
    if high:
        bounds.append(f"{'<=' if high[1] else '<'} {high[0]}")
    return base + (" " + " and ".join(bounds) if bounds else "")


def _kind_name(annotation: Any) -> str | None:
    origin = typing.get_origin(annotation)
    if origin is Literal:
        return one_of(typing.get_args(annotation))
    if annotation is bool:
        return "true or false"
    if annotation is int:
        return "an integer"
    if annotation is float:
        return "a number"
    if annotation is str:
        return "a string"
    if origin in (list, tuple) or annotation in (list, tuple):
        return "a list"
    if origin is dict or annotation is dict or (isinstance(annotation, type) and issubclass(annotation, BaseModel)):
        return "a mapping"
    return None


def _flatten(annotation: Any) -> list[Any]:
    origin = typing.get_origin(annotation)
    if origin is typing.Annotated:
        return _flatten(typing.get_args(annotation)[0])
    if origin in (Union, types.UnionType):
        return [leaf for arg in typing.get_args(annotation) for leaf in _flatten(arg)]
    return [annotation]


def _user_loc(loc: tuple, data: Any) -> PathKey:
    """pydantic's error location with union member tags dropped; the user's own keys are always kept."""
    path: list = []
    for part in loc:
        if isinstance(data, dict) and part in data:
            data = data[part]
        elif isinstance(data, (list, tuple)) and isinstance(part, int) and 0 <= part < len(data):
            data = data[part]
        elif _is_union_tag(part):
            continue
        else:
            data = None
        path.append(part)
    return tuple(path)


def _is_union_tag(part: Any) -> bool:
    """pydantic inserts member names such as 'int' or 'list[int]' into union error locations."""
    return isinstance(part, str) and (part in ("int", "float", "str", "bool") or ("[" in part and part.endswith("]")))


def _dedupe(problems: Sequence[Problem]) -> list[Problem]:
    seen, unique = set(), []
    for problem in problems:
        if (problem.location, problem.message) not in seen:
            seen.add((problem.location, problem.message))
            unique.append(problem)
    return unique
