"""Our recorded learning curves beside the original's, for the baselines and fidelity pages: per committed main-task
record, the measure of :mod:`hivex_dsl.evaluation.original.compare` and a small figure (drawn here, compared as
pixels by `hivex docs --check`; only the five main tasks' records are drawn, so the check stays quick)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np

from ..compiler import registry
from ..evaluation.original import compare
from ..evaluation.original.curves import original_curves

IMAGES = "images/curves"  # docs-relative folder of the figures


def _number(value: int) -> str:
    return f"{value:,}"


def budget_source(environment: str, max_steps: int) -> str:
    """Whose ``max_steps`` a record's is: "the config that ran" (today's default), "the paper appendix" or "its own"."""
    from ..train.config import appendix, paper_defaults

    if max_steps == paper_defaults(environment)["max_steps"]:
        return "the config that ran"
    return "the paper appendix" if max_steps == appendix(environment).get("max_steps") else "its own"


def budget_words(record: dict[str, Any], original_budget: int) -> dict[str, Any]:
    """The record's budget against the original's: ``steps``, ``which`` (whose max_steps it is: the config that
    ran, the appendix's, or its own) and ``differs`` (a sentence where it is not the original's, else "")."""
    trained = int(record["hyperparameters"]["max_steps"])
    which = budget_source(record["environment"], trained)
    differs = "" if trained == original_budget else (
        f"The budgets differ: the original trained {_number(original_budget)} (the config that ran, which its curves' "
        f"axes follow), this record {_number(trained)}; the measure reads ours at the original's steps"
        + (", and our curve goes on past its end." if trained > original_budget else "."))
    return {"steps": _number(trained), "which": which, "differs": differs}


def _comparison(record: dict[str, Any]) -> tuple[dict[str, Any], np.ndarray] | None:
    environment = record["environment"]
    if not record.get("curve"):
        return None
    task = compare.paper_task_index(environment, record["task_index"])
    cell = original_curves(environment, task, record["level"])
    if cell is None:
        return None
    run, *others = compare.seed_curves(record)
    rows = compare.measure(run, cell)
    budget = max(p.training.last_step for p in cell.panels.values() if p.training is not None)
    verdicts = [r.verdict for r in rows]
    context = {"environment": environment, "file": cell.file, "title": cell.title, "label": run.label,
               "image": f"{IMAGES}/{environment}.png", "table": compare.table(rows),
               "other_tables": [{"label": o.label, "table": compare.table(compare.measure(o, cell))} for o in others],
               "counts": {word: verdicts.count(word) for word in ("within", "above", "below", "no point")},
               "panels": sorted({r.panel for r in rows}), "budget": _number(budget),
               **{f"record_{k}": v for k, v in budget_words(record, budget).items()}}
    return context, compare.picture(run, cell, others=others)


def curve_comparisons(directory: Path | None) -> tuple[list[dict[str, Any]], dict[str, np.ndarray]]:
    """Per committed main-task record of ``directory`` (benchmarks/baselines) holding a training curve, in the
    catalogue's order: its measure against the original's cell (context for the pages) and its figure
    (docs-relative path -> (H, W, 3) uint8 picture)."""
    if directory is None or not Path(directory).is_dir():
        return [], {}
    found, images = [], {}
    for environment in registry.environments():
        path = Path(directory) / f"{environment}.json"
        if not path.is_file():
            continue
        drawn = _comparison(json.loads(path.read_text(encoding="utf-8")))
        if drawn is not None:
            found.append(drawn[0])
            images[drawn[0]["image"]] = drawn[1]
    return found, images
