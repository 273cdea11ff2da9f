"""The scenario keys that hold expressions (``terms``, ``shaping``, ``ends_on``), read before and after validation."""

from __future__ import annotations

from typing import Any, Mapping


def expression_term_names(data: Any) -> tuple[str, ...]:
    """Names of the terms a raw scenario declares (``terms:`` keys and the shaping term), for its weights model."""
    names: list[str] = []
    terms = data.get("terms") if isinstance(data, dict) else None
    if isinstance(terms, dict):
        names += [name for name in terms if isinstance(name, str)]
    shaping = data.get("shaping") if isinstance(data, dict) else None
    if isinstance(shaping, dict):
        name = shaping.get("name", "shaping")
        names.append(name if isinstance(name, str) else "shaping")
    return tuple(dict.fromkeys(names))


def declared_term_names(spec: Any) -> tuple[str, ...]:
    """Names of a validated scenario's expression terms, the shaping term last."""
    names = tuple(spec.terms or ()) if getattr(spec, "terms", None) else ()
    return names + ((spec.shaping.name,) if getattr(spec, "shaping", None) is not None else ())


def clashing_terms(data: Any, registered: tuple[str, ...]) -> list[tuple[tuple, str]]:
    """(path, message) for every declared term whose name the environment already registered."""
    terms = data.get("terms") if isinstance(data, dict) else None
    if not isinstance(terms, dict):
        return []
    return [(("terms", name), f"terms.{name}: '{name}' is already a reward term of this environment; "
                              "weight it in `weights:` or give the new term another name")
            for name in terms if name in registered]


def split_ends_on(spec: Any, events: Mapping[str, str]) -> tuple[tuple[str, ...], dict[tuple, str]]:
    """A scenario's ``ends_on`` as (event names, {path: expression}); a bare word that is no event is an expression."""
    names: list[str] = []
    expressions: dict[tuple, str] = {}
    for i, entry in enumerate(getattr(spec, "ends_on", ())):
        if entry in events:
            names.append(entry)
        else:
            expressions[("ends_on", i)] = entry
    return tuple(names), expressions


def expression_keys(spec: Any) -> dict[str, Any]:
    """The expression keys of a validated scenario as the language writes them (for the lock)."""
    out: dict[str, Any] = {}
    if getattr(spec, "terms", None):
        out["terms"] = {name: term.model_dump(mode="json", exclude_defaults=True) for name, term in spec.terms.items()}
    if getattr(spec, "shaping", None) is not None:
        out["shaping"] = spec.shaping.model_dump(mode="json")
    if getattr(spec, "ends_on", ()):
        out["ends_on"] = list(spec.ends_on)
    return out
