"""Template contexts of the expression language: its grammar, each environment's vocabulary, the YAML-only tasks."""

from __future__ import annotations

from typing import Any

from .. import compiler
from ..compiler import registry
from ..lang.expr import describe_grammar
from ..lang.spec.common import SCHEMA_VERSION
from ..lang.spec.expressions import ExpressionTermSpec, ShapingSpec, WeightSchedule
from ..sim.reward.vocabulary import vocabulary_of
from .fields import field_rows, num, schema_type
from .pages import env_page


def _rows(model) -> list[dict[str, str]]:
    """field_rows of ``model`` under the names a file writes (``from``, not the attribute ``start``)."""
    rows = field_rows(model)
    schema = model.model_json_schema()
    for row, field in zip(rows, model.model_fields.values()):
        if field.alias:
            row["name"] = field.alias
            row["type"] = schema_type(schema["properties"][field.alias], schema.get("$defs", {}))
    return rows


def _expression_scenarios(entry: registry.EnvironmentEntry) -> list[dict[str, Any]]:
    """Bundled scenarios of ``entry`` that declare expression terms or shaping, with the terms' contracts."""
    out = []
    for path in entry.scenario_files():
        compiled = compiler.compile_all(path)[0]
        if compiled.expressions is None or not compiled.expressions.terms:
            continue
        terms = [{"name": c.name, "title": c.title, "description": c.description, "equation": c.equation,
                  "range": f"[{num(float(c.low))}, {num(float(c.high))}]", "sign": c.sign, "scope": c.scope,
                  "weight": _weight(compiled, c.name)} for c in compiled.expressions.contracts]
        text = path.read_text("utf-8").split("\n")
        body = "\n".join(line for line in text if not line.startswith("# yaml-language-server")).strip()
        out.append({"file": f"scenarios/{entry.id}/{path.name}", "name": compiled.spec.name,
                    "description": compiled.spec.description, "terms": terms, "yaml": body})
    return out


def _weight(compiled, name: str) -> str:
    schedule = compiled.schedules.get(name)
    if schedule is None:
        return num(float(compiled.weights[name]))
    return f"{num(schedule.start)} to {num(schedule.end)} over {num(schedule.over_steps)} steps ({schedule.kind})"


def vocabulary_context(entry: registry.EnvironmentEntry) -> dict[str, Any]:
    """The quantities of an environment (ranges under the default scenario) and its YAML-only tasks."""
    compiled = compiler.compile({"hivex": SCHEMA_VERSION, "environment": entry.id})
    try:
        vocabulary = vocabulary_of(entry.id)
    except ModuleNotFoundError:
        return {"quantities": [], "not_modelled": [], "expression_scenarios": []}
    rows = [{"name": q.name, "per": q.per, "kind": q.kind, "unit": q.unit or "-",
             "range": "false / true" if q.kind == "bool" else f"[{num(float(q.low))}, {num(float(q.high))}]",
             "description": q.description} for q in vocabulary.quantities(compiled).values()]
    absent = [{"name": name, "why": why} for name, why in vocabulary.not_modelled.items()]
    return {"quantities": rows, "not_modelled": absent, "expression_scenarios": _expression_scenarios(entry)}


def expression_language_context() -> dict[str, Any]:
    """Grammar (from the core), the models of terms, shaping and schedules, and the bundled examples."""
    examples = [s for entry in registry.environments().values() for s in _expression_scenarios(entry)]
    return {"grammar": describe_grammar(), "term_fields": _rows(ExpressionTermSpec),
            "shaping_fields": _rows(ShapingSpec), "schedule_fields": _rows(WeightSchedule),
            "examples": examples,
            "vocabulary_pages": [{"id": e.id, "title": e.info.title, "page": env_page(e.id)}
                                 for e in registry.environments().values()]}
