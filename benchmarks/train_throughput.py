"""End-to-end training throughput of `hivex train` (environment, policy and updates) per environment.

    python benchmarks/train_throughput.py [--env ID ...] [--steps 200000] [--set NAME=VALUE ...] [-o out.json]

With -o benchmarks/results/train_throughput.json (what the baselines page shows) the rows are merged into
the file: a row of the same environment, worlds and threads is replaced, others are kept.

For each environment's main scenario it trains for --steps agent-steps with the paper's hyperparameters
(overridable with --set, e.g. --set num_worlds=32) and reports agent-steps per second and the share of the
wall time spent inside the vector env's step. Measure on a quiet machine: run nothing else, and compare
figures only between runs on the same machine (the issue's targets: Wind Farm Control 50,000 and Aerial
Wildfire Suppression 2,000 agent-steps/s on 2 CPU cores).
"""

from __future__ import annotations

import argparse
import json
import tempfile
import time
from pathlib import Path

from hivex_dsl import registry
from hivex_dsl.adapters.gymnasium import HivexVectorEnv
from hivex_dsl.compiler import compile
from hivex_dsl.train.baselines import machine
from hivex_dsl.train.config import Overrides, make_config, parse_assignments
from hivex_dsl.train.ppo import train

SCENARIOS = Path(__file__).resolve().parents[1] / "scenarios"


def measure(environment: str, steps: int, overrides: Overrides) -> dict:
    compiled = compile(SCENARIOS / environment / "main.yaml")
    cfg = make_config(environment, overrides, {"max_steps": steps, "checkpoint_every": 10 * steps})
    inside = [0.0]
    step = HivexVectorEnv.step

    def timed(self, actions):
        start = time.perf_counter()
        try:
            return step(self, actions)
        finally:
            inside[0] += time.perf_counter() - start

    HivexVectorEnv.step = timed
    try:
        with tempfile.TemporaryDirectory() as run_dir:
            summary = train(compiled, cfg, Path(run_dir), progress=False)
    finally:
        HivexVectorEnv.step = step
    wall = summary["wall_s"]
    return {"environment": environment, "agent_steps": summary["agent_steps"], "wall_s": wall,
            "agent_steps_per_s": round(summary["agent_steps"] / wall, 1), "env_share": round(inside[0] / wall, 3),
            "num_worlds": cfg.num_worlds, "torch_threads": cfg.torch_threads,
            "agents": compiled.agents, "buffer_size": cfg.buffer_size, "batch_size": cfg.batch_size,
            "num_epoch": cfg.num_epoch}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--env", action="append", help="environment id (repeatable; default all)")
    parser.add_argument("--steps", type=int, default=200_000, help="agent-steps per environment")
    parser.add_argument("--set", action="append", default=[], dest="assignments", metavar="NAME=VALUE")
    parser.add_argument("-o", "--output", type=Path)
    args = parser.parse_args()
    overrides = parse_assignments(args.assignments)
    rows = [measure(env, args.steps, overrides) for env in args.env or registry.environments()]
    for row in rows:
        print(f"{row['environment']:32} {row['agent_steps_per_s']:>10,.0f} agent-steps/s  "
              f"env {100 * row['env_share']:.0f}% of the time")
    if args.output:
        args.output.write_text(json.dumps(merged(args.output, rows), indent=2) + "\n")


def merged(path: Path, rows: list[dict]) -> dict:
    """The report at ``path`` (if any) with ``rows`` replacing the rows of the same configuration."""
    key = lambda row: (row["environment"], row["num_worlds"], row["torch_threads"])  # noqa: E731
    old = json.loads(path.read_text())["rows"] if path.is_file() else []
    fresh = {key(row) for row in rows}
    kept = [row for row in old if key(row) not in fresh]
    return {"machine": machine(), "rows": sorted(kept + rows, key=key)}


if __name__ == "__main__":
    main()
