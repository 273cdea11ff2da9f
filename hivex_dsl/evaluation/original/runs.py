"""A run read from disk for `hivex curves`: a `hivex train` run directory, finished or still training, or a
committed baseline record, with the cell it trained (hivex_dsl/evaluation/original/compare.py measures it)."""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ...base.errors import HivexError
from .compare import CompareError, RunCurve, from_points, paper_task_index, seed_curves, seed_words


@dataclass(frozen=True)
class Run:
    """A run read from disk: its curve and the cell it trained (environment id, the paper's task index, level)."""

    curve: RunCurve
    environment: str
    task_index: int
    level: int | None
    others: tuple[RunCurve, ...] = ()  # a record's other training seeds with curves


def read_run(path: Path) -> Run:
    """A `hivex train` run directory (curve.json and summary.json; a run still training, or stopped before its end,
    without summary.json: its config.json and the curve to its last checkpoint) or a committed baseline record (a
    .json file)."""
    path = Path(path)
    if not path.exists():
        raise CompareError(f"{path}: no such run directory or baseline record")
    try:
        others: list[RunCurve] = []
        if path.is_dir() and not (path / "summary.json").exists() and (path / "config.json").exists():
            summary = _unfinished_summary(path)
            if not (path / "curve.json").exists():
                raise CompareError(f"{path} is a run of `hivex train` still training (or stopped before its first "
                                   "checkpoint) with no curve yet: it writes curve.json with every checkpoint")
            curve = from_points(json.loads((path / "curve.json").read_text()),
                                f"this toolkit, {_seed_words(path, summary)} (unfinished)")
        elif path.is_dir():
            summary = json.loads((path / "summary.json").read_text())
            curve = from_points(json.loads((path / "curve.json").read_text()), f"this toolkit, {_seed_words(path, summary)}")
        else:
            summary = json.loads(path.read_text())
            curve, *others = seed_curves(summary)
        environment, task, level = summary["environment"], summary["task_index"], summary["level"]
    except FileNotFoundError as exc:
        raise CompareError(f"{path} is no run directory of `hivex train` (no {Path(exc.filename).name}) and no "
                           "baseline record") from None
    except (KeyError, TypeError, ValueError) as exc:
        raise CompareError(f"{path} is no run directory of `hivex train` and no baseline record ({exc})") from None
    return Run(curve, environment, paper_task_index(environment, task), level, tuple(others))


def _seed_words(path: Path, summary: dict[str, Any]) -> str:
    """The run's seed in words, with its training worlds' where its config.json names its own (:func:`seed_words`)."""
    config = path / "config.json"
    hyperparameters = json.loads(config.read_text())["hyperparameters"] if config.exists() else {}
    return seed_words({"seed": summary["seed"], "world_seed": hyperparameters.get("world_seed")})


def _unfinished_summary(path: Path) -> dict[str, Any]:
    """What summary.json would say of a run directory without one: its environment, task index, level and seed,
    from the config.json `hivex train` writes as it starts (the scenario as it resolved, compiled again)."""
    from ...compiler import compile as compile_scenario

    config = json.loads((path / "config.json").read_text())
    try:
        compiled = compile_scenario(config["scenario"])
    except HivexError as exc:
        raise CompareError(f"{path}/config.json: its scenario no longer compiles ({exc})") from None
    return {"environment": compiled.environment, "task_index": compiled.task_index, "level": compiled.level,
            "seed": config["hyperparameters"]["seed"]}


__all__ = ["Run", "read_run"]
