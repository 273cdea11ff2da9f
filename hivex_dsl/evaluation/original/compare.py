"""Our learning curves beside the original's: the measure of issue 52 and the figure.

A :class:`RunCurve` is one of our runs' training curve: per summary point the agent-steps, the episodes it pools,
and per panel (the original's panel titles: ``"Cumulative Reward"``, ``"Episode Length"`` and the statistics,
which this toolkit names as the original logs them, :mod:`hivex_dsl.sim.statistics`, and with curiosity
``"Curiosity Reward"``, an agent-episode's sum of its strength-weighted rewards) the value. It is read from a
run directory's curve.json (:func:`from_points`) or a committed baseline record, which keeps the return, and since
issue 52 Episode Length and the statistics too (:func:`from_record`, :func:`record_panels`; :func:`seed_curves` gives every training seed a record holds, :func:`is_stale` whether its
note marks it trained before a simulator change).

The measure (:func:`measure`): at 10, 25, 50 and 100% of the original's training budget (the last step of its
curve: the config that ran), our value against the original's band of three runs at the summary point nearest
that step (:func:`~hivex_dsl.evaluation.original.evidence.curve_points`): within, above or below it. Ours at a
step ``s`` pools our points within half the original's summary interval ``w`` of ``s`` (a run that summarises every
``w`` agent-steps, as `hivex train` does by default, has one point there; one that logged every update, as the
recorded baselines did, has a summary period's worth), weighted by their episodes where known; where none lies
that close (a run whose episodes end seldom, as Wind Farm Control's 5,000-step ones with 256 slots: a point every
1.28M agent-steps), the nearest point within 5% of the budget, named by its step; else none. Where the points
within ``w / 2`` hold fewer than half the episodes of a full point (the 95th percentile of the run's points), the
pool widens to the nearest points until they do, at most to 5% of the budget: our worlds start together, so the
episodes that run to the time limit end together in one point (12 worlds of 3 planes, as Aerial Wildfire
Suppression's grid trained: a point of up to 36 every 3,000 steps), and a narrow window between two such points
would hold only the odd early ending (a crash's -100 for a policy earning hundreds), where each of the original's
points averaged what ended in a window of worlds that had long since drifted apart. Several training seeds
(:func:`.seeds.measure_seeds`) are measured each so, and their mean (unweighted: each seed is one run, as each of the
original's three is one) against the same band. :mod:`.tail` pools every panel over the last tenth of the budget,
ours and the original's alike, which reads the policy where one point of the original's reads the draw of its
episodes (its runs may share them: Wildfire Resource Management's fires).

Our Episode Length is set beside theirs as ML-Agents logged it (:func:`as_logged_there`): its AgentProcessor counts
an episode's experiences less the terminal one, so an episode of ``n`` decisions logs ``n - 1`` (Wind Farm Control's
5,000-decision episodes: 4,999 at every one of the original's points), where a RunCurve, a run's curve.json and a
record hold our decisions.

:mod:`.figure` draws every panel both log: our curves over the original's mean and band.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from typing import Any, Sequence

import numpy as np

from ...base.errors import HivexError
from .curves import OriginalCell
from .evidence import EPISODE_LENGTH, RETURN, curve_points

FRACTIONS = (0.1, 0.25, 0.5, 1.0)
NEAREST_WITHIN = 0.05  # of the budget: how far from a step our nearest point may lie where none is within w / 2
FULL_SHARE = 0.5  # of a full point's episodes: what ours at a step pools at least, where the budget allows
# a curve.json key of the trainer's own numbers (a signal's mean episode sum, a value head's mean estimate) -> the
# original's panel of the same number
SIGNAL_PANELS = {"curiosity_reward": "Curiosity Reward", "extrinsic_value_estimate": "Extrinsic Value Estimate",
                 "curiosity_value_estimate": "Curiosity Value Estimate"}
# a curve.json ``losses`` key (the updates' means since the last point) -> the original's panel of the same number:
# the policy's entropy as ML-Agents sums it (each discrete branch's, plus the Gaussian's mean over its dimensions;
# its AgentProcessor adds each decision's under the acting policy, ours is the update's minibatch mean over the same
# decisions, the policy moving only within its epochs) and the curiosity module's two losses as its
# CuriosityRewardProvider computes them. The policy and value losses stay out: ML-Agents logs the clipped
# surrogate's absolute value and its value heads' mean, not ours as written.
LOSS_PANELS = {"entropy": "Entropy", "curiosity_forward": "Curiosity Forward Loss",
               "curiosity_inverse": "Curiosity Inverse Loss"}


class CompareError(HivexError, ValueError):
    """A curve that cannot be compared: no points, or no panel the original's cell also logs."""


@dataclass(frozen=True)
class RunCurve:
    """One run's training curve: ``steps`` (n,) agent-steps, ``episodes`` (n,) episodes pooled per point (ones where
    unknown), ``panels`` title -> (n,) values (NaN where a point lacks it); ``test`` (steps, means) of checkpoints
    scored on the test seeds, where the run has them; ``label`` names the run in tables and legends; ``stale``: of a
    record trained before a simulator change (:func:`is_stale`)."""

    steps: np.ndarray
    episodes: np.ndarray
    panels: dict[str, np.ndarray]
    label: str = "this toolkit"
    test: tuple[np.ndarray, np.ndarray] | None = field(default=None)
    stale: bool = False

    @property
    def last_step(self) -> int:
        return int(self.steps.max()) if len(self.steps) else 0


def from_points(points: Sequence[dict[str, Any]], label: str = "this toolkit") -> RunCurve:
    """A run directory's curve.json rows (``agent_steps``, ``return``, ``episodes``; ``length``, ``statistics``,
    ``curiosity_reward``, the value estimates and ``losses`` where the run wrote them) as a :class:`RunCurve`."""
    if not points:
        raise CompareError("the run's curve has no point: no episode ended while it trained")
    steps = np.array([p["agent_steps"] for p in points], dtype=float)
    episodes = np.array([p.get("episodes", 1) for p in points], dtype=float)
    panels = {RETURN: np.array([p["return"] for p in points], dtype=float)}
    if any("length" in p for p in points):
        panels[EPISODE_LENGTH] = np.array([p.get("length", np.nan) for p in points], dtype=float)
    names = sorted({name for p in points for name in p.get("statistics", {})})
    panels |= {name: np.array([p.get("statistics", {}).get(name, np.nan) for p in points], dtype=float)
               for name in names}
    for key, panel in SIGNAL_PANELS.items():
        if any(key in p for p in points):
            panels[panel] = np.array([p.get(key, np.nan) for p in points], dtype=float)
    for key, panel in LOSS_PANELS.items():
        if any(key in p.get("losses", {}) for p in points):
            panels[panel] = np.array([p.get("losses", {}).get(key, np.nan) for p in points], dtype=float)
    return RunCurve(steps, episodes, panels, label)


STALE = re.compile(r"(?:^|[.!?]\s+)stale\b", re.IGNORECASE)  # a sentence of the note that begins "Stale"


def is_stale(record: dict[str, Any]) -> bool:
    """Whether a baseline or grid record's note marks it stale, in a sentence that begins so ("Stale (issue 52):
    trained with ...", "... Stale since issue 52: planes now fly ..."): trained before a change of the simulator or
    the defaults, so its numbers are of another world than the scenario's now."""
    return bool(STALE.search(str(record.get("note", "")).strip()))


def seed_curves(record: dict[str, Any]) -> list[RunCurve]:
    """Every training seed's curve a baseline record holds: its own (:func:`from_record`), then each of its
    ``other_seeds`` recorded with one (``curve`` rows as the record's); labelled "stale record" where
    :func:`is_stale`."""
    others = [e for e in record.get("other_seeds", []) if e.get("curve")]
    stale = {"note": record["note"]} if is_stale(record) else {}
    return [from_record(record)] + [from_record({**e, **stale, "environment": record.get("environment")})
                                    for e in others]


def from_record(record: dict[str, Any]) -> RunCurve:
    """A committed baseline record (benchmarks/baselines/<environment>.json), one of its ``other_seeds`` or a grid
    record's point: its training return per summary point (``curve`` rows: agent-steps, wall s, return), its other
    panels where it keeps them (:func:`record_panels`) and its checkpoints on the test seeds (``test_curve``)."""
    rows = record.get("curve") or []
    if not rows:
        raise CompareError(f"the record of {record.get('environment')} holds no training curve")
    steps = np.array([r[0] for r in rows], dtype=float)
    test = record.get("test_curve") or []
    test_curve = (np.array([r[0] for r in test], dtype=float), np.array([r[2] for r in test], dtype=float)) if test else None
    stale = is_stale(record)
    label = f"this toolkit, {seed_words(record)}" + (" (stale record)" if stale else "")
    kept = {name: values for name, values in (record.get("curve_panels") or {}).items()}
    episodes = record.get("curve_episodes") or [1] * len(rows)
    wrong = [name for name, values in [("curve_episodes", episodes), *kept.items()] if len(values) != len(rows)]
    if wrong:
        raise CompareError(f"the record of {record.get('environment')} (seed {record.get('seed', 0)}) keeps "
                           f"{', '.join(wrong)} of another length than its {len(rows)} curve rows")
    panels = {RETURN: np.array([r[2] for r in rows], dtype=float)}
    panels |= {name: np.array([np.nan if v is None else v for v in values], dtype=float) for name, values in kept.items()}
    return RunCurve(steps, np.array(episodes, dtype=float), panels, label, test_curve, stale)


def seed_words(record: dict[str, Any]) -> str:
    """A record's (or one of its ``other_seeds``') training seed, and its training worlds' where it trained on worlds
    of its own (``world_seed``): "seed 1", "seed 1 on worlds 5001"."""
    worlds = record.get("world_seed", (record.get("hyperparameters") or {}).get("world_seed"))
    return f"seed {record.get('seed', 0)}" + ("" if worlds in (None, "scenario") else f" on worlds {worlds}")


def record_panels(run: RunCurve, digits: int = 4) -> dict[str, Any]:
    """What a record keeps of a run's curve beside its ``curve`` rows, which hold the return: ``curve_episodes`` (the
    agent-episodes each point pools) and ``curve_panels`` (every other panel, Episode Length, the statistics and the
    trainer's own numbers, one value a point, null where a point lacks one), so :func:`from_record` gives back the run's :class:`RunCurve`."""
    def kept(values: np.ndarray) -> list[float | None]:
        return [None if np.isnan(v) else round(float(v), digits) for v in values]

    return {"curve_episodes": [int(e) for e in run.episodes],
            "curve_panels": {name: kept(values) for name, values in run.panels.items() if name != RETURN}}


@dataclass(frozen=True)
class Ours:
    """Our value at a step: the pooled mean and the steps of the points it pools (None: no point near)."""

    value: float | None
    first: int | None = None
    last: int | None = None


def pooled_radius(run: RunCurve, known: np.ndarray, distance: np.ndarray, window: float, budget: float) -> float:
    """How far from a step ours pools its points: ``window / 2``, widened to the nearest points that hold
    :data:`FULL_SHARE` of a full point's episodes (the 95th percentile of the run's points, ``known`` (n,) those
    with a value, ``distance`` (n,) from the step), but no further than :data:`NEAREST_WITHIN` of ``budget``."""
    episodes = run.episodes[known]
    if not len(episodes):
        return window / 2
    need = FULL_SHARE * np.percentile(episodes, 95)
    order = np.argsort(distance[known], kind="stable")
    reach = np.searchsorted(np.cumsum(episodes[order]), need)  # the first point at which the pooled reach need
    radius = float(distance[known][order[min(reach, len(order) - 1)]])
    return max(window / 2, radius) if radius <= NEAREST_WITHIN * budget else window / 2


def as_logged_there(panel: str, values: np.ndarray) -> np.ndarray:
    """Our ``panel``'s values (n,) as the original's trainer would have logged them. ML-Agents' AgentProcessor adds
    an experience for every decision, but counts toward Environment/Episode Length only those that are not the
    episode's last (``if not terminated: episode_steps += 1``), so an episode of ``n`` decisions, ended or cut by the
    time limit, logs ``n - 1``; the statistics and the return are sums it logs as they are."""
    return values - 1.0 if panel == EPISODE_LENGTH else values


def ours_at(run: RunCurve, panel: str, step: float, window: float, budget: float) -> Ours:
    """Our ``panel`` at ``step`` (:func:`as_logged_there`): the episode-weighted mean of our points within
    :func:`pooled_radius` of it, else the nearest point within :data:`NEAREST_WITHIN` of ``budget``, else none (see
    the module's docstring)."""
    values = as_logged_there(panel, run.panels[panel])
    known = ~np.isnan(values)
    distance = np.abs(run.steps - step)
    near = known & (distance <= pooled_radius(run, known, distance, window, budget))
    if near.any():
        weights = run.episodes[near]
        return Ours(float(np.sum(values[near] * weights) / np.sum(weights)), int(run.steps[near].min()),
                    int(run.steps[near].max()))
    candidates = np.flatnonzero(known & (distance <= NEAREST_WITHIN * budget))
    if not len(candidates):
        return Ours(None)
    i = candidates[np.argmin(distance[candidates])]
    return Ours(float(values[i]), int(run.steps[i]), int(run.steps[i]))


@dataclass(frozen=True)
class Row:
    """One panel at one fraction of the original's budget: ours against the original's mean and band."""

    panel: str
    fraction: float
    step: int  # the original's summary point nearest the fraction of its budget
    ours: Ours
    mean: float
    lower: float
    upper: float

    @property
    def verdict(self) -> str:
        """``within``, ``above`` or ``below`` the original's band; ``no point`` where ours has none near."""
        return verdict(self.ours.value, self.lower, self.upper)


def verdict(value: float | None, lower: float, upper: float) -> str:
    """``within``, ``above`` or ``below`` the band ``lower``-``upper``; ``no point`` where ``value`` is None."""
    if value is None:
        return "no point"
    return "above" if value > upper else "below" if value < lower else "within"


def shared_panels(run: RunCurve, cell: OriginalCell) -> list[str]:
    """The panels both log (ours with a value somewhere, the original's with a training band), the return first,
    then Episode Length, then the original's page order."""
    ours = {name for name, values in run.panels.items() if not np.isnan(values).all()}
    theirs = [title for title, p in cell.panels.items()
              if p.training is not None and len(p.training.band_steps) and title in ours]
    return sorted(theirs, key=lambda t: (t != RETURN, t != EPISODE_LENGTH, theirs.index(t)))


def summary_interval(cell: OriginalCell, panel: str) -> float:
    """The original's agent-steps between summary points of ``panel`` (the median spacing of its band)."""
    steps = cell.panels[panel].training.band_steps  # type: ignore[union-attr]
    return float(np.median(np.diff(steps))) if len(steps) > 1 else float(steps[0])


def measure(run: RunCurve, cell: OriginalCell, fractions: Sequence[float] = FRACTIONS) -> list[Row]:
    """Every shared panel at ``fractions`` of the original's budget (see the module's docstring)."""
    if not fractions or any(not 0.0 < f <= 1.0 for f in fractions):
        raise CompareError(f"the measure reads fractions of the original's budget, each in (0, 1]: {list(fractions)}")
    panels = shared_panels(run, cell)
    if not panels:
        raise CompareError(f"the run logs none of the panels of the original's {cell.file}: "
                           f"{', '.join(cell.panels)}")
    rows = []
    for panel in panels:
        window = summary_interval(cell, panel)
        training = cell.panels[panel].training
        assert training is not None  # a shared panel has a training band
        points, budget = curve_points(training, tuple(fractions)), training.last_step
        rows += [Row(panel, p.fraction, p.step, ours_at(run, panel, p.step, window, budget), p.mean, p.lower, p.upper)
                 for p in points]
    return rows


def paper_task_index(environment: str, task_index: int) -> int:
    """The paper's index (the published results' key) of the toolkit's task ``task_index`` of ``environment``."""
    from ...compiler.registry import get

    return get(environment).reward_table.tasks[task_index].index


# the original's pages index Drone-Based Reforestation's tasks as the configs that ran list them, the published
# results as the appendix does; they agree on the first two (issue 52 item 11 settles the rest)
SETTLED_DBR_TASKS = (0, 1)


def pages_index_otherwise(environment: str, task_index: int) -> bool:
    """Whether the original's pages index the paper's task ``task_index`` otherwise (Drone-Based Reforestation's
    tasks beyond :data:`SETTLED_DBR_TASKS`), so its page and sheet values cannot be looked up by that index."""
    return environment == "drone_based_reforestation" and task_index not in SETTLED_DBR_TASKS


def original_cell(environment: str, task_index: int, level: int | None, page_task: int | None = None) -> OriginalCell:
    """The original's page of the paper's cell (``page_task``: the page's own task index, where it differs)."""
    from .curves import original_curves

    if page_task is None and pages_index_otherwise(environment, task_index):
        raise CompareError(f"the original's pages index Drone-Based Reforestation's tasks as the configs that ran "
                           f"list them, which differ from the paper's index {task_index} (issue 52 item 11): give "
                           "the page's task index")
    cell = original_curves(environment, task_index if page_task is None else page_task, level)
    if cell is None:
        raise CompareError(f"the original has no page of {environment} task {task_index if page_task is None else page_task}"
                           f" at level {level}")
    return cell


def original_test_average(environment: str, task_index: int, level: int | None, tag: str) -> float | None:
    """The original's ``tag`` (``"Environment/Episode Length"``) averaged over the test curve of the paper's cell
    (``task_index`` as the paper indexes it), as its average sheet prints it; None where the sheet has no value or
    the pages index that task otherwise (:func:`pages_index_otherwise`)."""
    from .curves import average_sheet

    if pages_index_otherwise(environment, task_index):
        return None
    found = average_sheet(environment).get(tag, {}).get((task_index, level))
    return None if found is None else found.value


def number(value: float) -> str:
    """A value as the tables show it: two significant digits below 0.1 (a curiosity loss of 0.0053, not 0.01), two
    decimals below 100, whole numbers with thousands separators above."""
    if 0 < abs(value) < 0.1:
        return f"{value:.2g}"
    return f"{value:,.2f}" if abs(value) < 100 else f"{value:,.0f}"


def ours_cell(ours: Ours) -> str:
    if ours.value is None:
        return "-"
    where = "" if ours.first is None else f" ({ours.first:,})" if ours.first == ours.last \
        else f" ({ours.first:,}-{ours.last:,})"
    return number(ours.value) + where


def table(rows: Sequence[Row]) -> str:
    """The measure as a Markdown table: panel, fraction, the original's step, ours (the steps it pools), the
    original's mean and band, the verdict."""
    lines = ["| panel | budget | agent-step | ours (our steps) | original mean | original band | verdict |",
             "| --- | --- | --- | --- | --- | --- | --- |"]
    lines += [f"| {r.panel} | {r.fraction:.0%} | {r.step:,} | {ours_cell(r.ours)} | {number(r.mean)} | "
              f"{number(r.lower)} - {number(r.upper)} | {r.verdict} |" for r in rows]
    return "\n".join(lines)


__all__ = ["CompareError", "FRACTIONS", "Ours", "Row", "RunCurve", "from_points", "from_record", "is_stale",
           "measure", "number", "original_cell", "original_test_average", "ours_at", "ours_cell",
           "pages_index_otherwise", "paper_task_index", "record_panels", "seed_curves", "shared_panels",
           "summary_interval", "table", "verdict"]
