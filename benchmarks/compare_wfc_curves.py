"""Wind Farm Control's training curves here beside the original's three runs (main task, pattern 0).

    python benchmarks/compare_wfc_curves.py RUN_DIR [RUN_DIR ...] [--write]   # runs of `hivex train`
    python benchmarks/compare_wfc_curves.py                                   # the committed curves

Reads each run's ``curve.json`` (the training return at every summary point), or with no RUN_DIR the
committed ``benchmarks/baselines/curves/wind_farm_control-main.json``; prints the return at 10, 25, 50 and
100% of the 8M budget against the band of the original's runs (:func:`hivex_dsl.evaluation.curves.compare_curves`)
and the near-random start of both. ``--write`` stores the runs' curves, compactly, as that committed file.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from hivex_dsl.evaluation.curves import compare_curves, comparison_table, original_wfc_main

BUDGET = 8_000_000
COMMITTED = Path(__file__).resolve().parent / "baselines" / "curves" / "wind_farm_control-main.json"
EARLY = 600_000  # the original's first 15 points, while its policy's entropy stayed near log 3 (uniform)


def run_curve(run_dir: Path) -> tuple[int, list[list[float]]]:
    """(training seed, [[agent_steps, return], ...]) of a finished run."""
    config = json.loads((run_dir / "config.json").read_text())
    points = json.loads((run_dir / "curve.json").read_text())
    seed = config.get("hyperparameters", config).get("seed", config.get("seed"))
    return int(seed), [[p["agent_steps"], round(p["return"], 1)] for p in points]


def early_mean(curve) -> float:
    values = [value for step, value in curve if step <= EARLY]
    return sum(values) / len(values)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("run_dirs", type=Path, nargs="*")
    parser.add_argument("--write", action="store_true", help=f"store the runs' curves as {COMMITTED}")
    args = parser.parse_args()
    if args.run_dirs:
        curves = dict(run_curve(run_dir) for run_dir in args.run_dirs)
    else:
        curves = {int(seed): curve for seed, curve in json.loads(COMMITTED.read_text())["curves"].items()}
    if args.write:
        COMMITTED.parent.mkdir(parents=True, exist_ok=True)
        COMMITTED.write_text(json.dumps({
            "scenario": "scenarios/wind_farm_control/main.yaml", "budget": BUDGET,
            "what": "Training return (mean per turbine-episode) at every summary point of `hivex train`, by seed.",
            "curves": {str(seed): curve for seed, curve in sorted(curves.items())}}, separators=(",", ":")) + "\n")
        print(f"wrote {COMMITTED}")
    theirs = original_wfc_main()
    ours = [curves[seed] for seed in sorted(curves)]
    print(f"seeds {sorted(curves)}; the original's three runs\n")
    print(comparison_table(compare_curves(ours, theirs, BUDGET)))
    print(f"\nfirst point: ours {[round(c[0][1]) for c in ours]} at {[c[0][0] for c in ours]}, "
          f"the original's {[round(c[0][1]) for c in theirs]} at 40,000")
    print(f"mean of the points up to {EARLY:,}: ours {[round(early_mean(c)) for c in ours]}, "
          f"the original's {[round(early_mean(c)) for c in theirs]}")


if __name__ == "__main__":
    main()
