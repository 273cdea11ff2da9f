"""Turn a finished `hivex train` run into a committed baseline: benchmarks/baselines/<environment>.json + .png.

    python benchmarks/record_baseline.py RUN_DIR SCENARIO [--episodes 10] [--command "..."] [--note "..."]
    python benchmarks/record_baseline.py --add-seed RUN_DIR [--add-seed RUN_DIR ...]   # other training seeds
    python benchmarks/record_baseline.py --grid RUN_DIR SWEEP [--episodes 10] [--partial]   # a trained sweep: grids/<env>.json
    python benchmarks/record_baseline.py --grid-add-seed RUN_DIR [...]   # a sweep's points trained on another seed
    python benchmarks/record_baseline.py --replot   # redraw every committed PNG from its JSON

It evaluates the run's checkpoint on the test seeds (as `hivex evaluate` does), measures the random and
scripted policies on the same seeds, evaluates every intermediate checkpoint the run kept on the test seeds
(--curve-episodes each), draws the learning curve, and writes both files; then run
`hivex docs` to regenerate docs/baselines.md. Needs the train and plots extras. --add-seed evaluates a run of
the same scenario and hyperparameters on another training seed (`hivex train ... --seed 1`) and adds it to
that environment's committed record, which the page then shows beside the recorded seed. --grid records a
sweep trained with `hivex train SWEEP -o RUN_DIR --eval-episodes N`: every point's test return beside the
paper's published cell for its task and level (each point's own evaluation when it holds --episodes episodes);
with --partial, a grid still training: the points trained so far, the others listed as not trained yet. A point
whose run is not in RUN_DIR keeps its row of the grid record already written, when that row is of the same
scenario (fingerprint), hyperparameters and test episodes: a grid trained in parts (`hivex train SWEEP --points
14-29`) on machines that do not keep their runs is recorded whole in the end. A grid record of another sweep (by
content: the points' fingerprints, not the sweep's path) is refused; --replace replaces it. --grid-add-seed adds the
points of a sweep trained on another seed (`hivex train SWEEP -o RUN_DIR --seed 1 --points ...`, the grid's
hyperparameters) to their rows of the environment's committed grid record, which re-recording the grid keeps. A run is
recorded only as the scenario it trained (its checkpoint's fingerprint), whatever its name.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from hivex_dsl.base.errors import HivexError
from hivex_dsl.cli.argtypes import positive
from hivex_dsl.train.baselines import GRIDS, add_seed, read_json, record_baseline, record_grid
from hivex_dsl.train.grid_seeds import add_grid_seed
from hivex_dsl.train.plots import learning_curve

OUT = Path(__file__).resolve().parent / "baselines"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("run_dir", type=Path, nargs="?")
    parser.add_argument("scenario", nargs="?", help="the bundled scenario path, e.g. scenarios/wind_farm_control/main.yaml")
    parser.add_argument("--replot", action="store_true", help="only redraw the committed PNGs from their JSON")
    parser.add_argument("--add-seed", action="append", type=Path, default=[], metavar="RUN_DIR",
                        help="add another training seed's run to its environment's committed record")
    parser.add_argument("--grid-add-seed", action="append", type=Path, default=[], metavar="RUN_DIR",
                        help="add a sweep's points trained on another seed to its environment's grid record")
    parser.add_argument("--grid", action="store_true",
                        help="RUN_DIR is a trained sweep and SCENARIO its sweep file (writes grids/<environment>.json)")
    parser.add_argument("--episodes", type=positive, default=10)
    parser.add_argument("--partial", action="store_true",
                        help="with --grid: record the points trained so far of a grid still training")
    parser.add_argument("--replace", action="store_true",
                        help="with --grid: replace the committed record of the environment's grid when it records "
                             "another sweep (refused without)")
    parser.add_argument("--command", help="the exact commands that trained the run (shown on the page; "
                                           "the record's own of the same scenario or sweep is kept when not given)")
    parser.add_argument("--note", help="one paragraph shown under the curve (the record's own of the same "
                                        "scenario or sweep is kept when not given)")
    parser.add_argument("--curve-episodes", type=positive, default=3,
                        help="test episodes per intermediate checkpoint (the test-seed curve)")
    args = parser.parse_args()
    try:
        record(parser, args)
    except HivexError as exc:  # a run, sweep or record it cannot use: one sentence, no traceback
        parser.exit(2, f"error: {exc}\n")


def record(parser: argparse.ArgumentParser, args: argparse.Namespace) -> None:
    """What the arguments ask: redraw, add seeds, record a grid, or record a run."""
    if args.replot:
        for path in sorted(OUT.glob("*.json")):
            learning_curve(json.loads(path.read_text()), path.with_suffix(".png"))
            print(f"redrew {path.with_suffix('.png')}")
        return
    for run_dir in args.add_seed:
        summary = read_json(run_dir / "summary.json", "summary")
        data = add_seed(OUT / f"{summary['environment']}.json", run_dir)
        entry = next(e for e in data["other_seeds"] if e["seed"] == summary["seed"])
        print(f"added seed {entry['seed']} to {OUT / summary['environment']}.json: test return "
              f"{entry['return']['mean']:.2f} ± {entry['return']['std']:.2f}")
    for run_dir in args.grid_add_seed:
        added = add_seed_to_grid(run_dir)
        print(f"added seed {added['seed']} to {added['record']} at {added['points']} points")
    if args.add_seed or args.grid_add_seed:
        return
    if args.run_dir is None or args.scenario is None:
        parser.error("RUN_DIR and SCENARIO are required (or --add-seed, --grid-add-seed, or --replot)")
    if args.partial and not args.grid:
        parser.error("--partial records a grid still training: it goes with --grid")
    if args.replace and not args.grid:
        parser.error("--replace replaces a grid record of another sweep: it goes with --grid")
    if args.grid:
        grid = record_grid(args.run_dir, args.scenario, OUT, args.episodes, args.command, args.note,
                           args.partial, args.replace)
        print(f"wrote {OUT / GRIDS / grid['environment']}.json: {len(grid['points'])} points"
              + (f", {len(grid['untrained'])} not trained yet" if grid["untrained"] else ""))
        return
    data = record_baseline(args.run_dir, args.scenario, OUT, args.episodes, args.command, args.note,
                           args.curve_episodes)
    print(f"wrote {OUT / data['environment']}.json and .png: test return "
          f"{data['test']['return']['mean']:.2f} ± {data['test']['return']['std']:.2f}")


def add_seed_to_grid(run_dir: Path) -> dict:
    """Add the points of the sweep trained in ``run_dir`` to the committed grid record of its environment; -> the
    record's path, the seed and how many points it gained."""
    trained = sorted(p for p in Path(run_dir).glob("*/summary.json"))
    if not trained:
        raise HivexError(f"{run_dir} holds no trained point of a sweep (no */summary.json)")
    summary = read_json(trained[0], "summary")
    record = OUT / GRIDS / f"{summary['environment']}.json"
    if not record.is_file():
        raise HivexError(f"no grid record of {summary['environment']} at {record}: record its grid with --grid first")
    data = add_grid_seed(record, run_dir)
    count = sum(any(e["seed"] == summary["seed"] for e in p.get("other_seeds", [])) for p in data["points"])
    return {"record": record, "seed": summary["seed"], "points": count}


if __name__ == "__main__":
    main()
