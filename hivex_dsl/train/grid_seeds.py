"""Other training seeds of a committed grid record: each point's ``other_seeds``, as a main-task record keeps them.

One seed a point tells where one run of a cell ends, which PPO may not (a Wildfire Resource Management run drifts to
keeping its resources or not by its seed). The original trained three runs a cell, and its pages draw their mean and
band; a grid here trains another seed with ``hivex train SWEEP -o RUN_DIR --seed N --points ...`` (any points of the
sweep), and :func:`add_grid_seed` adds every point of it trained to its end to its row of the grid record, with its
test-seed evaluation on the record's episodes and its training curve. The fidelity page then measures the mean of a
point's seeds against the original's band, like with like.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from ..compiler import compile_all
from .baselines import (check_other_seed, evaluation_of_point, finished_point, of_sweep, read_json, seed_entry,
                        trained_to_end, with_seed)
from .config import TrainError
from .grid import point_dir
from .rundir import dumps


def add_grid_seed(record: Path, grid_dir: Path) -> dict[str, Any]:
    """Add (or replace) every point of ``grid_dir`` trained to its end, a grid of the sweep the grid record
    ``record`` (``grids/<environment>.json``) records trained on another seed, to its point's ``other_seeds``; ->
    the record's new content, also written back.

    Each such point must have trained its row's scenario (fingerprint) with the record's hyperparameters but for
    the seeds (:data:`~.baselines.SEED_CHANGES`), on a seed other than its row's; its test-seed evaluation is the
    grid's own where it played the checkpoint as it is now on the record's episodes, and a fresh one otherwise.
    A point begun but not trained to its end is refused (resume it first); points with no run are left as they
    are."""
    record, grid_dir = Path(record), Path(grid_dir)
    data = read_json(record, "grid record")
    points = compile_all(data["sweep"])
    if not of_sweep(data, points):
        raise TrainError(f"{record} records a sweep other than {data['sweep']} holds now (its points' "
                         "fingerprints differ): record the grid again before adding seeds to it")
    rows = {row["name"]: row for row in data["points"]}
    added = 0
    for index, point in enumerate(points):
        run_dir = point_dir(grid_dir, index, point)
        if not run_dir.exists():
            continue
        if not trained_to_end(run_dir):
            raise TrainError(f"point {index} of {data['sweep']} ({run_dir}) did not train to its end: run its "
                             "`hivex train` command again with --resume, or move it aside")
        if point.name not in rows:
            raise TrainError(f"{record} has no row of point {index} ({point.name!r}) to add a seed to: record the "
                             "point's first seed with --grid first")
        finished_point(run_dir, index, point, data["sweep"])
        row = rows[point.name]
        check_other_seed(run_dir, point, data["hyperparameters"], row["seed"], f"{record.name}'s point {index}")
        report = evaluation_of_point(run_dir, point, data["test"]["episodes"])
        row["other_seeds"] = with_seed(row.get("other_seeds", []), seed_entry(run_dir, report))
        added += 1
    if not added:
        raise TrainError(f"{grid_dir} holds no point of {data['sweep']}: nothing to add")
    record.write_text(dumps(data, record, 1))
    return data
