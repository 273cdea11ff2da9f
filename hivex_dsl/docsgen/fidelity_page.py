"""The context of docs/fidelity.md: the stored fidelity suite beside the published results, and every reading."""

from __future__ import annotations

from pathlib import Path
from typing import Any, Optional

from .. import published, registry
from ..audit import AUDIT_POLICIES
from ..fidelity import FIDELITY_FILE, first_level, load_suite, published_level_mean


def _num(value: Optional[float]) -> str:
    if value is None:
        return "-"
    return f"{value:,.4g}" if abs(value) < 1e5 else f"{value:,.0f}"


def _task_row(audit: dict[str, Any]) -> dict[str, Any]:
    env, index = audit["environment"], audit["task_index"]
    cell = published.cell(env, index, audit["level"])
    mean = published_level_mean(env, index)
    ours = {p: audit["policies"][p] for p in AUDIT_POLICIES}
    names = list(cell.statistics) if cell else []
    stats = []
    for logged in names:
        if logged == published.RETURN:
            continue
        name = published.short_name(logged)
        values = [ours[p]["statistics"].get(name, {}).get("mean") for p in AUDIT_POLICIES]
        stats.append({"name": name, "level": _num(cell.statistics[logged][0]), "mean": _num(mean[name]),
                      "ours": ["not computed" if v is None else _num(v) for v in values]})
    ppo = cell.return_mean if cell else None
    scripted = ours["scripted"]["return"]["mean"]
    return {
        "environment": env, "task_index": index, "task": audit["task"], "ppo": _num(ppo),
        "ppo_mean": _num(mean["return"] if mean else None),
        "returns": [_num(ours[p]["return"]["mean"]) for p in AUDIT_POLICIES],
        "half": "-" if ppo is None or ppo <= 0.5 else ("yes" if scripted >= 0.5 * ppo else "**no**"),
        "flags": audit["flags"], "statistics": stats,
    }


def _environment(env_id: str, entry: registry.EnvironmentEntry, rows: list[dict[str, Any]]) -> dict[str, Any]:
    statistics = entry.statistics
    return {
        "id": env_id, "title": entry.info.title, "abbreviation": entry.info.abbreviation,
        "level": first_level(entry), "level_field": entry.info.level_field, "tasks": rows,
        "not_computed": sorted(statistics.not_computed.items()) if statistics else [],
        "readings": list(entry.reward_table.notes) + list(entry.notes) + list(statistics.notes if statistics else ()),
    }


def fidelity_context(results: Path) -> dict[str, Any]:
    """Everything docs/fidelity.md shows; ``results`` is the stored suite (it may not exist yet)."""
    report = load_suite(results)
    by_env: dict[str, list[dict[str, Any]]] = {}
    for audit in (report or {}).get("scenarios", []):
        by_env.setdefault(audit["environment"], []).append(_task_row(audit))
    environments = [_environment(env_id, entry, by_env.get(env_id, []))
                    for env_id, entry in registry.environments().items()]
    return {"measured": report is not None, "episodes": (report or {}).get("episodes"), "file": FIDELITY_FILE,
            "policies": AUDIT_POLICIES, "environments": environments, "source": published.raw()["source"],
            "published_notes": list(published.notes())}
