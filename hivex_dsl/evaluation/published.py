"""The paper's published test results as data: one :class:`PublishedCell` per environment, task and level.

The results ship inside the package (``hivex_dsl/data/published-test-results.json``, copied from
hivex-research/hivex-results' best models: PPO with learning rate 0 on the test seed 6000). Task keys
are the configs' 0-based task values, which are this toolkit's task indices (the file's notes say how
the Drone-Based Reforestation and Wildfire Resource Management keys were reconciled). Levels are the
Wind Farm Control pattern (0-8), the terrain level (1-10), or ``None`` for Ocean Plastic Collection.

Every value is the per-agent sum of a logged statistic over a test episode, averaged over test
episodes (mean) with its standard deviation. Statistic names are the logged ones, e.g.
``"Environment/Cumulative Reward"`` (the return) or ``"AerialWildfireSuppression/Water Pickup"``.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from functools import lru_cache
from importlib import resources
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from ..compiler import CompiledScenario

RETURN = "Environment/Cumulative Reward"
DATA_FILE = "published-test-results.json"


@dataclass(frozen=True)
class PublishedCell:
    """One published result: an environment, task and level, its return and every logged statistic."""

    environment: str
    task_index: int
    level: int | None
    return_mean: float
    return_std: float
    statistics: dict[str, tuple[float, float]]  # logged name -> (mean, std), the return included

    def statistic(self, name: str) -> tuple[float, float] | None:
        """(mean, std) of a statistic by its logged name, with or without the ``"<Environment>/"`` prefix."""
        if name in self.statistics:
            return self.statistics[name]
        for logged, value in self.statistics.items():
            if short_name(logged) == name:
                return value
        return None


def short_name(logged: str) -> str:
    """A logged name without its ``"<Environment>/"`` prefix: ``"Water Pickup"``."""
    return logged.split("/", 1)[-1]


@lru_cache(maxsize=1)
def raw() -> dict[str, Any]:
    """The whole file: ``source``, ``layout``, ``results`` and ``notes``."""
    text = resources.files("hivex_dsl").joinpath("data", DATA_FILE).read_text(encoding="utf-8")
    return json.loads(text)


def notes() -> tuple[str, ...]:
    """How the file's task keys were reconciled with the configs."""
    return tuple(raw()["notes"])


def _level(key: str) -> int | None:
    return None if key == "none" else int(key)


def _cell(environment: str, task: str, level: str, stats: dict[str, dict[str, float]]) -> PublishedCell:
    statistics = {name: (float(v["mean"]), float(v["std"])) for name, v in stats.items()}
    mean, std = statistics[RETURN]
    return PublishedCell(environment, int(task), _level(level), mean, std, statistics)


@lru_cache(maxsize=1)
def _all() -> dict[tuple[str, int, int | None], PublishedCell]:
    table = {}
    for environment, tasks in raw()["results"].items():
        for task, levels in tasks.items():
            for level, stats in levels.items():
                cell_ = _cell(environment, task, level, stats)
                table[(environment, cell_.task_index, cell_.level)] = cell_
    return table


def environments() -> tuple[str, ...]:
    """Environment ids with published results, in the file's order."""
    return tuple(raw()["results"])


def cell(environment: str, task_index: int, level: int | None) -> PublishedCell | None:
    """The published cell of one environment, task index and level; ``None`` where the paper has none."""
    return _all().get((environment, task_index, level))


def cells(environment: str) -> list[PublishedCell]:
    """Every published cell of one environment, by task index then level."""
    found = [c for (env, _, _), c in _all().items() if env == environment]
    return sorted(found, key=lambda c: (c.task_index, -1 if c.level is None else c.level))


def cell_for(compiled: "CompiledScenario") -> PublishedCell | None:
    """The published cell a compiled scenario reproduces, if any: its task's paper index and its level, and the
    paper's setting of that task otherwise (see :func:`differences_from_paper`). A scenario that changes the
    agents, the episode, the weights, the terms or the params has no published result of its own."""
    if differences_from_paper(compiled):
        return None
    return paper_cell(compiled)


def paper_cell(compiled: "CompiledScenario") -> PublishedCell | None:
    """The published cell of the scenario's task and level, whatever else the scenario changes."""
    task_index = compiled.entry.reward_table.tasks[compiled.task_index].index
    return cell(compiled.environment, task_index, compiled.level)


# what a scenario may change and still reproduce its cell: its name and the seeds it plays
_NOT_COMPARED = ("name", "seeds")


def differences_from_paper(compiled: "CompiledScenario") -> list[str]:
    """The top-level keys (agents, episode_length, decision_period, weights, terms, params, ...) in which the
    scenario's resolved content differs from the paper's scenario of the same task and level; empty when it
    reproduces the paper's setting."""
    mine = compiled.resolved()
    paper = _paper_setting(compiled.environment, compiled.task_index, compiled.entry.info.level_field, compiled.level)
    return sorted(k for k in set(mine) | set(paper) if k not in _NOT_COMPARED and mine.get(k) != paper.get(k))


@lru_cache(maxsize=256)
def _paper_setting(environment: str, task_index: int, level_field: str | None, level: int | None) -> dict:
    from ..compiler import compile

    data: dict[str, Any] = {"hivex": 1, "environment": environment, "task": task_index}
    if level_field:
        data[level_field] = level
    return compile(data).resolved()


def caveat(compiled: "CompiledScenario") -> str | None:
    """Why the paper's cell of this task and level is not set beside the scenario, if one exists; else None."""
    cell_of_task = paper_cell(compiled)
    changed = differences_from_paper(compiled)
    if cell_of_task is None or not changed:
        return None
    return (f"the paper's result for this task and level (return {cell_of_task.return_mean:.4g}) is not this "
            f"scenario's: it differs from the paper's setting in {', '.join(changed)}")


__all__ = ["PublishedCell", "RETURN", "caveat", "cell", "cell_for", "cells", "differences_from_paper", "environments",
           "notes", "paper_cell", "raw", "short_name"]
