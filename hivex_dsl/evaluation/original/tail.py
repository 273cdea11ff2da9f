"""The end of training pooled: our value over the last tenth of the original's budget against the original's.

The measure of :mod:`.compare` reads one summary point of the original's at each fraction of its budget, and one
point is the draw of the episodes that ended in it. The original's three runs may draw the same ones (Wildfire
Resource Management's fires: its band about 5% of its mean where its mean moves about 31% from one point to the
next), so a verdict there can read that draw where a pool over many points reads the policy. :func:`tail` pools a
panel over the last :data:`TAIL` of the budget: ours the mean of our points past its start weighted by their
episodes (Episode Length as ML-Agents logged it, :func:`~.compare.as_logged_there`), the original's the mean of its
summary points' means past it; their ratio says how near the end of training ours is. :func:`tail_seeds` does so
for every training seed and their mean (unweighted, one value a seed, as the original's mean is of its three runs),
:func:`tail_table` writes that as Markdown.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

import numpy as np

from .compare import CompareError, RunCurve, as_logged_there, number, shared_panels
from .seeds import mean_of_seeds
from .curves import OriginalCell
from .evidence import RETURN

TAIL = 0.1  # of the original's budget: the end of training :func:`tail` pools


@dataclass(frozen=True)
class Tail:
    """A panel pooled over the last :data:`TAIL` of the original's budget, from ``start`` agent-steps to its end:
    ``ours`` (None where no point of ours with a value lies there) and ``theirs``."""

    panel: str
    ours: float | None
    theirs: float
    start: int

    @property
    def ratio(self) -> float | None:
        """Ours over the original's (None where ours has no point there or theirs is 0)."""
        return None if self.ours is None or self.theirs == 0 else self.ours / self.theirs


def tail(run: RunCurve, cell: OriginalCell, panel: str = RETURN, share: float = TAIL) -> Tail:
    """``panel`` over the last ``share`` of the original's budget (the last step of that panel's training curve),
    ours and the original's (see the module's docstring); our points past the budget are left out."""
    if not 0.0 < share <= 1.0:
        raise CompareError(f"the pool reads a share of the original's budget in (0, 1]: {share}")
    training = cell.panels[panel].training if panel in cell.panels else None
    if training is None or not len(training.band_steps):
        raise CompareError(f"the original's {cell.file} draws no training band of {panel}")
    budget = training.last_step
    start = (1.0 - share) * budget
    theirs = float(np.mean(training.mean_at(training.band_steps[training.band_steps > start])))
    values = as_logged_there(panel, run.panels[panel]) if panel in run.panels else np.full(len(run.steps), np.nan)
    late = (run.steps > start) & (run.steps <= budget) & ~np.isnan(values)
    weights = run.episodes[late]
    ours = float((values[late] * weights).sum() / weights.sum()) if weights.sum() > 0 else None
    return Tail(panel, ours, theirs, int(start))


@dataclass(frozen=True)
class SeedsTail:
    """A panel pooled over the end of training for every seed (``seeds``, in the runs' order) and the original's."""

    panel: str
    seeds: tuple[Tail, ...]
    theirs: float
    start: int

    @property
    def value(self) -> float | None:
        """The mean of the seeds that have a point there (None: none has)."""
        return mean_of_seeds([t.ours for t in self.seeds])

    @property
    def ratio(self) -> float | None:
        return None if self.value is None or self.theirs == 0 else self.value / self.theirs


def tail_seeds(runs: Sequence[RunCurve], cell: OriginalCell, share: float = TAIL) -> list[SeedsTail]:
    """:func:`tail` of every run and their mean, per panel the first run shares with the original
    (:func:`~.compare.shared_panels`, its order)."""
    if not runs:
        raise CompareError("no training seed to pool")
    rows = []
    for panel in shared_panels(runs[0], cell):
        seeds = tuple(tail(run, cell, panel, share) for run in runs)
        rows.append(SeedsTail(panel, seeds, seeds[0].theirs, seeds[0].start))
    return rows


def _pooled(value: float | None, ratio: float | None) -> str:
    return "-" if value is None else number(value) + ("" if ratio is None else f" ({ratio:.2f})")


def tail_table(rows: Sequence[SeedsTail], labels: Sequence[str]) -> str:
    """:func:`tail_seeds` as a Markdown table: panel, from which agent-step, each seed (``labels``: its pooled value
    and its ratio to the original's), the seeds' mean and its ratio, the original's pooled value."""
    seeds = "".join(f" {label} |" for label in labels)
    lines = [f"| panel | from agent-step |{seeds} mean of seeds | original |",
             "| --- | --- |" + " --- |" * len(labels) + " --- | --- |"]
    for r in rows:
        each = "".join(f" {_pooled(t.ours, t.ratio)} |" for t in r.seeds)
        lines.append(f"| {r.panel} | {r.start:,} |{each} {_pooled(r.value, r.ratio)} | {number(r.theirs)} |")
    return "\n".join(lines)


__all__ = ["SeedsTail", "TAIL", "Tail", "tail", "tail_seeds", "tail_table"]
