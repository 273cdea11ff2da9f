"""Context of docs/ecosystem.md: the ids, modules and adapter semantics, read from the live code; the library x
environment table, read from the tests that prove it (:mod:`.ecosystem_matrix`); and each integration's overhead,
read from benchmarks/ecosystem_overhead.py's report."""

from __future__ import annotations

import inspect
import json
from pathlib import Path

from ..adapters import flat, joint, gymnasium as vector_adapter, module_doc, pettingzoo as parallel_adapter
from ..adapters.registration import bundled_scenarios, camel
from ..compiler import registry
from .ecosystem_matrix import matrix_context

OVERHEAD_FILE = "benchmarks/results/ecosystem.json"  # benchmarks/ecosystem_overhead.py writes it


def overhead_context(path: Path | None) -> dict:
    """The overhead table: per environment the raw vector env's agent-steps/s and each integration's rate as a
    fraction of it ('-' where it was not measured), with the run's machine, date and settings; ``None`` without
    a report."""
    if path is None or not Path(path).is_file():
        return {"overhead": None}
    report = json.loads(Path(path).read_text(encoding="utf-8"))
    keys = list(report["integrations"])
    rows = []
    for result in report["results"]:
        measured = result["integrations"]
        rows.append({"environment": result["environment"], "agents": result["agents"],
                     "raw": f"{result['raw_agent_steps_per_s']:,.0f}",
                     "ratios": [f"{measured[k]['ratio']:.2f}" if k in measured else "-" for k in keys]})
    return {"overhead": {"machine": report["machine"], "date": report["date"], "worlds": report["worlds"],
                         "steps": report["steps"], "repeats": report["repeats"],
                         "episode_length": report["episode_length"],
                         "versions": ", ".join(f"{name} {v}" for name, v in report.get("versions", {}).items()),
                         "integrations": [report["integrations"][k] for k in keys], "rows": rows,
                         "skipped": report.get("skipped", {})}}


def ecosystem_context(tests: Path | None = None, overhead: Path | None = None) -> dict:
    """Everything ecosystem.md shows; ``tests`` is the checkout's tests/ folder, ``overhead`` the benchmark report
    (either may be None or missing: its table is then left out)."""
    rows = []
    for env_id in registry.environments():
        rows.append({"env": env_id, "id": f"hivex/{camel(env_id)}-v0", "module": f"hivex_dsl.zoo.{env_id}_v0",
                     "scenarios": ", ".join(f"`hivex/{camel(env_id)}-{camel(name)}-v0`"
                                               for name in bundled_scenarios(env_id))})
    return {"rows": rows,
            **matrix_context(tests),
            **overhead_context(overhead),
            "vector_doc": inspect.getdoc(vector_adapter),
            "parallel_doc": inspect.getdoc(parallel_adapter.HivexParallelEnv),
            "flat_doc": inspect.getdoc(flat),
            "joint_doc": inspect.getdoc(joint),
            "sb3_doc": module_doc("sb3"),
            "torchrl_doc": module_doc("torchrl"),
            "benchmarl_doc": module_doc("benchmarl")}
