"""Our recorded learning curves beside the original's, for the baselines and fidelity pages: per committed main-task
record, the measure of :mod:`hivex_dsl.evaluation.original.compare` for every training seed it holds and their mean,
every panel it keeps, each panel pooled over the last tenth of the budget
(:mod:`~hivex_dsl.evaluation.original.tail`), and a small figure of the return and Episode Length (drawn here,
compared as pixels by `hivex docs --check`; only the five main tasks' records are drawn, so the check stays quick);
per grid record whose points hold their training curves, a compact table of the measure of each point's return and
its pool over the last tenth of the budget (no figure). A record whose note marks it stale is shown as such, not as
evidence."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np

from ..compiler import registry
from ..evaluation.original import compare
from ..evaluation.original import seeds as seeds_measure
from ..evaluation.original.curves import OriginalCell, original_curves
from ..evaluation.original.tail import tail_seeds, tail_table

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


def _cell(environment: str, toolkit_task: int, level: int | None) -> OriginalCell | None:
    """The original's page of a record's cell (None: no page, or a Drone-Based Reforestation task whose page index is
    not settled, :data:`~hivex_dsl.evaluation.original.compare.SETTLED_DBR_TASKS`)."""
    task = compare.paper_task_index(environment, toolkit_task)
    try:
        return compare.original_cell(environment, task, level)
    except compare.CompareError:
        return None


def _budget(cell: OriginalCell) -> int:
    return max(p.training.last_step for p in cell.panels.values() if p.training is not None)


def _comparison(record: dict[str, Any]) -> tuple[dict[str, Any], np.ndarray] | None:
    environment = record["environment"]
    if not record.get("curve"):
        return None
    cell = _cell(environment, record["task_index"], record["level"])
    if cell is None:
        return None
    from ..evaluation.original.figure import picture

    runs = compare.seed_curves(record)
    rows = seeds_measure.measure_seeds(runs, cell)
    budget = _budget(cell)
    verdicts = [r.verdict for r in rows]
    ends = tail_seeds(runs, cell)
    end = next(e for e in ends if e.panel == compare.RETURN)
    seeds = [str(run.label.removeprefix("this toolkit, ").removesuffix(" (stale record)")) for run in runs]
    context = {"environment": environment, "file": cell.file, "title": cell.title, "stale": compare.is_stale(record),
               "seeds": seeds, "seeds_recorded": 1 + len(record.get("other_seeds", [])),
               "image": f"{IMAGES}/{environment}.png", "table": seeds_measure.seeds_table(rows, seeds),
               "counts": {word: verdicts.count(word) for word in ("within", "above", "below", "no point")},
               "among": among_counts(rows, runs),
               "panels": list(dict.fromkeys(r.panel for r in rows)), "budget": _number(budget),
               "tail_table": tail_table(ends, seeds), "tail_start": _number(end.start),
               "tail_return": None if end.value is None else
               {"ours": compare.number(end.value), "theirs": compare.number(end.theirs), "ratio": f"{end.ratio:.2f}"},
               **{f"record_{k}": v for k, v in budget_words(record, budget).items()}}
    drawn = [p for p in (compare.RETURN, compare.EPISODE_LENGTH) if p in compare.shared_panels(runs[0], cell)]
    return context, picture(runs[0], cell, drawn, others=runs[1:])


def among_counts(rows: list[seeds_measure.SeedsRow], runs: list[compare.RunCurve]) -> dict[str, Any] | None:
    """How often the original's mean falls within the range of the seeds ``runs``, below all or above all of them,
    beside the shares one more seed would (:func:`~hivex_dsl.evaluation.original.seeds.exchangeable_shares`, as
    percentages), and how much of their return's swings the seeds share
    (:func:`~hivex_dsl.evaluation.original.seeds.shared_swings`); None with fewer than two seeds."""
    seeds = len(runs)
    if seeds < 2:
        return None
    found, shares = seeds_measure.among_tally(rows), seeds_measure.exchangeable_shares(seeds)
    ratio, swings = seeds_measure.band_over_range(rows), seeds_measure.shared_swings(runs)
    return {"points": sum(found.values()), "seeds": seeds, "band_over_range": "-" if ratio is None else f"{ratio:.2f}",
            "shared_swings": "-" if swings is None else f"{swings:.2f}",
            **{word.replace(" ", "_"): count for word, count in found.items()},
            "expected": {word.replace(" ", "_"): f"{share:.0%}" for word, share in shares.items()}}


def grid_comparisons(directory: Path | None) -> list[dict[str, Any]]:
    """Per committed grid record of ``directory`` (benchmarks/baselines; its grids/ folder) whose points hold their
    training curves, in the catalogue's order: the measure of each such point's return against the original's page
    of its cell, one row a point (task, level, each fraction's value and verdict); points without a page are named."""
    from ..train.baselines import GRIDS

    if directory is None or not (Path(directory) / GRIDS).is_dir():
        return []
    found = []
    for environment in registry.environments():
        path = Path(directory) / GRIDS / f"{environment}.json"
        if path.is_file():
            grid = _grid_comparison(json.loads(path.read_text(encoding="utf-8")))
            if grid is not None:
                found.append(grid)
    return found


def _grid_comparison(record: dict[str, Any]) -> dict[str, Any] | None:
    environment, rows, without = record["environment"], [], []
    for point in (p for p in record["points"] if p.get("curve")):
        cell = _cell(environment, point["task_index"], point["level"])
        if cell is None:
            without.append(point["name"])
            continue
        runs = compare.seed_curves(point | {"environment": environment})
        measured = [r for r in seeds_measure.measure_seeds(runs, cell) if r.panel == compare.RETURN]
        end = next(e for e in tail_seeds(runs, cell) if e.panel == compare.RETURN)
        rows.append({"task_index": compare.paper_task_index(environment, point["task_index"]), "task": point["task"],
                     "level": "-" if point["level"] is None else point["level"], "seeds": len(runs),
                     "cells": [f"{compare.number(r.value)}, {r.verdict}" if r.value is not None
                               else "no point" for r in measured],
                     "tail": "no point" if end.value is None else
                             f"{compare.number(end.value)} / {compare.number(end.theirs)} ({end.ratio:.2f})"})
    if not rows and not without:
        return None
    return {"environment": environment, "stale": compare.is_stale(record), "rows": rows, "without": without,
            "fractions": [f"{f:.0%}" for f in compare.FRACTIONS], "seeded": any(r["seeds"] > 1 for r in rows)}


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
