"""End-to-end training throughput of `hivex train` (environment, policy and updates) per environment.

    python benchmarks/train_throughput.py [--env ID ...] [--steps 200000] [--processes N] [--set NAME=VALUE ...]
                                          [-o out.json]

With -o benchmarks/results/train_throughput.json (what the baselines page shows) the rows are merged into
the file: a row of the same environment, worlds, threads, device and processes is replaced, others are kept.

For each environment's main scenario it trains for --steps agent-steps with the paper's hyperparameters
(overridable with --set, e.g. --set num_worlds=32 or --set device=cuda) and reports agent-steps per second and
the share of the wall time spent inside the vector env's step. With --processes N it trains N runs of the
environment at once, each in its own process on its own training seed (how a grid's points share a machine:
on a GPU machine the policies share the GPU and the environments the CPU cores), and reports their summed
agent-steps over the slowest run's wall time. Measure on a quiet machine: run nothing else, and compare figures
only between runs on the same machine (each row names its machine).
"""

from __future__ import annotations

import argparse
import datetime
import json
import os
import subprocess
import tempfile
import time
from concurrent.futures import ProcessPoolExecutor
from multiprocessing import get_context
from pathlib import Path

from hivex_dsl.compiler import registry
from hivex_dsl.adapters.gymnasium import HivexVectorEnv
from hivex_dsl.compiler import compile
from hivex_dsl.train.devices import machine
from hivex_dsl.train.config import Overrides, make_config, parse_assignments
from hivex_dsl.train.ppo import train

SCENARIOS = Path(__file__).resolve().parents[1] / "scenarios"


def measure(environment: str, steps: int, overrides: Overrides) -> dict:
    """One training run of ``environment``'s main scenario for ``steps`` agent-steps, timed."""
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
            "num_worlds": cfg.num_worlds, "torch_threads": cfg.threads(), "device": cfg.device, "processes": 1,
            "agents": compiled.agents, "buffer_size": cfg.buffer_size, "batch_size": cfg.batch_size,
            "num_epoch": cfg.num_epoch, "precision": cfg.precision, "machine": machine(cfg.device)}


def measure_concurrently(environment: str, steps: int, overrides: Overrides, processes: int) -> dict:
    """``processes`` runs of ``environment`` at once (training seeds 0, 1, ...), each in a fresh process;
    -> one row: their summed agent-steps over the slowest one's wall time, the mean env share."""
    if processes == 1:
        return measure(environment, steps, overrides)
    values = dict(overrides.values)  # a plain mapping travels to the workers (Overrides holds a lambda)
    seeded = [values | {"seed": int(values.get("seed", 0)) + i} for i in range(processes)]
    with ProcessPoolExecutor(processes, mp_context=get_context("spawn")) as pool:
        runs = list(pool.map(measure, [environment] * processes, [steps] * processes, seeded))
    wall = max(run["wall_s"] for run in runs)
    total = sum(run["agent_steps"] for run in runs)
    return runs[0] | {"agent_steps": total, "wall_s": wall, "agent_steps_per_s": round(total / wall, 1),
                      "env_share": round(sum(run["env_share"] for run in runs) / processes, 3),
                      "processes": processes}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--env", action="append", help="environment id (repeatable; default all)")
    parser.add_argument("--steps", type=int, default=200_000, help="agent-steps per environment (and per process)")
    parser.add_argument("--processes", type=int, default=1, help="concurrent runs per environment (default 1)")
    parser.add_argument("--set", action="append", default=[], dest="assignments", metavar="NAME=VALUE")
    parser.add_argument("-o", "--output", type=Path)
    args = parser.parse_args()
    if args.processes < 1 or args.processes > (os.cpu_count() or 1):
        parser.error(f"--processes: expected 1 to {os.cpu_count()} (this machine's cores), got {args.processes}")
    overrides = parse_assignments(args.assignments)
    rows = []
    for env in args.env or registry.environments():
        row = measure_concurrently(env, args.steps, overrides, args.processes) | when_and_what()
        rows.append(row)
        print(f"{row['environment']:32} {row['agent_steps_per_s']:>10,.0f} agent-steps/s  "
              f"env {100 * row['env_share']:.0f}% of the time  ({row['processes']} x {row['torch_threads']} "
              f"threads, {row['device']}, {row['wall_s']:.1f} s)", flush=True)
        if args.output:  # after each environment: a run stopped part-way keeps what it measured
            args.output.write_text(json.dumps(merged(args.output, [row]), indent=2) + "\n")


def when_and_what() -> dict:
    """The day (UTC) of a measurement and the code measured: the repository's commit, "+changes" where the work
    tree differs from it (None outside a git checkout). Rows of different days differ by several per cent on a
    shared machine: compare a change with a baseline measured the same day."""
    day = datetime.datetime.now(datetime.timezone.utc).date().isoformat()
    root = Path(__file__).resolve().parents[1]
    try:
        commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=root, capture_output=True, text=True,
                                check=True).stdout.strip()
        changed = subprocess.run(["git", "diff", "--quiet", "HEAD", "--", "hivex_dsl"], cwd=root).returncode != 0
    except (OSError, subprocess.CalledProcessError):
        return {"measured": day, "commit": None}
    return {"measured": day, "commit": commit + ("+changes" if changed else "")}


def merged(path: Path, rows: list[dict]) -> dict:
    """The report at ``path`` (if any) with ``rows`` replacing the rows of the same configuration on the same
    machine (another machine's rows of that configuration are kept: an H200's do not replace an H100's)."""
    key = lambda row: (row["machine"], row["environment"], row["num_worlds"], row["torch_threads"],  # noqa: E731
                       row.get("device", "cpu"), row.get("processes", 1), row.get("precision", "exact"))
    report = json.loads(path.read_text()) if path.is_file() else {"rows": []}
    # rows written before rows named their machine, device and precision: the file's machine, one exact process
    # on the CPU
    earlier = {"machine": report.get("machine", machine()), "device": "cpu", "processes": 1, "precision": "exact"}
    old = [earlier | row for row in report["rows"]]
    fresh = {key(row) for row in rows}
    kept = [row for row in old if key(row) not in fresh]
    return {"rows": sorted(kept + rows, key=key)}


if __name__ == "__main__":
    main()
