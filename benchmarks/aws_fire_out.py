"""Aerial Wildfire Suppression's Fire Out at the end of training beside the crashes it follows, ours against the
original's, level by level.

    python benchmarks/aws_fire_out.py [--grid] [--record] [--stages | --crashes] [RUN_DIR ...]

The release's HivexAgent.FireReward pays and counts Fire Out only on a plane that still flies: a plane that crossed
the border is frozen until its world ends and logs none. So a plane-episode's Fire Out reads both how often its
world's fire went out and whether the plane was still up when it did. Over the last tenth of the budget
(hivex_dsl.evaluation.original.tail, each side pooled as `hivex curves` pools it) this prints, level by level, Fire
Out, Crash Count and Fire Out a plane that did not crash (Fire Out / (1 - Crash Count): a frozen plane crashes at most
once an episode), first the original's with the correlation of Fire Out and Crash Count over its ten levels and the
least-squares line through them, then ours (``--grid``: the committed ten-level grid record; ``--record``: the main
record's seeds; RUN_DIR: runs of `hivex train`, a sweep's folder of them or one run) with that line read at our Crash
Count: what the original's levels log at the crash rate our planes reach (the reward table's notes record what it
printed, issue 52).

``--stages`` prints instead, tenth of the budget by tenth, the mean over the runs' levels of Fire Out, Crash Count,
Fire Out a plane still up, Water Drop and the trees a drop extinguished and prepared, the original's beside ours, and,
over every (level, tenth) window from half the budget on, how Fire Out a plane still up correlates with the drops and
the trees they wet: whether a fire goes out more often where the planes drop more, and whether the same water puts
ours out as often as the original's.

``--crashes`` prints Crash Count level by level and fifth of the budget by fifth, the original's beside ours, with the
median of ours over the original's and the correlation over the levels a fifth at a time: when in training our planes
part from the original's at the border, and whether they crash most at the levels where the original's did.
"""

from __future__ import annotations

import argparse
import json
import sys
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from hivex_dsl.evaluation.original.compare import CompareError, RunCurve, from_record, original_cell, seed_curves
from hivex_dsl.evaluation.original.runs import read_run
from hivex_dsl.evaluation.original.tail import tail

ENVIRONMENT = "aerial_wildfire_suppression"
LEVELS = range(1, 11)
FIRE_OUT, CRASHES = "Fire Out", "Crash Count"
DROPS, EXTINGUISHED, PREPARED = "Water Drop", "Extinguishing Trees", "Preparing Trees"
STAGE_PANELS = (FIRE_OUT, CRASHES, DROPS, EXTINGUISHED, PREPARED)
TENTHS = 10
FIFTHS = 5  # --crashes pools two tenths a column
LATE = 0.5  # the windows the correlations read start at half the budget or later
GRID = Path(__file__).parent / "baselines" / "grids" / f"{ENVIRONMENT}.json"
RECORD = Path(__file__).parent / "baselines" / f"{ENVIRONMENT}.json"


@dataclass(frozen=True)
class End:
    """Fire Out and Crash Count a plane-episode over the last tenth of the budget, at one level."""

    level: int
    fire_out: float
    crashes: float

    @property
    def per_plane_up(self) -> float:
        """Fire Out a plane-episode whose plane did not crash."""
        return self.fire_out / (1.0 - self.crashes) if self.crashes < 1.0 else float("nan")


def original_ends() -> list[End]:
    """The original's main task at every level: the means of its summary points over the last tenth."""
    ends = []
    for level in LEVELS:
        cell = original_cell(ENVIRONMENT, 0, level)
        empty = RunCurve(steps=np.zeros(0), episodes=np.zeros(0), panels={})
        ends.append(End(level, tail(empty, cell, FIRE_OUT).theirs, tail(empty, cell, CRASHES).theirs))
    return ends


def our_end(curve: RunCurve, level: int) -> End:
    """Ours at ``level``: the points over the last tenth of the original's budget, weighted by their episodes."""
    cell = original_cell(ENVIRONMENT, 0, level)
    fire_out, crashes = tail(curve, cell, FIRE_OUT).ours, tail(curve, cell, CRASHES).ours
    if fire_out is None or crashes is None:
        raise CompareError(f"the run at level {level} has no point in the last tenth of the original's budget")
    return End(level, fire_out, crashes)


def line(ends: list[End]) -> tuple[float, float, float]:
    """(intercept, slope, correlation) of Fire Out on Crash Count over ``ends``."""
    crashes = np.array([end.crashes for end in ends])
    fire_out = np.array([end.fire_out for end in ends])
    slope, intercept = np.polyfit(crashes, fire_out, 1)
    return float(intercept), float(slope), float(np.corrcoef(crashes, fire_out)[0, 1])


def _ratio(ours: float, theirs: float) -> str:
    """``ours`` over ``theirs`` to two places, or '-' where ``theirs`` is not positive (a line read past its zero, a
    level whose planes all crashed)."""
    return f"{ours / theirs:.2f}" if theirs > 0 else "-"


def ours_from_args(args: argparse.Namespace) -> list[tuple[str, RunCurve, int]]:
    """(label, curve, level) of every run asked for."""
    runs = []
    if args.grid:
        for point in json.loads(GRID.read_text())["points"]:
            runs.append((f"grid L{point['level']}", from_record({**point, "environment": ENVIRONMENT}),
                         point["level"]))
    if args.record:
        record = json.loads(RECORD.read_text())
        for curve in seed_curves(record):
            runs.append((f"main record, {curve.label.split(', ', 1)[-1]}", curve, record["level"]))
    for path in args.runs:
        folders = [path] if (path / "summary.json").exists() else sorted(p.parent for p in path.glob("*/summary.json"))
        if not folders:
            raise CompareError(f"{path}: no finished run of `hivex train` (no summary.json in it or its folders)")
        for folder in folders:
            run = read_run(folder)
            if run.environment != ENVIRONMENT or run.task_index != 0:
                raise CompareError(f"{folder}: not a run of the main task of {ENVIRONMENT}")
            runs.append((folder.name, run.curve, run.level))
    return runs


def report(ours: list[tuple[str, RunCurve, int]]) -> list[str]:
    theirs = original_ends()
    intercept, slope, correlation = line(theirs)
    lines = ["the original's main task over the last tenth of its budget, a plane-episode:"]
    lines += [f"  L{e.level}: Fire Out {e.fire_out:.3f}, Crash Count {e.crashes:.2f}, Fire Out a plane up "
              f"{e.per_plane_up:.3f}" for e in theirs]
    lines.append(f"  over its ten levels Fire Out = {intercept:.3f} {slope:+.3f} x Crash Count, correlation "
                 f"{correlation:.2f}")
    if ours:
        lines.append("ours over the same steps (the original's line at our Crash Count; its level's Fire Out a plane "
                     "up):")
    ends = [our_end(curve, level) for _, curve, level in ours]
    for (label, _, level), end in zip(ours, ends):
        there, expected = theirs[level - 1], intercept + slope * end.crashes
        lines.append(f"  {label}: Fire Out {end.fire_out:.3f}, Crash Count {end.crashes:.2f} (line {expected:.3f}, "
                     f"ratio {_ratio(end.fire_out, expected)}); a plane up {end.per_plane_up:.3f} against "
                     f"{there.per_plane_up:.3f} (ratio {_ratio(end.per_plane_up, there.per_plane_up)})")
    if len(ends) >= 3:
        intercept, slope, correlation = line(ends)
        lines.append(f"  over these runs Fire Out = {intercept:.3f} {slope:+.3f} x Crash Count, correlation "
                     f"{correlation:.2f}")
    return lines


def original_windows(level: int) -> np.ndarray:
    """(TENTHS, len(STAGE_PANELS)) the original's training mean at ``level``, each panel averaged over its summary
    points in each tenth (start, end] of the budget."""
    cell = original_cell(ENVIRONMENT, 0, level)
    windows = np.full((TENTHS, len(STAGE_PANELS)), np.nan)
    for column, panel in enumerate(STAGE_PANELS):
        training = cell.panels[panel].training
        budget = training.last_step
        for tenth in range(TENTHS):
            steps = training.band_steps
            inside = steps[(steps > tenth / TENTHS * budget) & (steps <= (tenth + 1) / TENTHS * budget)]
            if len(inside):
                windows[tenth, column] = float(np.mean(training.mean_at(inside)))
    return windows


def our_windows(curve: RunCurve, level: int) -> np.ndarray:
    """(TENTHS, len(STAGE_PANELS)) ours: each panel over our points in each tenth of the original's budget at
    ``level``, weighted by their episodes (NaN where no point lies)."""
    budget = original_cell(ENVIRONMENT, 0, level).panels[FIRE_OUT].training.last_step
    windows = np.full((TENTHS, len(STAGE_PANELS)), np.nan)
    for tenth in range(TENTHS):
        inside = (curve.steps > tenth / TENTHS * budget) & (curve.steps <= (tenth + 1) / TENTHS * budget)
        weights = curve.episodes[inside]
        if weights.sum() > 0:
            for column, panel in enumerate(STAGE_PANELS):
                windows[tenth, column] = float((curve.panels[panel][inside] * weights).sum() / weights.sum())
    return windows


def per_plane_up(windows: np.ndarray) -> np.ndarray:
    """Fire Out a plane still up of every window (..., TENTHS, panels): Fire Out / (1 - Crash Count)."""
    crashes = windows[..., STAGE_PANELS.index(CRASHES)]
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(crashes < 1.0, windows[..., STAGE_PANELS.index(FIRE_OUT)] / (1.0 - crashes), np.nan)


def late_correlations(windows: np.ndarray) -> tuple[list[float], int]:
    """Over the (run, tenth) windows of ``windows`` (runs, TENTHS, panels) from LATE of the budget on: the
    correlation of Fire Out a plane still up with Water Drop, Extinguishing Trees and Preparing Trees, and how many
    windows they read."""
    late = windows[:, int(LATE * TENTHS):].reshape(-1, len(STAGE_PANELS))
    up = per_plane_up(late)
    known = ~np.isnan(up) & ~np.isnan(late).any(axis=1)
    columns = [STAGE_PANELS.index(panel) for panel in (DROPS, EXTINGUISHED, PREPARED)]
    if known.sum() < 3:  # a run stopped before the late windows: nothing to correlate
        return [float("nan")] * len(columns), int(known.sum())
    return [float(np.corrcoef(late[known, column], up[known])[0, 1]) for column in columns], int(known.sum())


def stages(ours: list[tuple[str, RunCurve, int]]) -> list[str]:
    """The ``--stages`` report: ours and the original's at the runs' levels, tenth of the budget by tenth."""
    if not ours:
        raise CompareError("--stages reads runs of ours: name RUN_DIRs, --grid or --record")
    theirs = np.stack([original_windows(level) for _, _, level in ours])
    mine = np.stack([our_windows(curve, level) for _, curve, level in ours])
    levels = sorted({level for _, _, level in ours})
    lines = [f"the main task by tenth of the budget, the mean over {len(ours)} run{'s' * (len(ours) > 1)} at "
             f"level{'s' * (len(levels) > 1)} {', '.join(map(str, levels))}, the original's / ours (a plane-episode):"]
    column = {panel: STAGE_PANELS.index(panel) for panel in STAGE_PANELS}
    for tenth in range(TENTHS):
        two = [np.nanmean(side[:, tenth], axis=0) if not np.isnan(side[:, tenth]).all() else
               np.full(len(STAGE_PANELS), np.nan) for side in (theirs, mine)]
        up = [per_plane_up(side) for side in two]
        per_drop = [[side[column[panel]] / side[column[DROPS]] for side in two] for panel in (EXTINGUISHED, PREPARED)]
        lines.append(
            f"  {10 * tenth}-{10 * tenth + 10}%: Fire Out {two[0][column[FIRE_OUT]]:.2f}/"
            f"{two[1][column[FIRE_OUT]]:.2f},"
            f" Crash Count {two[0][column[CRASHES]]:.2f}/{two[1][column[CRASHES]]:.2f}, a plane up {up[0]:.2f}/"
            f"{up[1]:.2f} (ratio {_ratio(up[1], up[0])}), Water Drop {two[0][column[DROPS]]:.1f}/"
            f"{two[1][column[DROPS]]:.1f}, a drop extinguishes {per_drop[0][0]:.2f}/{per_drop[0][1]:.2f} and prepares "
            f"{per_drop[1][0]:.1f}/{per_drop[1][1]:.1f} trees")
    lines.append(f"Fire Out a plane up against Water Drop, Extinguishing Trees and Preparing Trees over the windows "
                 f"from {LATE:.0%} of the budget on, correlations:")
    for label, side in (("the original's", theirs), ("ours", mine)):
        correlations, count = late_correlations(side)
        lines.append(f"  {label}: {', '.join(f'{c:+.2f}' for c in correlations)} ({count} windows)")
    return lines


def crash_fifths(windows: np.ndarray) -> np.ndarray:
    """(..., FIFTHS) Crash Count over each fifth of the budget: the mean of its two tenths of ``windows`` (...,
    TENTHS, panels), the one where the other has no point."""
    crashes = windows[..., STAGE_PANELS.index(CRASHES)]
    pairs = crashes.reshape(crashes.shape[:-1] + (FIFTHS, TENTHS // FIFTHS))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # a fifth with no point of ours stays NaN
        return np.nanmean(pairs, axis=-1)


def crashes_by_level(ours: list[tuple[str, RunCurve, int]]) -> list[str]:
    """The ``--crashes`` report: Crash Count a plane-episode, level by level and fifth of the budget by fifth, the
    original's / ours; then, a fifth at a time, the median of ours over the original's and how the levels' two
    columns correlate (whether ours crash most where the original's did)."""
    if not ours:
        raise CompareError("--crashes reads runs of ours: name RUN_DIRs, --grid or --record")
    theirs = crash_fifths(np.stack([original_windows(level) for _, _, level in ours]))
    mine = crash_fifths(np.stack([our_windows(curve, level) for _, curve, level in ours]))
    heads = " ".join(f"{20 * fifth}-{20 * fifth + 20}%".rjust(11) for fifth in range(FIFTHS))
    lines = ["Crash Count a plane-episode by fifth of the budget, the original's / ours:", f"  {'':16}{heads}"]
    for (label, _, _), there, here in zip(ours, theirs, mine):
        lines.append(f"  {label:16}" + " ".join(f"{a:.2f}/{b:.2f}".rjust(11) for a, b in zip(there, here)))
    with np.errstate(divide="ignore", invalid="ignore"):
        ratios = np.nanmedian(np.where(theirs > 0, mine / theirs, np.nan), axis=0)
    lines.append(f"  {'median ratio':16}" + " ".join(f"{r:.2f}".rjust(11) for r in ratios))
    if len({level for _, _, level in ours}) >= 3:  # a correlation over levels needs levels that differ
        correlations = [np.corrcoef(theirs[:, fifth], mine[:, fifth])[0, 1] for fifth in range(FIFTHS)]
        lines.append(f"  {'correlation':16}" + " ".join(f"{c:+.2f}".rjust(11) for c in correlations))
    return lines


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("runs", nargs="*", type=Path, metavar="RUN_DIR")
    parser.add_argument("--grid", action="store_true", help="the committed ten-level grid record")
    parser.add_argument("--record", action="store_true", help="the main record's seeds (level 1)")
    shown = parser.add_mutually_exclusive_group()
    shown.add_argument("--stages", action="store_true",
                       help="tenth of the budget by tenth, and the late windows' correlations with the water")
    shown.add_argument("--crashes", action="store_true",
                       help="Crash Count level by level and fifth of the budget by fifth, with the levels' correlation")
    args = parser.parse_args(argv)
    try:
        runs = ours_from_args(args)
        lines = stages(runs) if args.stages else crashes_by_level(runs) if args.crashes else report(runs)
    except CompareError as error:
        print(f"error: {error}", file=sys.stderr)
        return 2
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
