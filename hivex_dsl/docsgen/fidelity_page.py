"""The context of docs/fidelity.md: the stored fidelity suite beside the published results, and every reading."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any, Optional

from ..compiler import registry
from ..evaluation import published
from ..evaluation.audit import AUDIT_POLICIES, compared

TRIVIAL_POLICIES = ("zeros", "random")
from ..evaluation.fidelity import FIDELITY_FILE, first_level, load_suite, published_level_mean


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
        values = [compared(ours[p]["statistics"][name]) if name in ours[p]["statistics"] else None
                  for p in AUDIT_POLICIES]
        stats.append({"name": name, "level": _num(cell.statistics[logged][0]), "mean": _num(mean[name]),
                      "ours": ["not computed" if v is None else _num(v) for v in values]})
    ppo = cell.return_mean if cell else None
    scripted = ours["scripted"]["return"]["mean"]
    return {
        "environment": env, "task_index": index, "task": audit["task"], "ppo": _num(ppo),
        "ppo_mean": _num(mean["return"] if mean else None),
        "returns": [_num(ours[p]["return"]["mean"]) for p in AUDIT_POLICIES],
        "half": "-" if ppo is None or ppo <= 0.5 else ("yes" if scripted >= 0.5 * ppo else "**no**"),
        "flags": audit["flags"], "notes": audit.get("notes", []), "statistics": stats,
    }


def trivial_best(audit: dict[str, Any]) -> float:
    """The higher mean return of the two trivial policies (all-zeros, random)."""
    return max(audit["policies"][p]["return"]["mean"] for p in TRIVIAL_POLICIES)


def standard_error(audit: dict[str, Any], policy: str) -> float:
    """The standard error of a policy's mean return over the audit's test episodes: the stored spread (over agents
    and episodes) over the square root of the episode count. The agents of one episode share its world, so the
    episodes, not the agent-episodes, are what is independent; a larger error than the agent count would give."""
    return audit["policies"][policy]["return"]["std"] / math.sqrt(audit["episodes"])


def _trivial_leads(audit: dict[str, Any]) -> list[tuple[str, float, float, float]]:
    """(policy, its mean return, that mean's standard error, the published PPO return) of each trivial policy, in
    the audit's published cell; none where the cell is not published."""
    cell = published.cell(audit["environment"], audit["task_index"], audit["level"])
    if cell is None:
        return []
    return [(p, audit["policies"][p]["return"]["mean"], standard_error(audit, p), cell.return_mean)
            for p in TRIVIAL_POLICIES]


def beaten(audit: dict[str, Any]) -> bool:
    """Whether a trivial policy's mean return is above the published PPO return of the audit's cell by more than its
    standard error: a lead within it is a tie, which another draw of test episodes could turn around."""
    return any(mean - error > ppo for _, mean, error, ppo in _trivial_leads(audit))


def ties(audit: dict[str, Any]) -> list[dict[str, Any]]:
    """The trivial policies whose mean return is above the published PPO return of the audit's cell, but by no more
    than its standard error (:func:`beaten` calls that a tie): each with its mean, that error and the PPO return."""
    return [{"policy": p, "mean": _num(mean), "error": _num(error), "ppo": _num(ppo)}
            for p, mean, error, ppo in _trivial_leads(audit) if ppo < mean <= ppo + error]


def _grid_cell(audit: dict[str, Any]) -> str:
    cell = published.cell(audit["environment"], audit["task_index"], audit["level"])
    if cell is None:
        return "-"
    text = f"{_num(cell.return_mean)} / {_num(trivial_best(audit))} / {_num(audit['policies']['scripted']['return']['mean'])}"
    return f"**{text}** ⚠" if beaten(audit) else text


def _grid(entry: registry.EnvironmentEntry, audits: list[dict[str, Any]]) -> dict[str, Any]:
    """The task x level table of one environment: PPO / best trivial / scripted in each published cell."""
    levels = sorted({a["level"] for a in audits if a["level"] is not None})
    by_key = {(a["task_index"], a["level"]): a for a in audits}
    rows = []
    for task in entry.reward_table.tasks:
        cells = [_grid_cell(by_key[(task.index, level)]) if (task.index, level) in by_key else "-"
                 for level in (levels or [None])]
        rows.append({"task_index": task.index, "task": task.name, "cells": cells})
    published_audits = [a for a in audits if published.cell(a["environment"], a["task_index"], a["level"])]
    evidence = [{"task_index": task.index, "task": task.name, "text": task.trivial_beats_ppo}
                for task in entry.reward_table.tasks if task.trivial_beats_ppo]
    in_order = sorted(published_audits, key=lambda a: (a["task_index"], a["level"] or 0))
    tied = [{"task_index": a["task_index"], "task": a["task"], "level": a["level"], "policies": leads}
            for a, leads in ((a, [] if beaten(a) else ties(a)) for a in in_order) if leads]
    return {"levels": levels, "rows": rows, "cells": len(published_audits),
            "beaten": [a["scenario"] for a in published_audits if beaten(a)], "evidence": evidence, "ties": tied}


def _environment(env_id: str, entry: registry.EnvironmentEntry, audits: list[dict[str, Any]]) -> dict[str, Any]:
    statistics = entry.statistics
    first = first_level(entry)
    rows = [_task_row(a) for a in audits if a["level"] == first]
    return {
        "id": env_id, "title": entry.info.title, "abbreviation": entry.info.abbreviation,
        "level": first, "level_field": entry.info.level_field, "tasks": rows, "grid": _grid(entry, audits),
        "not_computed": sorted(statistics.not_computed.items()) if statistics else [],
        "readings": list(entry.reward_table.notes) + list(entry.notes) + list(statistics.notes if statistics else ()),
    }


def fidelity_context(results: Path) -> dict[str, Any]:
    """Everything docs/fidelity.md shows; ``results`` is the stored suite (it may not exist yet)."""
    report = load_suite(results)
    by_env: dict[str, list[dict[str, Any]]] = {}
    for audit in (report or {}).get("scenarios", []):
        by_env.setdefault(audit["environment"], []).append(audit)
    environments = [_environment(env_id, entry, by_env.get(env_id, []))
                    for env_id, entry in registry.environments().items() if published.cells(env_id)]
    return {"measured": report is not None, "episodes": (report or {}).get("episodes"), "file": FIDELITY_FILE,
            "policies": AUDIT_POLICIES, "environments": environments, "source": published.raw()["source"],
            "published_notes": list(published.notes())}
