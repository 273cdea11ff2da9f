"""`hivex train` and `hivex evaluate`: argument parsing here, the work in train's ppo/grid/evaluate (imported
lazily, so the rest of the CLI never needs torch). Moved here from train/ so that train never imports the CLI."""

from __future__ import annotations

import argparse
import importlib.util
import json
import os
import sys
from pathlib import Path
from typing import TYPE_CHECKING

from ..base.errors import HivexError
from .argtypes import positive, seed
from .exits import EXIT_INTERRUPTED

if TYPE_CHECKING:
    from ..train.config import PPOConfig

TRAIN_EXTRA = "training needs torch: pip install torch, then pip install 'hivex-dsl[train]'"
TRAIN_MODULES = ("tensorboard",)  # the train extra's packages besides torch


def add_commands(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("train", help="train the paper's parameter-shared PPO on a scenario (a sweep trains every point)")
    p.add_argument("file", metavar="SCENARIO", help="scenario file; a sweep file trains every grid point")
    p.add_argument("-o", "--output", type=Path, default=None, metavar="RUN_DIR",
                   help="run directory (default runs/<scenario name>)")
    p.add_argument("--steps", type=positive, default=None,
                   help="agent-steps to train: decisions of every agent, as ML-Agents counts them, rounded up "
                        "to a whole step of every slot (worlds x agents; the last rollout stops there) "
                        "(default: the max_steps of the environment's config that ran)")
    p.add_argument("--seed", type=seed, default=None, help="seed of the network and the action sampling (default 0)")
    p.add_argument("--device", default=None, help="torch device: cpu, cuda or cuda:N (default cpu)")
    p.add_argument("--config", type=Path, default=None, metavar="YAML",
                   help="hyperparameters overriding the paper's (ML-Agents' key names)")
    p.add_argument("--set", action="append", default=[], metavar="NAME=VALUE", dest="assignments",
                   help="override one hyperparameter (repeatable), e.g. --set num_worlds=16")
    p.add_argument("--eval-episodes", type=int, default=0, metavar="N",
                   help="after training, evaluate on the test seeds for N episodes (default 0: skip)")
    p.add_argument("--ray", nargs="?", const="local", default=None, metavar="ADDRESS",
                   help="run a sweep's points as Ray tasks: a local instance, or the cluster at ADDRESS")
    p.add_argument("--jobs", type=positive, default=1, metavar="N",
                   help="train N points of a sweep at once, each in a process of its own (default 1: in turn); "
                        "a point's auto torch threads are then the cores / N. On two cores, --jobs 2 trains a grid "
                        "faster than one point at a time on both")
    p.add_argument("--points", default=None, metavar="INDICES",
                   help="train only these points of a sweep, by their index as `hivex compile` numbers them: "
                        "e.g. 14-29 or 0,3,5-7 (each in the folder of its index, so a grid can be trained a few "
                        "points at a time, on several machines)")
    p.add_argument("--resume", action="store_true",
                   help="go on from RUN_DIR/checkpoint.pt (same scenario and hyperparameters; --steps may grow)")
    p.add_argument("--force", action="store_true",
                   help="replace an earlier run in RUN_DIR (without it, or --resume, a used RUN_DIR is refused)")
    p.add_argument("--no-progress", action="store_true",
                   help="no progress bars (of training and of --eval-episodes; shown only on a terminal anyway)")
    p.add_argument("--json", action="store_true", help="print a single run's summary as JSON (summary.json's fields)")
    p.set_defaults(handler=cmd_train)

    p = sub.add_parser("evaluate", help="test a trained checkpoint on the test seeds, beside the published result")
    p.add_argument("checkpoint", type=Path, metavar="CHECKPOINT")
    p.add_argument("file", nargs="?", default=None, metavar="SCENARIO",
                   help="scenario to evaluate on (default: the one the checkpoint trained on)")
    p.add_argument("--point", metavar="INDEX|KEY=VALUE,...", default=None,
                   help="one point of a sweep SCENARIO: its index or its swept values")
    p.add_argument("--split", choices=("train", "test"), default="test", help="seed split (default test)")
    p.add_argument("--episodes", type=positive, default=10, help="episodes (default 10)")
    p.add_argument("--deterministic", action="store_true", help="take the policy's modes instead of sampling")
    p.add_argument("--seed", type=seed, default=0, help="seed of the action sampling (default 0)")
    p.add_argument("--torch-threads", type=positive, default=1, metavar="N",
                   help="torch threads of the network (default 1: one world's agents are small batches)")
    p.add_argument("--json", action="store_true", help="print the report as JSON")
    p.set_defaults(handler=cmd_evaluate)


def require_torch() -> None:
    """torch and the rest of the ``train`` extra (tensorboard writes the scalars), or one
    sentence naming what to install: torch alone gave a ModuleNotFoundError traceback for tensorboard."""
    try:
        import torch  # noqa: F401
    except ImportError:
        raise HivexError(TRAIN_EXTRA) from None
    missing = [name for name in TRAIN_MODULES if importlib.util.find_spec(name) is None]
    if missing:
        raise HivexError(f"training needs {' and '.join(missing)} beside torch: pip install 'hivex-dsl[train]'")


def train_config(environment: str, args: argparse.Namespace) -> PPOConfig:
    """The hyperparameters `hivex train` runs ``environment`` with: the paper's, then --config, --set and the
    flags (--steps, --seed, --device), each over the last."""
    from ..train.config import Overrides, make_config, parse_assignments, read_overrides

    flag_of = {"max_steps": "--steps", "seed": "--seed", "device": "--device"}
    given = {name: getattr(args, flag[2:]) for name, flag in flag_of.items()}
    flags = Overrides({name: value for name, value in given.items() if value is not None},
                      locate=lambda name, key: flag_of[name])
    layers = [read_overrides(args.config) if args.config else {}, parse_assignments(args.assignments), flags]
    return make_config(environment, *layers)


def cmd_train(args) -> int:
    from ..compiler import compile_all

    require_torch()
    points = compile_all(args.file)
    indices = list(range(len(points)))
    if args.points is not None:
        from .points import point_indices

        if len(points) == 1:
            raise HivexError(f"--points chooses points of a sweep, and {args.file} is one scenario")
        indices = point_indices(args.points, len(points), str(args.file))
        points = [points[i] for i in indices]
    configs = [train_config(p.environment, args) for p in points]
    if args.eval_episodes < 0:
        raise HivexError(f"--eval-episodes must be 0 or more, got {args.eval_episodes}")
    if args.resume and args.force:
        raise HivexError("--resume goes on from RUN_DIR's run and --force replaces it: give one")
    if args.jobs > 1 and args.ray is not None:
        raise HivexError(f"--jobs {args.jobs} runs the points in local processes and --ray runs them as Ray tasks "
                         "(one CPU each): give one")
    run_dir = args.output or Path("runs") / points[0].spec.name
    if len(points) == 1 and args.ray is None and args.points is None:
        from ..train.grid import train_point

        result = train_point(points[0].resolved(), configs[0].model_dump(mode="json"), str(run_dir),
                             args.eval_episodes, progress=not args.no_progress, resume=args.resume,
                             overwrite=args.force)
        print(json.dumps(result, indent=2) if args.json else format_run(result, run_dir, args.file))
        _say_if_no_episode_ended(result, points[0], configs[0])
        return _exit_code([result], run_dir)
    from ..train.grid import format_table, run_grid

    results = run_grid(points, configs, run_dir, args.eval_episodes, args.ray, progress=not args.no_progress,
                       resume=args.resume, overwrite=args.force, jobs=args.jobs, indices=indices)
    print(format_table(results))
    print(f"wrote {run_dir / 'results.json'}")
    return _exit_code(results, run_dir)


def format_run(result: dict, run_dir: Path, scenario: Path) -> str:
    """A finished (or stopped) run in a few lines: what it trained, where it wrote, and the command to run next."""
    shown = "no episode ended" if result["final_return"] is None else \
        f"last mean episode return {result['final_return']:,.2f}"
    verb = "stopped early after" if result["stopped_early"] else "trained"
    lines = [f"{result['scenario']}: {verb} {result['agent_steps']:,} agent-steps in {result['wall_s']:,.1f} s "
             f"({shown})",
             f"run directory {run_dir}: checkpoint.pt, curve.json, summary.json, tb/ (tensorboard --logdir "
             f"{run_dir / 'tb'})"]
    if "test_return" in result:
        test = result["test_return"]
        lines.append(f"test seeds: return {test['mean']:,.2f} ± {test['std']:,.2f} per agent and episode "
                     "(evaluation.json)")
    checkpoint = run_dir / "checkpoint.pt"
    lines.append(f"next: hivex evaluate {checkpoint} --episodes 10   (the test seeds, beside the published result)")
    lines.append(f"      hivex render {scenario} --checkpoint {checkpoint} -o episode.gif   (watch it play)")
    return "\n".join(lines)


def _say_if_no_episode_ended(result: dict, compiled, cfg: PPOConfig) -> None:
    """A run too short for any episode to end has no return to show (final_return null, curve.json empty):
    say so, and how long an episode is, rather than leave a null to puzzle over."""
    if result["final_return"] is not None or result["stopped_early"]:
        return
    slots, decisions = cfg.num_worlds * compiled.agents, compiled.episode_decisions
    print(f"hivex: no episode ended within {result['agent_steps']:,} agent-steps, so the run has no return yet: an "
          f"episode of {compiled.name} lasts {decisions:,} {'steps' if compiled.decision_period == 1 else 'decisions'} "
          f"of each of its {slots} slots ({decisions * slots:,} agent-steps); train longer with --steps",
          file=sys.stderr)


def _exit_code(results: list[dict], run_dir: Path) -> int:
    """0, or the CLI's 130 when Ctrl-C or SIGTERM stopped a run before its end (saying how to go on)."""
    if not any(result["stopped_early"] for result in results):
        return 0
    print(f"hivex: interrupted: the run stopped after its update and kept its checkpoint; add --resume to the "
          f"same command to go on in {run_dir}", file=sys.stderr)
    return EXIT_INTERRUPTED


def cmd_evaluate(args) -> int:
    from .points import one_point
    from ..train.evaluate import evaluate, format_report

    require_torch()
    if args.owns_process:
        _with_the_checkpoint_s_kernels(args.checkpoint)
    if args.point is not None and not args.file:
        raise HivexError("--point chooses a point of a sweep SCENARIO: give the SCENARIO after the CHECKPOINT")
    scenario = one_point(args.file, args.point) if args.file else None
    report = evaluate(args.checkpoint, scenario, args.split, args.episodes, args.deterministic, args.seed,
                      args.torch_threads, progress=not args.json)
    sys.stdout.write(json.dumps(report, indent=2) + "\n" if args.json else format_report(report) + "\n")
    return 0


def _with_the_checkpoint_s_kernels(checkpoint: Path) -> None:
    """A checkpoint trained with ``cpu_kernels portable`` plays under those kernels, which must be pinned before torch's
    first dispatch, and reading a checkpoint dispatches: so the command starts again in a fresh process whose
    environment pins them from its start (:data:`~hivex_dsl.train.kernels.PORTABLE_ENVIRONMENT`). Nothing to do for a
    native checkpoint, or where the environment pins them already. Only for the process's own command line: called
    from Python (``main(argv)``), :func:`~hivex_dsl.train.evaluate.evaluate` says a fresh process is needed."""
    from ..train.checkpoint import load_checkpoint
    from ..train.kernels import PORTABLE_ENVIRONMENT

    pinned = all(os.environ.get(name) == value for name, value in PORTABLE_ENVIRONMENT.items())
    if pinned or load_checkpoint(checkpoint)["config"].cpu_kernels != "portable":
        return
    sys.stdout.flush()
    sys.stderr.flush()
    os.execve(sys.executable, [sys.executable, "-m", "hivex_dsl.cli", *sys.argv[1:]],
              os.environ | PORTABLE_ENVIRONMENT)
