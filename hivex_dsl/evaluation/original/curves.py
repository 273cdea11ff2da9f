"""The original release's learning curves as data: every statistic of every published cell, training and test.

``hivex_dsl/data/original-curves.json.xz`` holds the original's own plot pages read back as numbers
(:mod:`hivex_dsl.evaluation.original.digitise` writes it from the PDFs; its docstring says the precision). Per
cell, per panel (a logged TensorBoard scalar, keyed by the panel's title: ``"Cumulative Reward"``, ``"Episode Length"``,
``"Water Pickup"``), a training and a test :class:`Curve`: the mean of three runs as the vertices the PDF kept,
and seaborn's 95% bootstrap band over the runs at every summary point, against agent-steps (decisions).

Cells are keyed as :mod:`hivex_dsl.evaluation.published` keys them (environment id, task index, level: WFC
pattern, terrain level, ``None`` for OPC), with the task index the page's own file name gives (``task_<n>``,
the configs that ran; Drone-Based Reforestation's differ from the published results' keys: see the
published file's notes). Each cell records its file name and page title.
"""

from __future__ import annotations

import json
import lzma
from dataclasses import dataclass
from functools import lru_cache
from importlib import resources
from typing import Any

import numpy as np

from ...base.errors import HivexError, did_you_mean
from .heatmap import Annotation

DATA_FILE = "original-curves.json.xz"
# ML-Agents' own scalars, by the last part of their name (the panel titles)
_TRAINER_TAGS = {name.split("/")[-1]: name for name in (
    "Environment/Cumulative Reward", "Environment/Episode Length", "Policy/Entropy", "Policy/Learning Rate",
    "Policy/Epsilon", "Policy/Beta", "Policy/Extrinsic Value Estimate", "Policy/Extrinsic Reward",
    "Policy/Curiosity Value Estimate", "Policy/Curiosity Reward", "Losses/Policy Loss", "Losses/Value Loss",
    "Losses/Curiosity Forward Loss", "Losses/Curiosity Inverse Loss")}


class UnknownEnvironment(HivexError, KeyError):
    """An environment id the original's curves do not hold."""

    def __str__(self) -> str:
        return str(self.args[0])


@dataclass(frozen=True)
class Curve:
    """One source (training or test) of a panel, against agent-steps.

    ``steps``/``mean`` (k,): the mean over the three runs at the line's vertices (the points the PDF kept);
    ``band_steps``/``lower``/``upper`` (n,): the band at every summary point (empty when the page drew none)."""

    steps: np.ndarray
    mean: np.ndarray
    band_steps: np.ndarray
    lower: np.ndarray
    upper: np.ndarray

    def mean_at(self, steps: np.ndarray | float) -> np.ndarray:
        """The mean, linearly interpolated between the kept vertices, at ``steps`` (any shape); the line
        lies within 1/9 pt on the page of the points the PDF dropped."""
        return np.interp(np.asarray(steps, dtype=float), self.steps, self.mean)

    @property
    def last_step(self) -> int:
        """The furthest agent-step the curve reaches."""
        return int(max(self.steps.max(), self.band_steps.max() if len(self.band_steps) else 0))


@dataclass(frozen=True)
class OriginalPanel:
    """One logged scalar of a cell: its title, its TensorBoard name where known, and its curves."""

    title: str
    tag: str | None
    y_decimals: int  # the stored values' decimal places (a power of ten within 0.001 pt of the page)
    x_per_pt: float  # agent-steps per point of the page's x axis
    y_per_pt: float  # data units per point of the page's y axis: the page's resolution of this panel
    training: Curve | None
    test: Curve | None


@dataclass(frozen=True)
class OriginalCell:
    """One cell page: its key, its file name and page title, and its panels by title."""

    environment: str
    task_index: int
    level: int | None
    file: str
    title: str
    panels: dict[str, OriginalPanel]

    def panel(self, name: str) -> OriginalPanel | None:
        """A panel by its title (``"Episode Length"``) or its TensorBoard name (``"Environment/Episode Length"``)."""
        if name in self.panels:
            return self.panels[name]
        return next((p for p in self.panels.values() if p.tag == name), None)


@lru_cache(maxsize=1)
def raw() -> dict[str, Any]:
    """The whole file: ``source``, ``layout``, ``precision``, ``cells`` and ``average_sheets``."""
    packed = resources.files("hivex_dsl").joinpath("data", DATA_FILE).read_bytes()
    return json.loads(lzma.decompress(packed))


def environments() -> tuple[str, ...]:
    """Environment ids with curves."""
    return tuple(raw()["cells"])


def _frozen(values: list) -> np.ndarray:
    """A read-only array: cells are cached and shared between callers."""
    array = np.asarray(values, dtype=float)
    array.setflags(write=False)
    return array


def _curve(data: dict[str, Any] | None) -> Curve | None:
    if data is None:
        return None
    steps, mean = (_frozen(v) for v in data["line"])
    band = [_frozen(v) for v in data.get("band", ([], [], []))]
    return Curve(steps, mean, *band)


def _tag(environment: str, title: str) -> str | None:
    """The full TensorBoard name of a panel title: ML-Agents' own, or a published statistic of the environment."""
    if title in _TRAINER_TAGS:
        return _TRAINER_TAGS[title]
    from .. import published

    names = {name for c in published.cells(environment) for name in c.statistics}
    found = sorted(name for name in names if published.short_name(name) == title)
    return found[0] if len(found) == 1 else None


def _cell(environment: str, task: str, level: str, data: dict[str, Any]) -> OriginalCell:
    panels = {title: OriginalPanel(title, _tag(environment, title), p["y_decimals"], p["x_per_pt"], p["y_per_pt"],
                                   _curve(p.get("training")), _curve(p.get("test")))
              for title, p in data["panels"].items()}
    return OriginalCell(environment, int(task), None if level == "none" else int(level), data["file"],
                        data["title"], panels)


def _known(environment: str) -> dict[str, Any]:
    cells = raw()["cells"]
    if environment not in cells:
        raise UnknownEnvironment(f"no original curves for environment {environment!r}"
                                 f"{did_you_mean(environment, cells)}")
    return cells[environment]


@lru_cache(maxsize=None)
def original_curves(environment: str, task_index: int, level: int | None) -> OriginalCell | None:
    """The original's curves of one cell (task index as the page's file name gives it); ``None`` where the
    original has no page for it. Raises :class:`UnknownEnvironment` for an environment id it does not hold."""
    tasks = _known(environment)
    data = tasks.get(str(task_index), {}).get("none" if level is None else str(level))
    return None if data is None else _cell(environment, str(task_index), "none" if level is None else str(level), data)


def average_sheet(environment: str) -> dict[str, dict[tuple[int, int | None], Annotation]]:
    """The environment's average sheet: per tag (as the sheet titles it: ``"Environment/Episode Length"``,
    ``"Water Pickup"``), per (task index, level), each cell's average over its test curve as printed."""
    _known(environment)
    sheet = raw()["average_sheets"].get(environment, {})
    return {tag: {(int(task), None if level == "none" else int(level)): Annotation(*value)
                  for task, levels in tasks.items() for level, value in levels.items()}
            for tag, tasks in sheet.items()}


def original_cells(environment: str) -> list[OriginalCell]:
    """Every cell page of one environment, by task index then level."""
    found = [original_curves(environment, int(task), None if level == "none" else int(level))
             for task, levels in _known(environment).items() for level in levels]
    return sorted((c for c in found if c is not None),
                  key=lambda c: (c.task_index, -1 if c.level is None else c.level))


__all__ = ["Curve", "DATA_FILE", "OriginalCell", "OriginalPanel", "UnknownEnvironment", "average_sheet",
           "environments", "original_cells", "original_curves", "raw"]
