"""Learning curves beside the original's: a run's training return at fractions of the budget against the
band of the original's runs.

A curve is a sequence of ``(agent_steps, value)`` summary points, as ``hivex train`` writes them
(``curve.json``: the mean return of the agent-episodes that ended since the last point) and as ML-Agents
logged them. One summary point of Wind Farm Control is one episode of a farm (40,000 agent-steps in the
original), so a single point swings with that episode's wind; the value "at" a step is therefore the mean
of the points in a window before it (``window`` of the budget, 5% by default: ten of the original's points).

The original's own curves ship as package data (``hivex_dsl/data/original-wfc-main-curves.json``, extracted
from its TensorBoard scalars by ``benchmarks/extract_original_wfc_curves.py``): Wind Farm Control's main
task on pattern 0, three training runs.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from functools import lru_cache
from importlib import resources
from typing import Any, Optional, Sequence

FRACTIONS = (0.1, 0.25, 0.5, 1.0)
WINDOW = 0.05
ORIGINAL_FILE = "original-wfc-main-curves.json"
RETURN = "Environment/Cumulative Reward"

Curve = Sequence[Sequence[float]]  # (agent_steps, value) pairs in step order


def window_mean(curve: Curve, end: float, width: float) -> Optional[float]:
    """Mean value of the points with ``end - width < step <= end``; None when no point falls there."""
    values = [float(value) for step, value in curve if end - width < step <= end]
    return sum(values) / len(values) if values else None


@dataclass(frozen=True)
class CurvePoint:
    """Both sides at one fraction of the budget: each run's window mean (None: the run has no point there)."""

    fraction: float
    step: int
    ours: tuple[Optional[float], ...]
    theirs: tuple[Optional[float], ...]

    @staticmethod
    def _present(values: tuple[Optional[float], ...]) -> list[float]:
        return [v for v in values if v is not None]

    @property
    def ours_mean(self) -> Optional[float]:
        present = self._present(self.ours)
        return sum(present) / len(present) if present else None

    @property
    def band(self) -> Optional[tuple[float, float]]:
        """(lowest, highest) of the original's runs."""
        present = self._present(self.theirs)
        return (min(present), max(present)) if present else None

    @property
    def verdict(self) -> str:
        """'inside', 'above' or 'below' the original's band (our runs' mean against it), or 'no data'."""
        if self.ours_mean is None or self.band is None:
            return "no data"
        low, high = self.band
        return "below" if self.ours_mean < low else "above" if self.ours_mean > high else "inside"


def compare_curves(ours: Sequence[Curve], theirs: Sequence[Curve], budget: int,
                   fractions: Sequence[float] = FRACTIONS, window: float = WINDOW) -> list[CurvePoint]:
    """Every run of both sides at each fraction of ``budget`` agent-steps (window means, see the module)."""
    if budget <= 0 or not 0.0 < window <= 1.0 or any(not 0.0 < f <= 1.0 for f in fractions):
        raise ValueError(f"budget must be > 0 and window and fractions in (0, 1]: {budget}, {window}, {fractions}")
    width = window * budget
    points = []
    for fraction in fractions:
        end = fraction * budget
        points.append(CurvePoint(fraction, round(end), tuple(window_mean(c, end, width) for c in ours),
                                 tuple(window_mean(c, end, width) for c in theirs)))
    return points


@lru_cache(maxsize=1)
def _original() -> dict[str, Any]:
    text = resources.files("hivex_dsl").joinpath("data", ORIGINAL_FILE).read_text(encoding="utf-8")
    return json.loads(text)


def original_wfc_main(statistic: str = RETURN, split: str = "train") -> list[list[tuple[int, float]]]:
    """The original's WFC main-task (pattern 0) runs of one logged scalar, each as (agent_steps, value) pairs."""
    part = _original()[split]
    if statistic not in part["runs"]:
        raise KeyError(f"no {statistic!r} in the original's WFC curves; there are {sorted(part['runs'])}")
    return [list(zip(part["steps"], run)) for run in part["runs"][statistic]]


def comparison_table(points: Sequence[CurvePoint]) -> str:
    """A markdown table: each fraction's step, our runs and their mean, the original's runs and band, the verdict."""
    show = lambda v: "-" if v is None else f"{v:,.0f}"  # noqa: E731
    rows = ["| Budget | Agent-steps | Ours (each run) | Ours (mean) | Original (each run) | Verdict |",
            "|---:|---:|---|---:|---|---|"]
    for p in points:
        rows.append(f"| {p.fraction:.0%} | {p.step:,} | {', '.join(show(v) for v in p.ours)} | {show(p.ours_mean)} "
                    f"| {', '.join(show(v) for v in p.theirs)} | {p.verdict} |")
    return "\n".join(rows)
