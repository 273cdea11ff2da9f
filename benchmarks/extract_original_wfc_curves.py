"""Extract the original's Wind Farm Control learning curves into compact package data.

    python benchmarks/extract_original_wfc_curves.py [EVENT_SCALARS_JSON]

Input: the original's raw TensorBoard scalars of WFC main task, pattern 0 (three training runs of 200
summary points every 40,000 agent-steps, and their three test runs), as copied from
hivex-research/hivex-results into the session's shared folder (default
``../shared/paper/original-wfc-event-scalars.json``). Output:
``hivex_dsl/data/original-wfc-main-curves.json``: the step axis once and, per scalar that bears on learning
(return, Individual Performance, policy entropy, and the clip epsilon whose decay dates the updates), the three
runs' values, as
:mod:`hivex_dsl.evaluation.curves` reads them.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
DEFAULT_INPUT = ROOT.parent / "shared" / "paper" / "original-wfc-event-scalars.json"
OUTPUT = ROOT / "hivex_dsl" / "data" / "original-wfc-main-curves.json"
SCALARS = {"Environment/Cumulative Reward": 1, "WindFarmControl/Individual Performance": 1, "Policy/Entropy": 4,
           "Policy/Epsilon": 6}  # epsilon as logged: its linear decay dates the updates of each summary point


def runs_of(scalars: dict, split: str) -> tuple[list[int], dict[str, list[list[float]]]]:
    """(steps, {scalar: [run 0 values, run 1 values, run 2 values]}) of the train or test runs."""
    names = sorted(name for name in scalars["runs"] if name.startswith(f"{split}_run_"))
    steps = [int(step) for step, _ in scalars["runs"][names[0]]["Environment/Cumulative Reward"]]
    values = {}
    for scalar, digits in SCALARS.items():
        series = [scalars["runs"][name][scalar] for name in names]
        if any([int(step) for step, _ in points] != steps for points in series):
            raise ValueError(f"{scalar}: the {split} runs are not logged at the same steps")
        values[scalar] = [[round(value, digits) for _, value in points] for points in series]
    return steps, values


def main() -> None:
    source = Path(sys.argv[1]) if len(sys.argv) > 1 else DEFAULT_INPUT
    scalars = json.loads(source.read_text())
    train_steps, train = runs_of(scalars, "train")
    test_steps, test = runs_of(scalars, "test")
    data = {
        "source": scalars["source"],
        "what": ("The original's Wind Farm Control main task (Generate Energy), pattern 0: three ML-Agents training "
                 "runs (one environment of 8 turbines, env seed 5000 in all three, so every run met the same "
                 "wind in its n-th episode) and their test runs (learning rate 0, seed 6000). Each value is one "
                 "TensorBoard summary point (40,000 agent-steps: one episode of the 8 turbines)."),
        "train": {"steps": train_steps, "runs": train},
        "test": {"steps": test_steps, "runs": test},
    }
    OUTPUT.write_text(json.dumps(data, separators=(",", ":")) + "\n")
    print(f"wrote {OUTPUT} ({OUTPUT.stat().st_size:,} bytes)")


if __name__ == "__main__":
    main()
