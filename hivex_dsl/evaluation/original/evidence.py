"""What the original's curves show about its episodes and budgets: decision periods, training budgets, learning.

Read from :mod:`hivex_dsl.evaluation.original.curves` (the original's plot pages as data), not from this toolkit's
defaults:

- :func:`episode_ceiling` / :func:`decision_period`: ML-Agents' ``Environment/Episode Length`` counts an
  agent's decisions; an episode cut by Unity's ``MaxStep`` (physics steps) at decision period k logs
  ``MaxStep / k - 1`` of them (Wind Farm Control: 4,999 for 5,000). The longest length any cell shows, when it
  is such a ceiling (reached with the band collapsed on it: every run cut there), gives k.
- :func:`budgets`: the step axis of the training and test curves against the paper's appendix.
- :func:`learning_points`: a panel's mean and band at fractions of the training budget (0: the untrained
  policy's first summary point).
- :func:`best_of_three`: a published cell against the three test runs it was chosen from.
- :func:`pooled_ratio`: one panel sum over another's across a stretch of training (trees wetted a water drop).

``python -m hivex_dsl.evaluation.original.evidence`` prints :func:`summary`, the tables in Markdown.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...base.errors import HivexError
from .. import published
from .curves import Curve, OriginalCell, average_sheet, original_cells, original_curves

EPISODE_LENGTH = "Episode Length"
RETURN = "Cumulative Reward"
# Unity's MaxStep per environment, in physics steps: the configs that ran count an episode so in their
# comments ("3 agents a 2000 steps"), and the paper says 2,000 for DBR.
MAX_STEP = {"wind_farm_control": 5000, "ocean_plastic_collection": 5000, "drone_based_reforestation": 2000,
            "wildfire_resource_management": 500, "aerial_wildfire_suppression": 3000}
# The paper appendix's trainer configs: (max_steps, summary_freq) in agent-steps.
APPENDIX = {"wind_farm_control": (8_000_000, 40_000), "wildfire_resource_management": (4_500_000, 4_500),
            "drone_based_reforestation": (2_000_000, 10_000), "ocean_plastic_collection": (3_000_000, 15_000),
            "aerial_wildfire_suppression": (1_800_000, 9_000)}
FRACTIONS = (0.0, 0.1, 0.25, 0.5, 1.0)
# what tells Drone-Based Reforestation's tasks apart on the pages (the configs that ran name file tasks 2 and 3
# Pick Up Seed and Drop Seed; the published results' note keys them by the appendix's list)
DBR_TASK_STATISTICS = ("Tree Drop Count", "Recharge Energy Count", "Out of Energy Count",
                       "Highest Potential Soild Found", "Highest Point on Terrain Found", "Furthest Distance Explored",
                       "Environment/Cumulative Reward", "Environment/Episode Length")


class EvidenceError(HivexError, ValueError):
    """The curves do not show what was asked of them (e.g. no episode reaches the time limit)."""


@dataclass(frozen=True)
class CellLength:
    """One cell's Episode Length: the longest training mean, band edge and test mean, and how many training
    summary points sit on the environment's ceiling with the band collapsed (every run's episodes cut there)."""

    task_index: int
    level: int | None
    file: str
    training_mean_max: float
    training_upper_max: float
    test_mean_max: float | None
    points_at_ceiling: int
    points: int


@dataclass(frozen=True)
class EpisodeCeiling:
    """The longest Episode Length of an environment's cells and the decision period it implies."""

    environment: str
    max_step: int
    longest: float
    cells: tuple[CellLength, ...]

    @property
    def period_bound(self) -> int:
        """The largest decision period the longest episode allows: ``longest <= MaxStep / k - 1``."""
        return int(self.max_step // (self.longest + 1))

    @property
    def at_time_limit(self) -> bool:
        """Whether the longest length is the time limit's ceiling ``MaxStep / k - 1`` for a whole k, reached
        by every run at once somewhere."""
        k = self.period_bound
        return abs((self.longest + 1) * k - self.max_step) < 0.5 and any(c.points_at_ceiling for c in self.cells)


def _max(values: np.ndarray) -> float:
    return float(values.max()) if len(values) else float("-inf")


def _cell_length(cell: OriginalCell, ceiling: float, tolerance: float) -> CellLength | None:
    panel = cell.panel(EPISODE_LENGTH)
    if panel is None or panel.training is None:
        return None
    train, test = panel.training, panel.test
    on_ceiling = int(np.sum((train.lower >= ceiling - tolerance) & (train.upper <= ceiling + tolerance)))
    return CellLength(cell.task_index, cell.level, cell.file, _max(train.mean), _max(train.upper),
                      _max(test.mean) if test is not None else None, on_ceiling, len(train.band_steps))


def episode_ceiling(environment: str) -> EpisodeCeiling:
    """Every cell's Episode Length and the longest of them, against the environment's MaxStep."""
    cells = [c for c in original_cells(environment) if c.panel(EPISODE_LENGTH) is not None]
    if not cells:
        raise EvidenceError(f"{environment}: no cell page has an Episode Length panel")
    longest = max(max(_max(p.training.mean), _max(p.training.upper)) for p in
                  (c.panel(EPISODE_LENGTH) for c in cells) if p is not None and p.training is not None)
    tolerance = max(10.0 ** -c.panel(EPISODE_LENGTH).y_decimals for c in cells)  # type: ignore[union-attr]
    lengths = tuple(x for x in (_cell_length(c, longest, tolerance) for c in cells) if x is not None)
    return EpisodeCeiling(environment, MAX_STEP[environment], longest, lengths)


def decision_period(environment: str) -> int:
    """The decision period the original's Episode Length panels show: MaxStep / (ceiling + 1)."""
    ceiling = episode_ceiling(environment)
    if not ceiling.at_time_limit:
        raise EvidenceError(f"{environment}: the longest Episode Length {ceiling.longest:g} is no time-limit "
                            f"ceiling MaxStep / k - 1 of MaxStep {ceiling.max_step}; the period is at most "
                            f"{ceiling.period_bound}")
    return ceiling.period_bound


def runs_agree(environment: str, panel: str = EPISODE_LENGTH) -> float:
    """The share of training summary points, over every cell, at which the band is collapsed: all three runs
    logged the same value (WRM's Episode Length: every point, so its episodes end whatever the policy does)."""
    agree, total = 0, 0
    for cell in original_cells(environment):
        found = cell.panel(panel)
        if found is None or found.training is None:
            continue
        curve = found.training
        agree += int(np.sum(curve.upper - curve.lower <= 10.0 ** -found.y_decimals))
        total += len(curve.band_steps)
    if not total:
        raise EvidenceError(f"{environment}: no training band of {panel!r}")
    return agree / total


def training_average(environment: str, task_index: int, level: int | None, panel: str = EPISODE_LENGTH) -> float:
    """One cell's panel averaged over its training summary points (each the mean over the three runs): what the
    whole run logged. ML-Agents logs at each point the mean of the episodes that ended since the last (a window
    of summary_freq agent-steps), so a length averaged so weighs long episodes a little more than a mean over
    episodes would. Where no policy changes the panel (WRM's Episode Length: :func:`runs_agree` is 1) every
    point samples the same episodes' distribution, the untrained first one included, and this is its most
    precise reading."""
    return float(training_points(environment, task_index, level, panel).mean())


def training_spread(environment: str, task_index: int, level: int | None, panel: str = EPISODE_LENGTH) -> float:
    """How far one cell's training summary points (each the mean over the three runs) scatter: their sample
    standard deviation. Where no policy changes the panel it reads how widely the episodes behind the points
    spread, each point pooling the episodes that ended in its window; this toolkit's runs compare like with like
    when their episodes are pooled in the same windows (benchmarks/wrm_fire_length.py)."""
    return float(training_points(environment, task_index, level, panel).std(ddof=1))


def training_autocorrelation(environment: str, task_index: int, level: int | None, panel: str = EPISODE_LENGTH,
                             lag: int = 1) -> float:
    """The lag-``lag`` autocorrelation of one cell's training summary points (each the mean over the three runs):
    near 0 where a point's episodes do not depend on the last point's, toward 1 where a slowly changing condition
    of the run (a weather field that stays with it) carries over from point to point."""
    points = training_points(environment, task_index, level, panel)
    if not 1 <= lag < len(points):
        raise EvidenceError(f"lag {lag} must lie in [1, {len(points) - 1}] for {len(points)} training points")
    deviations = points - points.mean()
    return float((deviations[:-lag] * deviations[lag:]).sum() / (deviations * deviations).sum())


def training_points(environment: str, task_index: int, level: int | None, panel: str = EPISODE_LENGTH) -> np.ndarray:
    """(k,) one cell's panel at each training summary point, the mean over the three runs."""
    cell = original_curves(environment, task_index, level)
    found = cell.panel(panel) if cell is not None else None
    if found is None or found.training is None or not len(found.training.band_steps):
        raise EvidenceError(f"{environment} task {task_index} level {level}: no training band of {panel!r}")
    curve = found.training
    return np.asarray(curve.mean_at(curve.band_steps), dtype=float)


@dataclass(frozen=True)
class Budget:
    """The agent-steps an environment's curves span, beside the appendix's."""

    environment: str
    trained: int  # the training curves' last step (the x axis's reach)
    summary: int  # steps between training summary points
    tested: int  # the test curves' last step
    appendix_max_steps: int
    appendix_summary_freq: int


def _spacing(curve: Curve) -> int:
    steps = curve.band_steps if len(curve.band_steps) > 1 else curve.steps
    return int(np.median(np.diff(steps)))


def budgets(environment: str) -> Budget:
    """The longest training and test curves of any cell of the environment, and their summary interval."""
    panels = [p for c in original_cells(environment) for p in c.panels.values()]
    trained = max(p.training.last_step for p in panels if p.training is not None)
    tested = max(p.test.last_step for p in panels if p.test is not None)
    spacing = int(np.median([_spacing(p.training) for p in panels if p.training is not None]))
    return Budget(environment, trained, spacing, tested, *APPENDIX[environment])


@dataclass(frozen=True)
class LearningPoint:
    """A panel's training curve at a fraction of the budget: the summary point nearest it, the mean there
    and the band."""

    fraction: float
    step: int
    mean: float
    lower: float
    upper: float


def learning_points(environment: str, task_index: int, level: int | None, panel: str = RETURN,
                    fractions: tuple[float, ...] = FRACTIONS) -> list[LearningPoint]:
    """The training curve of one cell's panel at ``fractions`` of its last step (0: the first point)."""
    cell = original_curves(environment, task_index, level)
    found = cell.panel(panel) if cell is not None else None
    if found is None or found.training is None or not len(found.training.band_steps):
        raise EvidenceError(f"{environment} task {task_index} level {level}: no training band of {panel!r}")
    return curve_points(found.training, fractions)


def curve_points(curve: Curve, fractions: tuple[float, ...] = FRACTIONS) -> list[LearningPoint]:
    """A training curve (with its band) at ``fractions`` of its last step: the summary point nearest each."""
    points = []
    for fraction in fractions:
        i = int(np.argmin(np.abs(curve.band_steps - fraction * curve.last_step)))
        step = curve.band_steps[i]
        points.append(LearningPoint(fraction, int(step), float(curve.mean_at(step)), float(curve.lower[i]),
                                    float(curve.upper[i])))
    return points


@dataclass(frozen=True)
class BestOfThree:
    """A published cell's value beside the three test runs it was chosen from, each averaged over the test points.

    The published result is the best of three runs (its source says so; Wind Farm Control's event files show
    it: test run 2, the highest of the three, is the published cell) and its mean over that run's test points.
    A page's band is seaborn's 95% bootstrap interval over the three runs, which for three values is their
    minimum and maximum (a resample of the highest value thrice has probability 1/27 > 2.5%); so at each point
    the runs are the band's edges and three times the mean less both."""

    published: float
    lowest: float  # the band's lower edge: the worst run at each point
    mean: float  # the three runs' mean
    highest: float  # the band's upper edge: the best run at each point

    @property
    def other_two(self) -> float:
        """The mean of the two runs the published one was chosen over: (3 mean - published) / 2."""
        return (3.0 * self.mean - self.published) / 2.0

    @property
    def best_over_mean(self) -> float:
        """How far the published run stands above the three runs' mean, as a ratio."""
        return self.published / self.mean


def best_of_three(environment: str, task_index: int, level: int | None, panel: str = RETURN) -> BestOfThree:
    """One cell's published ``panel`` (the return by default) beside its three test runs."""
    cell = original_curves(environment, task_index, level)
    found = cell.panel(panel) if cell is not None else None
    paper = next((c for c in published.cells(environment) if (c.task_index, c.level) == (task_index, level)), None)
    if paper is None:
        value = None
    else:
        value = paper.return_mean if panel == RETURN else (paper.statistic(panel) or (None,))[0]
    if found is None or found.test is None or not len(found.test.band_steps) or value is None:
        raise EvidenceError(f"{environment} task {task_index} level {level}: no published {panel!r} with a test band")
    curve = found.test
    return BestOfThree(float(value), float(curve.lower.mean()), float(curve.mean_at(curve.band_steps).mean()),
                       float(curve.upper.mean()))


def pooled_ratio(environment: str, task_index: int, level: int | None, numerators: tuple[str, ...],
                 denominator: str, start: float = 0.0, stop: float = float("inf"), source: str = "training"
                 ) -> tuple[float, float]:
    """(sum of the ``numerators``' means / sum of the ``denominator``'s mean, the denominator's mean) over the
    summary points of ``source`` ("training" or "test") whose agent-step lies in [start, stop].

    A ratio of sums, not a mean of ratios: a point whose episodes held few of the denominator (a point of
    untrained planes that dropped water 0.8 times an episode) weighs by what it held instead of swinging the
    result. Each point is the mean of the three runs at the point (the runs' own episodes are not on the page)."""
    cell = original_curves(environment, task_index, level)
    panels = [cell.panel(name) if cell is not None else None for name in (denominator, *numerators)]
    curves = [getattr(p, source) if p is not None else None for p in panels]
    if any(c is None or not len(c.band_steps) for c in curves):
        raise EvidenceError(f"{environment} task {task_index} level {level}: no {source} band of every one of "
                            f"{(denominator, *numerators)}")
    steps = curves[0].band_steps[(curves[0].band_steps >= start) & (curves[0].band_steps <= stop)]
    if not len(steps):
        raise EvidenceError(f"{environment} task {task_index} level {level}: no {source} point in [{start:g}, {stop:g}]")
    below = float(curves[0].mean_at(steps).sum())
    if below <= 0:
        raise EvidenceError(f"{environment} task {task_index} level {level}: {denominator!r} is 0 in [{start:g}, {stop:g}]")
    above = sum(float(c.mean_at(steps).sum()) for c in curves[1:])
    return above / below, below / len(steps)


__all__ = ["APPENDIX", "BestOfThree", "Budget", "CellLength", "EpisodeCeiling", "EvidenceError", "LearningPoint",
           "MAX_STEP", "best_of_three", "budgets", "curve_points", "decision_period", "episode_ceiling",
           "learning_points", "pooled_ratio", "runs_agree", "sheet_rows", "summary", "training_average",
           "training_points", "training_spread"]


def _level(level: int | None) -> str:
    return "-" if level is None else str(level)


def _ceiling_rows(environment: str) -> list[str]:
    ceiling = episode_ceiling(environment)
    budget = budgets(environment)
    period = str(ceiling.period_bound) if ceiling.at_time_limit else f"<= {ceiling.period_bound}"
    at_limit = [c for c in ceiling.cells if c.points_at_ceiling]
    where = ", ".join(sorted({f"task {c.task_index}" for c in at_limit})) or "none"
    appendix = f"{budget.appendix_max_steps:,} ({budget.appendix_summary_freq:,})"
    return [f"| {environment} | {ceiling.max_step:,} | {ceiling.longest:,.0f} | {period} | {where} | "
            f"{runs_agree(environment):.0%} | {budget.trained:,} ({budget.summary:,}) | {appendix} | "
            f"{budget.tested:,} |"]


def _task_rows(environment: str) -> list[str]:
    """Per task: the longest training mean and band edge over its levels, and the levels where every run's
    episodes reach the ceiling."""
    ceiling = episode_ceiling(environment)
    rows = []
    for task in sorted({c.task_index for c in ceiling.cells}):
        cells = [c for c in ceiling.cells if c.task_index == task]
        means = [c.training_mean_max for c in cells]
        uppers = [c.training_upper_max for c in cells]
        at_limit = sum(1 for c in cells if c.points_at_ceiling)
        rows.append(f"| {environment} | {task} | {min(means):,.0f} - {max(means):,.0f} | "
                    f"{min(uppers):,.0f} - {max(uppers):,.0f} | {at_limit} of {len(cells)} |")
    return rows


def sheet_rows(environment: str, level: int | None, tags: tuple[str, ...]) -> list[str]:
    """A Markdown table of the average sheet: a row per task (the file's index) at one level, a column per tag
    (``-`` where the sheet has no value)."""
    sheet = average_sheet(environment)
    tasks = sorted({c.task_index for c in original_cells(environment)})
    rows = ["| task | " + " | ".join(tags) + " |", "| --- |" + " --- |" * len(tags)]
    for task in tasks:
        values = [sheet.get(tag, {}).get((task, level)) for tag in tags]
        rows.append(f"| {task} | " + " | ".join("-" if v is None else f"{v.value:g}" for v in values) + " |")
    return rows


def _points_table(points: list[LearningPoint]) -> list[str]:
    rows = ["| fraction | agent-step | mean | band |", "| --- | --- | --- | --- |"]
    rows += [f"| {p.fraction:.0%} | {p.step:,} | {p.mean:,.1f} | {p.lower:,.1f} - {p.upper:,.1f} |" for p in points]
    return rows


def summary() -> str:
    """The evidence as Markdown: decision periods and budgets per environment, WFC's learning and OPC's
    vessel-episode lengths."""
    lines = ["Decision periods and budgets from the original's curves (hivex_dsl/data/original-curves.json.xz).",
             "Episode Length counts decisions; an episode cut at MaxStep physics steps logs MaxStep / k - 1.", "",
             "| environment | MaxStep | longest Episode Length | decision period | cells at the limit (every run) | "
             "points where the runs' lengths agree | trained to (summary) | appendix (summary) | tested to |",
             "| --- | --- | --- | --- | --- | --- | --- | --- | --- |"]
    for environment in MAX_STEP:
        lines += _ceiling_rows(environment)
    lines += ["", "Per task (the file's task_<n>), over its levels: the longest Episode Length in training.", "",
              "| environment | task | longest mean | longest band edge | levels where every run reaches the ceiling |",
              "| --- | --- | --- | --- | --- |"]
    for environment in MAX_STEP:
        lines += _task_rows(environment)
    lines += ["", "Wind Farm Control, pattern 0, main task: the return (Cumulative Reward) in training, mean and "
              "band of three runs."]
    lines += ["", *_points_table(learning_points("wind_farm_control", 0, 0))]
    lines += ["", "Ocean Plastic Collection, main task: Episode Length (decisions per vessel-episode) in training.", ""]
    lines += _points_table(learning_points("ocean_plastic_collection", 0, None, EPISODE_LENGTH))
    lines += ["", "Drone-Based Reforestation at level 1, by the pages' task index: each cell's average over its test "
              "curve, from the average sheet.", ""]
    lines += sheet_rows("drone_based_reforestation", 1, DBR_TASK_STATISTICS)
    return "\n".join(lines)


if __name__ == "__main__":
    print(summary())
