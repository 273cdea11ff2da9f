"""Template contexts built from the live code: registry, reward tables, terms, models, scenarios."""

from __future__ import annotations

import importlib
import json
from pathlib import Path
from typing import Any

from .. import compiler
from ..base.resources import data_dir
from ..compiler import registry
from ..lang import loader
from ..lang.expr import syntax
from ..lang.spec import scenario as scenario_spec
from ..lang.spec.catalogue import PAPER_ENVIRONMENTS, listing_key
from ..lang.spec.common import MAX_SEED, MAX_WEIGHT, SCHEMA_VERSION
from ..lang.spec.expressions import MAX_EXPRESSION_CHARS
from ..lang.spec.reward_table import RewardTable, TaskColumn
from ..sim.reward.composer import RETURN_LIMIT
from ..train.config import has_paper_hyperparameters
from .expressions import expression_language_context, vocabulary_context
from .fields import field_rows, num, show_value, source_tag
from .pages import SCHEMA_FILE, env_page
from .spaces_table import global_state_table, specification

MAX_LISTED_VALUES = 6


def index_context() -> dict[str, Any]:
    available = registry.environments()
    infos = {**PAPER_ENVIRONMENTS, **{env_id: entry.info for env_id, entry in available.items()}}
    rows = []
    for info in sorted(infos.values(), key=lambda info: listing_key(info.id)):
        level = f"`{info.level_field}` ({info.level_count} levels)" if info.level_field else "none"
        rows.append({
            "id": info.id, "title": info.title, "abbreviation": info.abbreviation,
            "agents": (f"{info.default_agents} (fixed)" if info.min_agents == info.max_agents
                       else f"{info.default_agents} ({info.min_agents} to {info.max_agents})"),
            "episode_length": num(info.default_episode_length), "level": level,
            "available": info.id in available, "page": env_page(info.id),
        })
    return {"environments": rows, "available": [r for r in rows if r["available"]], "schema_file": SCHEMA_FILE,
            "schema_version": SCHEMA_VERSION}


def checkout_path(path: Path) -> str:
    """A content file's path as the docs link it: from the checkout's top (``scenarios/<id>/main.yaml``), or as it
    is for a file outside the checkout (an installed environment package's)."""
    top = data_dir("rewards").parent.resolve()
    path = Path(path).resolve()
    return path.relative_to(top).as_posix() if top in path.parents else path.as_posix()


def _vocabulary(entry: registry.EnvironmentEntry) -> scenario_spec.ScenarioVocabulary:
    return scenario_spec.ScenarioVocabulary(entry.info, entry.params_model, entry.reward_table.task_names,
                                            entry.term_names, entry.level_names)


def _matrix(entry: registry.EnvironmentEntry) -> dict[str, Any]:
    table = entry.reward_table
    rows = []
    for term_name, weights in table.matrix.items():
        contract = entry.terms[term_name].contract if term_name in entry.terms else None  # None: an expression term
        title = contract.title if contract else (table.terms[term_name].title or term_name)
        rows.append({"name": term_name, "title": title,
                     "paper_row": num(contract.paper_row) if contract and contract.paper_row is not None else "-",
                     "weights": [num(float(w)) for w in weights]})
    tasks = [{"index": t.index, "name": t.name, "title": t.title, "description": t.description,
              "ends_on": [{"name": e, "meaning": entry.events.get(e, ""), "world": e in entry.world_events}
                          for e in t.ends_on],
              "unpaid": list(t.unpaid)}
             for t in table.tasks]
    return {"source": table.source, "tasks": tasks, "rows": rows}


def _contracts(entry: registry.EnvironmentEntry) -> list[dict[str, Any]]:
    out = []
    for term in entry.terms:
        c = term.contract
        out.append({"name": c.name, "title": c.title, "description": c.description,
                    "range": f"[{num(float(c.low))}, {num(float(c.high))}]", "sign": c.sign, "timing": c.timing,
                    "scope": c.scope, "paper_row": num(c.paper_row) if c.paper_row is not None else "-",
                    "equation": c.equation})
    return out


def _params(entry: registry.EnvironmentEntry) -> list[dict[str, str]]:
    rows = field_rows(entry.params_model)
    for row in rows:
        row["source"], row["description"] = source_tag(row["description"])
    return rows


def _generators(entry: registry.EnvironmentEntry) -> list[dict[str, Any]]:
    """Each generator slot with its fields; defaults are the preset's at the first level."""
    first = 1 if entry.info.level_field == "terrain_level" else (0 if entry.info.level_field else None)
    out = []
    for name, slot in entry.generators.items():
        preset = slot.preset(first).model_dump()
        rows = field_rows(slot.spec_model)
        for row in rows:
            row["source"], row["description"] = source_tag(row["description"])
            row["default"] = show_value(preset[row["name"]])
        out.append({"name": name, "description": slot.description, "rows": rows})
    return out


def _levels(entry: registry.EnvironmentEntry) -> dict[str, Any] | None:
    info = entry.info
    if info.level_field is None:
        return None
    # The environment's package (e.g. hivex_dsl.envs.wind_farm_control) may hold a PRESET of its levels.
    package = importlib.import_module(entry.params_model.__module__.rsplit(".", 1)[0])
    preset = getattr(package, "PRESET", None)
    descriptions = {p.index: p.description for p in getattr(preset, "patterns", ())}
    if info.level_field == "pattern":
        rows = [{"index": i, "name": name, "title": entry.level_titles[i] if i < len(entry.level_titles) else "",
                 "description": descriptions.get(i, "")} for i, name in enumerate(entry.level_names)]
        return {"field": "pattern", "heading": "Layout patterns", "rows": rows}
    low, high = scenario_spec.TERRAIN_LEVELS
    rows = [{"index": level, "name": str(level), "title": "", "description": ""} for level in range(low, high + 1)]
    return {"field": "terrain_level", "heading": "Terrain levels", "rows": rows}


def _listing(values: list[Any]) -> str:
    distinct = list(dict.fromkeys(values))
    if len(distinct) == 1:
        return str(distinct[0])
    if len(distinct) <= MAX_LISTED_VALUES:
        return "swept: " + ", ".join(str(v) for v in distinct)
    return f"swept: {len(distinct)} values"


def _scenarios(entry: registry.EnvironmentEntry) -> list[dict[str, Any]]:
    out = []
    for path in entry.scenario_files():
        compiled = compiler.compile_all(path)
        first = compiled[0]
        level = ""
        if entry.info.level_field == "pattern":
            level = _listing([entry.level_names[c.level] for c in compiled])
        elif entry.info.level_field:
            level = _listing([c.level for c in compiled])
        out.append({"file": checkout_path(path), "name": first.spec.name,
                    "description": first.spec.description, "count": len(compiled),
                    "swept": list(first.sweep_point), "task": _listing([c.task_name for c in compiled]),
                    "level": level, "agents": _listing([c.agents for c in compiled])})
    return out


def environment_context(entry: registry.EnvironmentEntry) -> dict[str, Any]:
    compiled = compiler.compile({"hivex": SCHEMA_VERSION, "environment": entry.id})
    simulator = entry.make_simulator(compiled)
    return {
        "info": entry.info,
        "spec": specification(entry.info, compiled, simulator),
        "global_state": global_state_table(compiled, simulator),
        "matrix": _matrix(entry),
        "events": sorted(entry.events.items()),
        "world_events": sorted(entry.world_events),
        "contracts": _contracts(entry),
        "params": _params(entry),
        "generators": _generators(entry),
        "levels": _levels(entry),
        "notes": list(entry.notes),
        "table_notes": list(entry.reward_table.notes),
        "scenarios": _scenarios(entry),
        "schema_file": SCHEMA_FILE,
        "reward_file": checkout_path(entry.reward_table_path),
        "vocabulary": vocabulary_context(entry),
        "paper": entry.id in PAPER_ENVIRONMENTS,
        "paper_rows": any(term.contract.paper_row is not None for term in entry.terms),
        "paper_hyperparameters": has_paper_hyperparameters(entry.id),
    }


def _nested_models(model: type) -> list[tuple[str, type]]:
    out = []
    for name, field in model.model_fields.items():
        if field.default_factory is not None and isinstance(field.default_factory, type):
            out.append((name, field.default_factory))
    return out


def language_context() -> dict[str, Any]:
    envs = []
    for entry in registry.environments().values():
        model = entry.scenario_model
        nested = {name: field_rows(sub) for name, sub in _nested_models(model) if name != "params"}
        envs.append({
            "id": entry.id, "title": entry.info.title, "page": env_page(entry.id),
            "fields": field_rows(model), "nested": nested,
            "sweepable": list(scenario_spec.sweepable_fields(_vocabulary(entry))),
            "prefixes": {"params": list(entry.params_model.model_fields), "weights": list(entry.term_names),
                         "seeds": list(scenario_spec.Seeds.model_fields)},
        })
    limits = [
        ("Scenario file size", f"{num(loader.MAX_FILE_BYTES)} bytes", "lang.loader.MAX_FILE_BYTES"),
        ("YAML nodes per file", num(loader.MAX_NODES), "lang.loader.MAX_NODES"),
        ("YAML nesting depth", num(loader.MAX_DEPTH), "lang.loader.MAX_DEPTH"),
        ("Values per swept field", num(compiler.MAX_SWEEP_VALUES), "compiler.MAX_SWEEP_VALUES"),
        ("Scenarios per sweep (grid points)", num(compiler.MAX_SWEEP_POINTS), "compiler.MAX_SWEEP_POINTS"),
        ("Expressions compiled per sweep (its points x the expressions its file writes)",
         num(compiler.MAX_SWEEP_EXPRESSIONS), "compiler.MAX_SWEEP_EXPRESSIONS"),
        ("Expression characters compiled per sweep (its points x the characters of the expressions its file writes)",
         num(compiler.MAX_SWEEP_EXPRESSION_CHARS), "compiler.MAX_SWEEP_EXPRESSION_CHARS"),
        ("Seeds per split", num(scenario_spec.MAX_SEEDS_PER_SPLIT), "lang.spec.scenario.MAX_SEEDS_PER_SPLIT"),
        ("Largest seed", num(MAX_SEED), "lang.spec.common.MAX_SEED"),
        ("Largest episode length", num(scenario_spec.MAX_EPISODE_LENGTH), "lang.spec.scenario.MAX_EPISODE_LENGTH"),
        ("Largest weight magnitude", num(MAX_WEIGHT), "lang.spec.common.MAX_WEIGHT"),
        ("Characters per expression", num(MAX_EXPRESSION_CHARS), "lang.spec.expressions.MAX_EXPRESSION_CHARS"),
        ("Parentheses, calls and prefix operators open at once in an expression", num(syntax.MAX_NESTING),
         "lang.expr.syntax.MAX_NESTING"),
        ("Depth of an expression's tree", num(syntax.MAX_DEPTH), "lang.expr.syntax.MAX_DEPTH"),
        ("Largest episode return one agent's weighted terms may reach (proven from their ranges)",
         f"{RETURN_LIMIT:g}", "sim.reward.composer.RETURN_LIMIT"),
    ]
    return {
        "environments": envs, "schema_version": SCHEMA_VERSION, "schema_file": SCHEMA_FILE,
        "sweepable_all": list(scenario_spec.SWEEPABLE_FIELDS), "prefixes": list(scenario_spec.SWEEPABLE_PREFIXES),
        "limits": limits,
        "reward_table": {"doc": _doc(RewardTable), "fields": field_rows(RewardTable)},
        "task_column": {"doc": _doc(TaskColumn), "fields": field_rows(TaskColumn)},
    } | expression_language_context()


def _doc(model: type) -> str:
    """The first paragraph of a model's docstring, on one line."""
    text = (model.__doc__ or "").strip().split("\n\n")[0]
    return " ".join(text.split())


def performance_context(results: Path) -> dict[str, Any]:
    """The rows of a `hivex bench --json` report, formatted, with each environment's target."""
    from ..evaluation.bench import MEMORY_LIMIT_MB, REFERENCE, step_us

    report = json.loads(Path(results).read_text(encoding="utf-8"))
    rows = []
    for r in report["results"]:
        ratio = r.get("env_steps_vs_reference") if r["adapter"] == "parallel" else r.get("agent_steps_vs_reference")
        goal = ""
        if "target_rate" in r:
            unit = "env-steps/s" if r["adapter"] == "parallel" else "agent-steps/s"
            goal = f"{'met' if r['meets_target'] else 'missed'}: {r['target_rate']:,} {unit}"
        rows.append({"target": r["target"], "adapter": r["adapter"], "batch": r["batch"], "agents": r["agents"],
                     "env_rate": f"{r['env_steps_per_s']:,.0f}", "agent_rate": f"{r['agent_steps_per_s']:,.0f}",
                     "memory": f"{r['peak_memory_mb']:,.0f}", "ratio": "" if ratio is None else f"{ratio:.1f}",
                     "goal": goal, "step_us": f"{step_us(r):,.1f}",
                     "floor_us": "" if r.get("api_floor_us") is None else f"{r['api_floor_us']:,.1f}"})
    return {"machine": report["machine"], "seconds": report["seconds_per_run"], "repeats": report["repeats"],
            "rows": rows, "reference": REFERENCE, "memory_limit": MEMORY_LIMIT_MB, "results_file": str(results.name)}
