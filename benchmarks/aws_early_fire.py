"""Aerial Wildfire Suppression's fire in early training against the original's: the fire's course as its first
summary points log it, level by level.

    python benchmarks/aws_early_fire.py RUN_DIR [RUN_DIR ...] [--record] [--steps 90000]

Each RUN_DIR is a `hivex train` run of the main task (a sweep's folder of points or one run) trained with
``--set summary_freq=1``; ``--record`` adds the committed grid record (benchmarks/baselines/grids/
aerial_wildfire_suppression.json, the defaults it was trained at). Over the first ``--steps`` agent-steps it pools
Fire too Close to City and Fire Out a plane-decision (the statistic over Episode Length, summed over the points,
each of ours weighted by the episodes it pools, the original's summary points alike) and prints them beside the
original's pages at the same level, with the ratio and its median over the levels. Both flags are events of a
whole world at most once an episode, set by how fast the fire runs while the planes are still untrained, so they
measure the fire's pace where the policy matters least (the reward table's notes record what it printed, issue 52).
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np

from hivex_dsl.evaluation.original.compare import CompareError, RunCurve, from_points, from_record
from hivex_dsl.evaluation.original.curves import original_curves

ENVIRONMENT = "aerial_wildfire_suppression"
PANELS = ("Fire too Close to City", "Fire Out")
LENGTH = "Episode Length"
GRID = Path(__file__).parent / "baselines" / "grids" / f"{ENVIRONMENT}.json"


def pooled(curve: RunCurve, panel: str, steps: float) -> float:
    """``panel`` a plane-decision over ``curve``'s points up to ``steps`` agent-steps, weighted by their episodes."""
    early = curve.steps <= steps
    weight = curve.episodes[early]
    return float((curve.panels[panel][early] * weight).sum() / (curve.panels[LENGTH][early] * weight).sum())


def original_pooled(level: int, panel: str, steps: float) -> float:
    """The same of the original's main-task page at ``level``: its summary points' means up to ``steps``."""
    cell = original_curves(ENVIRONMENT, 0, level)
    at = cell.panel(LENGTH).training.band_steps
    at = at[at <= steps]
    values = cell.panel(panel).training.mean_at(at)
    return float(values.sum() / cell.panel(LENGTH).training.mean_at(at).sum())


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
    parser.add_argument("--steps", type=float, default=90_000.0, help="agent-steps pooled (default 90,000)")
    args = parser.parse_args(argv)
    try:
        sources = [("grid record", grid_curves())] if args.record else []
        sources += [(str(path), run_curves(path)) for path in args.runs]
        if not sources:
            raise CompareError("name a run directory or --record")
        for label, curves in sources:
            print("\n".join(report(label, curves, args.steps)), flush=True)
    except (CompareError, KeyError, OSError) as error:
        print(f"aws_early_fire: {error}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
