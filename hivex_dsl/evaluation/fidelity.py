"""The fidelity suite: every task of every environment at every published level, audited against the paper.

The suite is the whole published grid (222 cells: each environment, task and level or pattern the paper
published a PPO result for) plus each task at its first level where no cell exists (Drone-Based
Reforestation's Group Up). An environment the paper published nothing for (one added to the catalogue) is
not in it, so adding one leaves the stored results as they are. Rolling it for the three audit policies
takes minutes, too long for `hivex docs --check` in CI, so the measured numbers are stored: ``hivex audit --suite -o
benchmarks/results/fidelity.json`` writes them (:func:`measure_suite`), docs/fidelity.md is rendered from
that file, and tests/test_fidelity.py re-measures the cheap tasks (WFC, WRM, DBR Drop Seed at their
first level) and checks every scenario's fingerprint to prove the file is not stale.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any, Optional, TextIO

from ..compiler import registry
from ..compiler import CompiledScenario, compile as compile_scenario
from ..lang.loader import load_file
from . import published
from .audit import audit_all

FIDELITY_VERSION = 1
FIDELITY_FILE = "benchmarks/results/fidelity.json"
SUITE_EPISODES = 10  # the standard for a verdict: two episodes flipped near ties (issue 52)


def first_level(entry: registry.EnvironmentEntry) -> Optional[int]:
    """The level the suite (and the issue's comparison) uses: pattern 0, terrain level 1, or none."""
    return {"pattern": 0, "terrain_level": 1}.get(entry.info.level_field or "")


def suite_levels(env_id: str, entry: registry.EnvironmentEntry, task_index: int) -> list[Optional[int]]:
    """The levels the suite rolls for a task: every published one, else the first level."""
    published_levels = sorted((c.level for c in published.cells(env_id) if c.task_index == task_index),
                              key=lambda level: -1 if level is None else level)
    return published_levels or [first_level(entry)]


def scenario_name(entry: registry.EnvironmentEntry, task: str, level: Optional[int]) -> str:
    """A suite row's name: ``wrm-main-l1`` (terrain level 1), ``wfc-avoid-damage-p3`` (pattern 3), ``opc-group-up``."""
    base = f"{entry.info.abbreviation.lower()}-{task.replace('_', '-')}"
    if level is None:
        return base
    return f"{base}-{'p' if entry.info.level_field == 'pattern' else 'l'}{level}"


def suite_scenarios(environments: Optional[list[str]] = None, first_only: bool = False) -> list[CompiledScenario]:
    """Each environment's bundled main scenario with each of its tasks at each suite level (only the first
    level with ``first_only``), in environment, task, level order; environments with a published cell only."""
    out = []
    for env_id, entry in registry.environments().items():
        if (environments is not None and env_id not in environments) or not published.cells(env_id):
            continue
        main = load_file(entry.scenario_dir / "main.yaml").data
        for task in entry.reward_table.tasks:
            levels = [first_level(entry)] if first_only else suite_levels(env_id, entry, task.index)
            for level in levels:
                data = dict(main, task=task.name, name=scenario_name(entry, task.name, level))
                if entry.info.level_field:
                    data[entry.info.level_field] = level
                out.append(compile_scenario(data))
    return out


def measure_suite(episodes: int = SUITE_EPISODES, environments: Optional[list[str]] = None,
                  stream: Optional[TextIO] = None, quiet: bool = False) -> dict[str, Any]:
    """Audit every suite scenario; the JSON-ready report (each audit with its scenario's fingerprint)."""
    compiled = suite_scenarios(environments)
    audits = audit_all(compiled, episodes, stream, quiet=quiet)
    rows = []
    for scenario, audit in zip(compiled, audits):
        row = audit.as_dict()
        row["source"] = f"{scenario.environment}/main.yaml (task {scenario.task_name}, level {scenario.level})"
        rows.append(row | {"fingerprint": scenario.fingerprint})
    return {"hivex_fidelity": FIDELITY_VERSION, "episodes": episodes, "split": "test", "scenarios": rows}


def remeasure_suite(stored: dict[str, Any], environments: list[str], stream: Optional[TextIO] = None,
                    quiet: bool = False, episodes: Optional[int] = None) -> dict[str, Any]:
    """``stored`` with the rows of ``environments`` measured again (at ``episodes``, by default the stored count)
    and every other row kept as it was, in suite order: what changing one environment needs, not the whole grid.
    Each row keeps its own episode count; the report's is the fewest of any row (what every row has at least)."""
    fresh = measure_suite(episodes or stored["episodes"], environments, stream, quiet)
    kept = [row for row in stored["scenarios"] if row["environment"] not in environments]
    order = {env_id: i for i, env_id in enumerate(registry.environments())}
    rows = sorted(kept + fresh["scenarios"], key=lambda row: order.get(row["environment"], len(order)))
    return dict(stored, episodes=min(row["episodes"] for row in rows), scenarios=rows)


def write_suite(report: dict[str, Any], output: Path) -> None:
    """The report as JSON, one scenario a line (a re-measured row shows as one changed line in a diff)."""
    output.parent.mkdir(parents=True, exist_ok=True)
    head = {k: v for k, v in report.items() if k != "scenarios"}
    rows = ",\n".join(json.dumps(row, sort_keys=False) for row in report["scenarios"])
    text = json.dumps(head)[:-1] + ', "scenarios": [\n' + rows + "\n]}\n"
    output.write_text(text, encoding="utf-8")


def load_suite(path: Path) -> Optional[dict[str, Any]]:
    """The stored report, or None where none was measured yet."""
    path = Path(path)
    if not path.is_file():
        return None
    return json.loads(path.read_text(encoding="utf-8"))


def published_level_mean(environment: str, task_index: int) -> Optional[dict[str, float]]:
    """The published return and statistics of a task averaged over its levels (None without any)."""
    found = [c for c in published.cells(environment) if c.task_index == task_index]
    if not found:
        return None
    names = found[0].statistics
    return {published.short_name(name) if name != published.RETURN else "return":
            sum(c.statistics[name][0] for c in found if name in c.statistics) / len(found) for name in names}


__all__ = ["FIDELITY_FILE", "measure_suite", "load_suite", "published_level_mean", "suite_scenarios",
           "write_suite", "first_level", "suite_levels", "scenario_name"]
