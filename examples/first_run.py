"""`make run`: this toolkit's main job, whole, in under a minute on two quiet cores.

It trains parameter-shared PPO (`hivex train`, the paper's hyperparameters) on Wind Farm Control's main task,
evaluates the trained policy on the test seeds (`hivex evaluate`), plays the random and the scripted policy on
the same test episodes, writes a replay page of one test episode of the trained policy (`hivex replay`), draws the
learning curve, and ends with a verdict beside the paper's published return and the paths of everything it wrote.

    python examples/first_run.py [--scenario scenarios/wind_farm_control/main.yaml] [--steps 2560000]
                                 [--episodes 3] [-o runs/first-run] [--set NAME=VALUE ...] [--replay-steps N]

An earlier run is never replaced: without -o a used runs/first-run leaves the run to runs/first-run-2 (-3...);
a given -o must be new or empty. first_run.json's final_return is the trained policy's mean return on the test
episodes at the end; summary.json's is training's last mean episode return.

The default budget is 2,560,000 agent-steps, a third of the paper's 8M, in 8 worlds x 8 turbines (WORLDS; `--set
num_worlds=N` for another count): eight episodes of 5,000 steps in each world. Every world ends its episode at
once, so the learning curve gets a point at each of them. It updates on a fixed rollout of 2,048 experiences
(FAST: `buffer_fill: rollout`), several times as often as the original's one environment did, which learns the
task in this budget; `hivex train`'s Wind Farm Control defaults (one world, `buffer_fill: trajectories`) update
when the original did and learn at its pace, reaching the published return only near the paper's whole budget
(`--set num_worlds=1 --set buffer_fill=trajectories --steps 8000000`, several times as long).
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from hivex_dsl.compiler import compile
from hivex_dsl.replay import replay
from hivex_dsl.replay.sources import checkpoint_player
from hivex_dsl.train.baselines import LEVEL_POLICIES, level_of
from hivex_dsl.train.config import make_config, parse_assignments
from hivex_dsl.train.evaluate import evaluate
from hivex_dsl.train.ppo import train

ROOT = Path(__file__).resolve().parents[1]
DEFAULT_STEPS = 2_560_000
DEFAULT_OUTPUT = Path("runs") / "first-run"
WORLDS = 8  # parallel worlds: enough episodes in the default budget for a learning curve of several points
FAST = {"num_worlds": WORLDS, "buffer_fill": "rollout"}  # a quick first run, not the original's learning pace


def parse_args(argv=None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenario", default=str(ROOT / "scenarios" / "wind_farm_control" / "main.yaml"))
    parser.add_argument("--steps", type=int, default=DEFAULT_STEPS, help="agent-steps to train")
    parser.add_argument("--episodes", type=int, default=3, help="test episodes of each policy")
    parser.add_argument("-o", "--output", type=Path, default=None,
                        help=f"run directory (default {DEFAULT_OUTPUT}, or {DEFAULT_OUTPUT}-2, -3... where it holds "
                             "an earlier run; a given one must be new or empty)")
    parser.add_argument("--set", action="append", default=[], dest="assignments", metavar="NAME=VALUE")
    parser.add_argument("--replay-steps", type=int, default=None, metavar="N",
                        help="decisions of the replay page (default: the whole test episode)")
    return parser.parse_args(argv)


def run_config(environment: str, args: argparse.Namespace):
    """The paper's hyperparameters with FAST's fixed rollout in WORLDS worlds, then the user's --set values, then the
    budget's."""
    return make_config(environment, FAST, parse_assignments(args.assignments),
                       {"max_steps": args.steps, "checkpoint_every": max(args.steps // 4, 1)})


def main(argv=None) -> dict:
    """Train, evaluate, compare, plot; -> the comparison (also written as ``RUN_DIR/first_run.json``)."""
    args = parse_args(argv)
    if args.output is None:
        args.output = fresh_folder(DEFAULT_OUTPUT)
    elif args.output.exists() and any(args.output.iterdir()):
        raise SystemExit(f"first_run: {args.output} is not empty; give a new folder with -o (nothing was replaced)")
    compiled = compile(args.scenario)
    cfg = run_config(compiled.environment, args)
    say(f"1/4 training {compiled.name} for {args.steps:,} agent-steps ({cfg.num_worlds} worlds x "
        f"{compiled.agents} agents, the paper's hyperparameters) into {args.output}")
    summary = train(compiled, cfg, args.output, progress=sys.stderr.isatty())
    say(f"2/4 the trained policy on {args.episodes} test episodes (seed {compiled.seeds.test})")
    report = evaluate(args.output / "checkpoint.pt", split="test", episodes=args.episodes)
    say(f"3/4 the random and the scripted policy on the same {args.episodes} test episodes")
    levels = {name: level_of(compiled, name, args.episodes) for name in LEVEL_POLICIES}
    result = {"scenario": compiled.name, "agent_steps": summary["agent_steps"], "wall_s": summary["wall_s"],
              "episodes": args.episodes, "final_return": report["return"]["mean"],  # the trained policy's, at the end
              "trained": report["return"], "published": (report["published"] or {}).get("return"), **levels,
              "run_dir": str(args.output), "tensorboard": str(args.output / "tb")}
    say(f"4/4 a replay page of the trained policy's first test episode, term by term")
    result["replay"] = str(replay([checkpoint_player(args.output / "checkpoint.pt")], args.output / "replay.html",
                                  steps=args.replay_steps)["path"])
    result["curve"] = draw_curve(result, args.output)
    (args.output / "first_run.json").write_text(json.dumps(result, indent=2) + "\n")
    print(verdict(result))
    return result


def fresh_folder(preferred: Path) -> Path:
    """``preferred`` if it is new or empty, else the first of ``preferred-2``, ``-3``... that is: an earlier run
    is never replaced."""
    candidates = [preferred] + [preferred.with_name(f"{preferred.name}-{n}") for n in range(2, 10_000)]
    chosen = next(c for c in candidates if not c.exists() or not any(c.iterdir()))
    if chosen != preferred:
        say(f"{preferred} holds an earlier run (kept): this run goes to {chosen}")
    return chosen


def say(line: str) -> None:
    print(line, file=sys.stderr, flush=True)


def draw_curve(result: dict, run_dir: Path) -> str | None:
    """The training curve PNG beside the test-seed levels (None without matplotlib, the `plots` extra)."""
    from hivex_dsl.train.config import TrainError
    from hivex_dsl.train.plots import learning_curve

    curve = json.loads((run_dir / "curve.json").read_text())
    data = {"environment": result["scenario"], "task": "first run", "agent_steps": result["agent_steps"],
            "curve": [[p["agent_steps"], p["wall_s"], p["return"]] for p in curve],
            "test": {"return": result["trained"], "episodes": result["episodes"]}, "random": result["random"],
            "scripted": result["scripted"], "published": {"return": result["published"]} if result["published"] else None}
    try:
        return str(learning_curve(data, run_dir / "curve.png"))
    except TrainError:
        return None


def verdict(result: dict) -> str:
    """A few readable lines: ours beside the paper's, the trivial and the scripted policy, and the paths."""
    ours, paper = result["trained"], result["published"]
    lines = [f"{result['scenario']}: PPO trained {result['agent_steps']:,} agent-steps in {result['wall_s']:.0f} s",
             f"  trained policy (test seeds)   {ours['mean']:10.1f} ± {ours['std']:.1f}"]
    if paper:
        lines.append(f"  the paper's PPO (published)   {paper['mean']:10.1f} ± {paper['std']:.1f}   "
                     f"(its spread is over TensorBoard summary points, not single episodes)")
    lines += [f"  random policy                 {result['random']['mean']:10.1f} ± {result['random']['std']:.1f}",
              f"  scripted policy               {result['scripted']['mean']:10.1f} ± {result['scripted']['std']:.1f}"]
    if paper:
        gap = ours["mean"] - paper["mean"]
        lines.append(f"  verdict: {'above' if gap >= 0 else 'below'} the paper's return by {abs(gap):.1f} "
                     f"({100 * gap / abs(paper['mean']):+.1f}%)")
    lines += [f"run directory: {result['run_dir']} (checkpoint.pt, curve.json, summary.json)",
              f"learning curve: {result['curve'] or 'not drawn: pip install hivex-dsl[plots]'}",
              f"replay (open it in a browser): {result['replay']}",
              f"TensorBoard: tensorboard --logdir {result['tensorboard']}"]
    return "\n".join(lines)


if __name__ == "__main__":
    main()
