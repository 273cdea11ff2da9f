"""Ocean Plastic Collection: how long trained vessels live against the collision distance (issue 52).

The original's trained vessel-episodes end after about 150 decisions (its Episode Length at 50-100% of the budget);
this toolkit's record until session 69 (benchmarks/results/opc_record_5m.json), trained at a collision distance of
5 m, learned to live 193-246. This records the training curves of runs of the main scenario at other collision
distances, as `hivex train` wrote them, beside the commands that trained them, for
tests/fidelity/test_opc_collision.py and the reward table's ending note:

    hivex train SCENARIO -o runs/opc-coll10-s0 --seed 0 --set torch_threads=1 --set num_worlds=8 \
        --set buffer_fill=rollout   (SCENARIO: the main scenario with params: {collision_distance_m: 10.0}; the
        committed record's protocol, 8 worlds on the fixed rollout; stopped when it had passed half the budget)
    python benchmarks/opc_collision.py runs/opc-coll10-s0 [RUN ...] -o benchmarks/results/opc_collision.json

and prints each run's Episode Length, Local Reward and return at 10, 25 and 50% of the budget beside the original's
training mean and band (the fidelity page's measure, hivex_dsl.evaluation.original.compare).
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

ENV = "ocean_plastic_collection"
FRACTIONS = (0.1, 0.25, 0.5)
PANELS = ("Episode Length", "Local Reward", "Cumulative Reward")
KEPT = ("agent_steps", "return", "episodes", "length", "statistics")


class RunError(Exception):
    """A run folder this script cannot read as an Ocean Plastic Collection training run."""


def read_run(folder: Path) -> dict:
    """One run's collision distance, seed, hyperparameters and training curve (curve.json's points)."""
    try:
        config = json.loads((folder / "config.json").read_text())
        points = json.loads((folder / "curve.json").read_text())
    except (OSError, json.JSONDecodeError) as error:
        raise RunError(f"{folder}: not a training run's folder ({error})") from None
    scenario = config.get("scenario", {})
    if scenario.get("environment") != ENV:
        raise RunError(f"{folder}: a run of {scenario.get('environment')!r}, expected {ENV!r}")
    if not points:
        raise RunError(f"{folder}: its curve holds no training point yet")
    hyperparameters = config["hyperparameters"]
    return {"collision_distance_m": scenario["params"]["collision_distance_m"],
            "seed": hyperparameters["seed"], "max_steps": hyperparameters["max_steps"],
            "hyperparameters": hyperparameters, "scenario": scenario, "agent_steps": points[-1]["agent_steps"],
            "curve": [{key: point[key] for key in KEPT} for point in points]}


def report(runs: list[dict]) -> str:
    """Each run's measure against the original's band, a line a panel."""
    from hivex_dsl.evaluation.original import compare

    cell = compare.original_cell(ENV, 0, None)
    lines = []
    for run in runs:
        curve = compare.from_points(run["curve"], f"{run['collision_distance_m']:g} m, seed {run['seed']}")
        rows = {(row.panel, row.fraction): row for row in compare.measure(curve, cell, FRACTIONS)}
        lines.append(f"collision distance {run['collision_distance_m']:g} m, seed {run['seed']}, "
                     f"{run['agent_steps']:,} agent-steps")
        for panel in PANELS:
            cells = [f"{row.ours.value:,.0f} against {row.mean:,.0f} [{row.lower:,.0f}-{row.upper:,.0f}] {row.verdict}"
                     if row.ours.value is not None else "-" for row in (rows[(panel, f)] for f in FRACTIONS)]
            lines.append(f"  {panel}: " + " | ".join(cells))
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("runs", nargs="+", type=Path, help="run folders `hivex train` wrote")
    parser.add_argument("-o", "--output", type=Path, help="write the runs' curves to this JSON file")
    args = parser.parse_args(argv)
    try:
        runs = [read_run(folder) for folder in args.runs]
    except RunError as error:
        print(f"opc_collision: {error}", file=sys.stderr)
        return 2
    print(report(runs))
    if args.output:
        args.output.write_text(json.dumps({"environment": ENV, "source": __doc__.split("\n\n")[1].strip(),
                                           "runs": runs}, indent=1) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
