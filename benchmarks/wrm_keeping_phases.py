"""Wildfire Resource Management: how the main task's keeping moves over training, the original's and ours.

    python benchmarks/wrm_keeping_phases.py

Keeping is Reward for Moving Resources to Self over Individual Performance (the main task weighs both terms 1), each
phase of the budget pooling its summary points. A level of the original is one stream of fires and its three runs
shared their weights (every config that ran has env_settings.seed 5000), so a level's end is one outcome of its
learner; the mean over the ten levels reads the pull that learner felt. Printed per level and over the levels: the
original's runs' mean (the digitised pages) and the mean over the committed grid's seeds
(benchmarks/baselines/grids/wildfire_resource_management.json). The reward table's note 'Keeping over training,
pooled over the levels' records what it printed (issue 52).
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np

from hivex_dsl.base.errors import HivexError
from hivex_dsl.evaluation.original.curves import original_curves

ENVIRONMENT = "wildfire_resource_management"
SELF, INDIVIDUAL = "Reward for Moving Resources to Self", "Individual Performance"
GRID = Path(__file__).resolve().parent / "baselines" / "grids" / f"{ENVIRONMENT}.json"
PHASES = ((0.0, 0.1), (0.1, 0.25), (0.25, 0.5), (0.5, 0.75), (0.9, 1.0))  # fractions of the budget


def phase_keeping(fractions: np.ndarray, kept: np.ndarray, individual: np.ndarray) -> list[float]:
    """Keeping in each of :data:`PHASES` (lower bound excluded, upper included) of a training curve: its summary
    points at ``fractions`` (k,) of the budget, ``kept`` (k,) summed over a phase's points over ``individual``'s
    (k,; NaN where a point held no episode); NaN for a phase whose points logged none."""
    found = []
    for low, high in PHASES:
        here = (fractions > low) & (fractions <= high) & np.isfinite(individual)
        total = float(individual[here].sum())
        found.append(float(np.nansum(kept[here])) / total if total > 0 else float("nan"))
    return found


def original_phase_keeping(level: int) -> list[float]:
    """:func:`phase_keeping` of the original's runs' mean, main task at ``level``."""
    cell = original_curves(ENVIRONMENT, 0, level)
    if cell is None:
        raise HivexError(f"no original main-task cell at level {level}")
    kept, individual = (cell.panel(name).training for name in (SELF, INDIVIDUAL))
    return phase_keeping(kept.band_steps / kept.last_step, kept.mean_at(kept.band_steps),
                         individual.mean_at(kept.band_steps))


def recorded_phase_keeping(run: dict, budget: float) -> list[float]:
    """:func:`phase_keeping` of one recorded run (a grid point or one of its ``other_seeds``) of ``budget``
    agent-steps."""
    steps = np.array([row[0] for row in run["curve"]], dtype=float)
    kept, individual = (np.asarray(run["curve_panels"][name], dtype=float) for name in (SELF, INDIVIDUAL))  # None: NaN
    return phase_keeping(steps / budget, kept, individual)


def phase_table(grid: Path = GRID) -> list[tuple[int, list[float], list[float]]]:
    """(level, :func:`original_phase_keeping`, the mean over the grid record's seeds of their
    :func:`recorded_phase_keeping`) of the main task at each level the record holds."""
    points = json.loads(Path(grid).read_text())["points"]
    main = sorted((p for p in points if p["task_index"] == 0), key=lambda p: p["level"])
    return [(point["level"], original_phase_keeping(point["level"]),
             list(np.mean([recorded_phase_keeping(run, point["agent_steps"])
                           for run in (point, *point.get("other_seeds", []))], axis=0)))
            for point in main]


def main() -> int:
    try:
        table = phase_table(GRID)
    except (HivexError, OSError, KeyError) as error:
        print(f"error: {error}", file=sys.stderr)
        return 2
    print("level  " + "  ".join(f"{low:.2f}-{high:.2f} original / ours" for low, high in PHASES))
    for level, theirs, ours in table:
        print(f"{level:5d}  " + "  ".join(f"{a:9.3f} / {b:.3f}    " for a, b in zip(theirs, ours)))
    theirs, ours = (np.mean([row[column] for row in table], axis=0) for column in (1, 2))
    print("mean   " + "  ".join(f"{a:9.3f} / {b:.3f}    " for a, b in zip(theirs, ours)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
