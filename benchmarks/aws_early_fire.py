"""Aerial Wildfire Suppression's fire in early training against the original's: the fire's course as its first
summary points log it, level by level.

    python benchmarks/aws_early_fire.py RUN_DIR [RUN_DIR ...] [--record] [--main-record] [--seeds]
                                        [--steps 90000] [--by-length]

Each RUN_DIR is a `hivex train` run of the main task (a sweep's folder of points or one run) trained with
``--set summary_freq=1``; ``--record`` adds the committed grid record (benchmarks/baselines/grids/
aerial_wildfire_suppression.json, the defaults it was trained at). Over the first ``--steps`` agent-steps it pools
Fire too Close to City and Fire Out a plane-decision (the statistic over Episode Length, summed over the points,
each of ours weighted by the episodes it pools, the original's summary points alike) and prints them beside the
original's pages at the same level, with the ratio and its median over the levels. ``--seeds`` takes the runs
named as seeds (one level each, or sweeps of the same levels) and ``--main-record`` adds the main record's three
seeds (level 1): each then reports the mean of its runs level by level, as the original's pages draw the mean of
theirs. Both statistics are events of a whole world at most once an episode, set by how fast the fire runs while
the planes are still untrained, so they measure the fire's pace where the policy matters least (the reward table's
notes record what it printed, issue 52).

A plane-decision still counts the planes' survival: under the release's rules every plane-episode of a world lasts
until its last plane finishes, and a fire needs hundreds of decisions to reach the village, so a run whose planes
learn later to stay up logs fewer events a decision at the same fire. ``--by-length`` prints Fire too Close to City
a plane-episode by the summary point's Episode Length instead (ours re-pooled into the original's 9,000-agent-step
points first), which compares the fire's pace at equal survival, and sums the bins up as one ratio (their geometric
mean, each weighted by the original's points); a mean of three runs there compares with the original's pages like
with like.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np

from hivex_dsl.evaluation.original.compare import CompareError, RunCurve, from_points, from_record, seed_curves
from hivex_dsl.evaluation.original.curves import original_curves

ENVIRONMENT = "aerial_wildfire_suppression"
PANELS = ("Fire too Close to City", "Fire Out")
LENGTH = "Episode Length"
GRID = Path(__file__).parent / "baselines" / "grids" / f"{ENVIRONMENT}.json"
RECORD = Path(__file__).parent / "baselines" / f"{ENVIRONMENT}.json"
SUMMARY_STEPS = 9_000.0  # the original's AWS summary_freq (its pages' points)
LENGTH_EDGES = (0.0, 300.0, 500.0, 800.0, 1_200.0, 1_800.0, 2_600.0, 3_001.0)


def pooled(curve: RunCurve, panel: str, steps: float) -> float:
    """``panel`` a plane-decision over ``curve``'s points up to ``steps`` agent-steps, weighted by their episodes."""
    early = curve.steps <= steps
    weight = curve.episodes[early]
    return float((curve.panels[panel][early] * weight).sum() / (curve.panels[LENGTH][early] * weight).sum())


def original_points(level: int, steps: float):
    """The original's main-task page at ``level`` and its summary points' agent-steps up to ``steps`` (K,)."""
    cell = original_curves(ENVIRONMENT, 0, level)
    at = cell.panel(LENGTH).training.band_steps
    return cell, at[at <= steps]


def original_pooled(level: int, panel: str, steps: float) -> float:
    """The same of the original's main-task page at ``level``: its summary points' means up to ``steps``."""
    cell, at = original_points(level, steps)
    values = cell.panel(panel).training.mean_at(at)
    return float(values.sum() / cell.panel(LENGTH).training.mean_at(at).sum())


def summary_points(curve: RunCurve, interval: float = SUMMARY_STEPS) -> RunCurve:
    """``curve`` re-pooled into summary points every ``interval`` agent-steps, as the original's trainer logged: each
    point the episode-weighted mean of the points in its interval, (K,) arrays for the K intervals holding any."""
    window = np.ceil(curve.steps / interval).astype(np.int64)
    kept, index = np.unique(window, return_inverse=True)
    episodes = np.bincount(index, weights=curve.episodes)
    panels = {name: np.bincount(index, weights=values * curve.episodes) / episodes
              for name, values in curve.panels.items()}
    return RunCurve(steps=kept * interval, episodes=episodes, panels=panels)


def mean_of_runs(curves: list[RunCurve]) -> RunCurve:
    """The mean of several runs of one cell at the summary points they all logged, as the original's pages draw
    the mean of their three runs: each point weighs one (a mean of length 500 may hold a run at 300 and one at
    700, and the fire reaches the village in long episodes alone, so single runs and means differ at short
    lengths)."""
    runs = [summary_points(curve) for curve in curves]
    steps = runs[0].steps
    for run in runs[1:]:
        steps = np.intersect1d(steps, run.steps)
    panels = {name: np.mean([run.panels[name][np.searchsorted(run.steps, steps)] for run in runs], axis=0)
              for name in set.intersection(*(set(run.panels) for run in runs))}
    return RunCurve(steps=steps, episodes=np.ones(len(steps)), panels=panels)


def by_length(curves: dict[int, RunCurve], steps: float, panel: str = PANELS[0],
              edges: tuple[float, ...] = LENGTH_EDGES) -> list[tuple[float, float, float, int, float, int]]:
    """``panel`` a plane-episode over the summary points up to ``steps`` of every level, binned by the point's
    Episode Length: (low, high, ours, our points, the original's, its points) a bin, ours weighted by episodes
    (re-pooled into the original's summary points first), the original's points (means of its runs) alike; nan
    where a bin holds no point."""
    ours = np.zeros((3, len(edges) - 1))  # panel x episodes, episodes, points
    theirs = np.zeros((3, len(edges) - 1))

    def add(into: np.ndarray, lengths: np.ndarray, values: np.ndarray, weights: np.ndarray) -> None:
        bins = np.digitize(lengths, edges[1:-1])
        for row, added in enumerate((values * weights, weights, np.ones_like(weights))):
            np.add.at(into[row], bins, added)

    for level, curve in curves.items():
        points = summary_points(curve)
        early = points.steps <= steps
        add(ours, points.panels[LENGTH][early], points.panels[panel][early], points.episodes[early])
        cell, at = original_points(level, steps)
        add(theirs, cell.panel(LENGTH).training.mean_at(at), cell.panel(panel).training.mean_at(at), np.ones(len(at)))
    with np.errstate(invalid="ignore", divide="ignore"):
        mine, original = ours[0] / ours[1], theirs[0] / theirs[1]
    return [(edges[i], edges[i + 1], float(mine[i]), int(ours[2][i]), float(original[i]), int(theirs[2][i]))
            for i in range(len(edges) - 1)]


def length_ratio(rows: list[tuple[float, float, float, int, float, int]]) -> float:
    """One number for :func:`by_length`'s rows, to set a cadence by: the geometric mean of ours over the original's,
    each bin weighted by the original's points (bins where either is 0 or has no point left out; nan if none)."""
    kept = [(np.log(mine / original), original_count) for _, _, mine, count, original, original_count in rows
            if count and original_count and mine > 0 and original > 0]
    if not kept:
        return float("nan")
    logs, weights = np.array(kept).T
    return float(np.exp((logs * weights).sum() / weights.sum()))


def length_report(label: str, curves: dict[int, RunCurve], steps: float) -> list[str]:
    lines = [f"{label}: {PANELS[0]} a plane-episode over the first {steps:,.0f} agent-steps by the summary point's "
             f"{LENGTH}, ours / the original's (points)"]
    rows = by_length(curves, steps)
    for low, high, mine, count, original, original_count in rows:
        lines.append(f"  {low:,.0f}-{high:,.0f}: {mine:.3f} ({count}) / {original:.3f} ({original_count})")
    lines.append(f"  ours over the original's, a geometric mean weighted by the original's points: "
                 f"{length_ratio(rows):.2f}")
    return lines


def run_curves(path: Path) -> dict[int, RunCurve]:
    """Level -> training curve of every run under ``path`` (a run directory or a sweep's folder of them)."""
    found = {}
    for summary_path in sorted([path / "summary.json"] if (path / "summary.json").exists()
                               else path.glob("*/summary.json")):
        summary = json.loads(summary_path.read_text())
        if summary["environment"] != ENVIRONMENT or summary["task_index"] != 0:
            raise CompareError(f"{summary_path.parent}: not a run of the main task of {ENVIRONMENT}")
        found[summary["level"]] = from_points(json.loads((summary_path.parent / "curve.json").read_text()))
    if not found:
        raise CompareError(f"{path}: no run of `hivex train` (no summary.json in it or its folders)")
    return found


def record_seeds() -> dict[int, RunCurve]:
    """The main record's seeds (level 1), as the mean of their runs."""
    record = json.loads(RECORD.read_text())
    return {record["level"]: mean_of_runs(seed_curves(record))}


def seeds_by_level(paths: list[Path]) -> dict[int, RunCurve]:
    """The runs under ``paths`` as seeds, one a path (each a run directory, or a sweep's folder of the same levels
    as the others): per level, the mean of its runs."""
    found = [run_curves(path) for path in paths]
    levels = set(found[0])
    if any(set(curves) != levels for curves in found):
        raise CompareError("--seeds takes runs of one level, or sweeps of the same levels, one seed a path; these hold "
                           + "; ".join(f"levels {sorted(curves)}" for curves in found))
    return {level: mean_of_runs([curves[level] for curves in found]) for level in sorted(levels)}


def grid_curves() -> dict[int, RunCurve]:
    return {point["level"]: from_record({**point, "environment": ENVIRONMENT})
            for point in json.loads(GRID.read_text())["points"]}


def report(label: str, curves: dict[int, RunCurve], steps: float) -> list[str]:
    lines = [f"{label}: a plane-decision over the first {steps:,.0f} agent-steps, ours / the original's (ratio)"]
    for panel in PANELS:
        ratios, cells = [], []
        for level in sorted(curves):
            ours, theirs = pooled(curves[level], panel, steps), original_pooled(level, panel, steps)
            ratios.append(ours / theirs if theirs > 0 else np.nan)
            cells.append(f"L{level} {ours * 1e4:.2f}/{theirs * 1e4:.2f}")
        finite = np.array(ratios)[np.isfinite(ratios)]
        median = f"{np.median(finite):.2f}" if len(finite) else "n/a"
        lines.append(f"  {panel} (x 1e-4): " + ", ".join(cells) + f"; median ratio {median}")
    return lines


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("runs", nargs="*", type=Path, help="run directories or sweep folders of the main task")
    parser.add_argument("--record", action="store_true", help="also the committed grid record")
    parser.add_argument("--main-record", action="store_true",
                        help="also the committed main record's seeds (level 1), as the mean of their runs")
    parser.add_argument("--seeds", action="store_true",
                        help="the runs named are seeds (of one level, or sweeps of the same levels): report the "
                             "mean of their runs, level by level")
    parser.add_argument("--steps", type=float, default=90_000.0, help="agent-steps pooled (default 90,000)")
    parser.add_argument("--by-length", action="store_true",
                        help="Fire too Close to City a plane-episode by the points' Episode Length instead")
    args = parser.parse_args(argv)
    try:
        sources = [("grid record", grid_curves())] if args.record else []
        sources += [("main record's seeds", record_seeds())] if args.main_record else []
        if args.seeds:
            sources.append((f"mean of {len(args.runs)} runs", seeds_by_level(args.runs)))
        else:
            sources += [(str(path), run_curves(path)) for path in args.runs]
        if not sources:
            raise CompareError("name a run directory or --record")
        for label, curves in sources:
            lines = (length_report if args.by_length else report)(label, curves, args.steps)
            print("\n".join(lines), flush=True)
    except (CompareError, KeyError, OSError) as error:
        print(f"aws_early_fire: {error}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
