"""Layer 11, cli: the `hivex` command, the top layer.

This module parses the arguments and runs the commands; audit_command.py, train_commands.py, replay_command.py
and curves_command.py hold `hivex audit`'s, `hivex train`/`evaluate`'s, `hivex replay`'s and `hivex curves`',
argtypes.py and points.py what several commands read, exits.py the exit codes.
Imports: every layer below (each command imports the work it needs when it runs, so the CLI never needs torch).
"""

from __future__ import annotations

import argparse
import json
import os
import sys
from pathlib import Path
from typing import Sequence

from ..base.errors import HivexError, ScenarioError, did_you_mean
from .argtypes import positive, seed
from .exits import EXIT_FAIL, EXIT_INTERRUPTED, EXIT_OK, EXIT_PIPE, EXIT_USAGE

FRAME_STEP = 10  # `hivex render`'s default: 61 frames of 600 decisions, 1.1 MB for WFC (the largest; 6.3 MB before)


def main(argv: Sequence[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    args.owns_process = argv is None  # the command line of this process, which a command may start again
    try:
        code = args.handler(args)
        sys.stdout.flush()  # here, so a reader that went away (`| head -1`) is seen while we can still handle it
        return code
    except BrokenPipeError:
        return _reader_gone()
    except ScenarioError as exc:
        for problem in exc.problems:
            print(problem, file=sys.stderr)
        return EXIT_USAGE
    except HivexError as exc:
        print(f"hivex: {exc}", file=sys.stderr)
        return EXIT_USAGE
    except KeyboardInterrupt:
        print("hivex: interrupted", file=sys.stderr)
        return EXIT_INTERRUPTED
    except OSError as exc:  # an output path the system refuses (permissions, a full disk, ...)
        where = f": {exc.filename}" if exc.filename else ""
        print(f"hivex: {exc.strerror or exc}{where}", file=sys.stderr)
        return EXIT_FAIL


def _reader_gone() -> int:
    """stdout's reader closed the pipe: stop quietly, as `yes | head -1` does; point stdout at /dev/null so
    Python's own flush at exit does not report the broken pipe again."""
    try:
        target = sys.stdout.fileno()
    except (AttributeError, OSError, ValueError):  # stdout without a file descriptor: nothing more is written
        return EXIT_PIPE
    devnull = os.open(os.devnull, os.O_WRONLY)
    os.dup2(devnull, target)
    os.close(devnull)
    return EXIT_PIPE


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="hivex")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")

    p = sub.add_parser("validate", help="check scenario files; report every problem as path:line:col")
    p.add_argument("files", nargs="+", metavar="FILE")
    p.set_defaults(handler=cmd_validate)

    p = sub.add_parser("compile", help="show the resolved scenario(s); -o writes a lock file")
    p.add_argument("file", metavar="FILE")
    p.add_argument("-o", "--output", metavar="OUT", help="lock JSON (a directory of them for a sweep)")
    p.set_defaults(handler=cmd_compile)

    p = sub.add_parser("run", help="run episodes with a scripted or random policy; print returns per term")
    p.add_argument("file", metavar="FILE")
    _policy_args(p)
    p.add_argument("--episodes", type=positive, default=1, help="episodes to run (default 1)")
    p.add_argument("--split", choices=("train", "test"), default="train", help="seed split (default train)")
    p.set_defaults(handler=cmd_run)

    p = sub.add_parser("render", help="write an animated GIF of one episode")
    p.add_argument("file", metavar="FILE")
    p.add_argument("-o", "--output", required=True, metavar="GIF")
    _policy_args(p)
    p.add_argument("--steps", type=positive, default=600,
                   help="decisions to play (default 600; each is decision_period physics steps)")
    p.add_argument("--frame-step", "--every", type=positive, default=FRAME_STEP, dest="frame_step", metavar="N",
                   help=f"keep every N-th decision's frame (default {FRAME_STEP}; --every is its old name)")
    p.add_argument("--fps", type=positive, default=10, help="GIF frames per second (default 10)")
    p.add_argument("--checkpoint", type=Path, metavar="CHECKPOINT",
                   help="play the policy of a checkpoint `hivex train` wrote (of FILE's environment) instead of "
                        "--policy; its actions are sampled, as `hivex evaluate` samples them")
    p.set_defaults(handler=cmd_render)

    from .audit_command import add_command as add_audit_command

    add_audit_command(sub)

    p = sub.add_parser("schema", help="print the JSON Schema of the scenario language")
    p.set_defaults(handler=cmd_schema)

    p = sub.add_parser("docs", help="generate docs/ from the live code; --check fails if it is stale")
    p.add_argument("--dir", default="docs", type=Path, help="docs directory (default ./docs)")
    p.add_argument("--check", action="store_true", help="only check; exit 1 if docs/ is stale")
    p.set_defaults(handler=cmd_docs)

    p = sub.add_parser("preview", help="write the paper's sample figures (layouts, terrain, pollution) as PNG")
    p.add_argument("-o", "--output", required=True, type=Path, metavar="DIR")
    p.set_defaults(handler=cmd_preview)

    p = sub.add_parser("bench", help="measure steps per second of every environment on one core, against MPE")
    p.add_argument("--env", action="append", metavar="ID", help="only this environment (repeatable; default all)")
    p.add_argument("--seconds", type=float, default=3.0, help="timed seconds per run (default 3)")
    p.add_argument("--repeats", type=positive, default=3, help="runs per measurement; medians are reported (default 3)")
    p.add_argument("--batch", type=positive, default=256, help="worlds of the vector env (default 256)")
    p.add_argument("--no-reference", action="store_true", help="skip PettingZoo's MPE simple_spread_v3")
    p.add_argument("--json", action="store_true", help="print the report as JSON instead of a table")
    p.add_argument("-o", "--output", type=Path, metavar="JSON", help="also write the JSON report to this file")
    p.set_defaults(handler=cmd_bench)

    p = sub.add_parser("list", help="list the bundled scenarios")
    p.set_defaults(handler=cmd_list)

    p = sub.add_parser("vocab", help="list the quantities an environment's expressions may read, with their "
                                     "units, ranges and meanings")
    p.add_argument("scenario", metavar="ENV_OR_SCENARIO",
                   help="an environment (its main scenario's ranges) or a scenario file (its own ranges)")
    p.add_argument("--json", action="store_true", help="print the quantities as JSON")
    p.set_defaults(handler=cmd_vocab)

    from .train_commands import add_commands as add_train_commands

    add_train_commands(sub)
    from .replay_command import add_command as add_replay_command
    from .curves_command import add_command as add_curves_command

    add_replay_command(sub)
    add_curves_command(sub)
    parser.description = f"The `hivex` command: {' | '.join(sub.choices)}."  # every command, as added
    return parser


def _policy_args(p: argparse.ArgumentParser) -> None:
    p.add_argument("--policy", choices=("scripted", "random", "zeros"), default="scripted", help="default scripted")
    p.add_argument("--seed", type=seed, default=None, help="environment seed (default: the scenario's split seeds)")
    _point_arg(p)


def _point_arg(p: argparse.ArgumentParser) -> None:
    p.add_argument("--point", metavar="INDEX|KEY=VALUE,...", default=None,
                   help="one point of a sweep file: its index (as `hivex compile` numbers them) or its swept values")


def cmd_validate(args) -> int:
    from ..compiler import compile_all

    failed = 0
    for file in args.files:
        try:
            count = len(compile_all(file))
        except ScenarioError as exc:
            failed += 1
            for problem in exc.problems:
                print(problem, file=sys.stderr)
            continue
        print(f"ok  {file}  ({count} scenario{'s' if count != 1 else ''})")
    return EXIT_USAGE if failed else EXIT_OK


def cmd_compile(args) -> int:
    from ..compiler import compile_all
    from ..evaluation.report import describe_compiled, describe_sweep

    compiled = compile_all(args.file)
    locks = _lock_paths(len(compiled), Path(args.output)) if args.output else []
    print(describe_compiled(compiled[0]) if len(compiled) == 1 else describe_sweep(compiled))
    if locks:
        locks[0].parent.mkdir(parents=True, exist_ok=True)
    for scenario, path in zip(compiled, locks):
        path.write_text(json.dumps(scenario.to_lock(), indent=2) + "\n", encoding="utf-8")
        print(f"wrote {path}")
    return EXIT_OK


def _lock_paths(count: int, output: Path) -> list[Path]:
    """Where the locks of ``count`` scenarios go: the file ``output``, or for a sweep files in the directory
    ``output`` (created if need be); checked before anything is written."""
    if count == 1:
        if output.is_dir():
            raise HivexError(f"-o {output} is a directory; give the lock file's name (a directory is for a sweep)")
        if not output.parent.is_dir():
            raise HivexError(f"-o {output}: the directory {output.parent} does not exist")
        return [output]
    if output.exists() and not output.is_dir():
        raise HivexError(f"-o {output} is a file; a sweep of {count} scenarios writes one lock per point "
                         "into a directory")
    names = [output / f"{i:04d}.lock.json" for i in range(count)]
    stale = sorted(set(output.glob("*.lock.json")) - set(names)) if output.is_dir() else []
    if stale:
        raise HivexError(f"-o {output} holds lock files this sweep would not overwrite ({stale[0].name}, ...); "
                         "they would be mixed with its points: choose an empty directory")
    return names


def cmd_run(args) -> int:
    from .points import one_point
    from ..evaluation.report import run_episodes

    compiled = one_point(args.file, args.point)
    print(run_episodes(compiled, args.policy, args.episodes, args.split, args.seed))
    return EXIT_OK


def cmd_render(args) -> int:
    from .points import one_point
    from ..evaluation.progress import bar
    from ..sim.render.gif import save_gif
    from ..evaluation.report import episode_frames

    if Path(args.output).suffix.lower() != ".gif":
        raise HivexError(f"-o {args.output}: expected a file name ending in .gif (hivex render writes an animated GIF)")
    if args.frame_step > args.steps:
        raise HivexError(f"--frame-step {args.frame_step} is more than --steps {args.steps}: the GIF would hold the "
                         f"first frame only; give a step of at most {args.steps}")
    compiled = one_point(args.file, args.point)
    policy = args.policy
    if args.checkpoint is not None:
        from .train_commands import require_torch

        require_torch()
        from ..train.evaluate import checkpoint_policies

        policy = checkpoint_policies(args.checkpoint)(compiled)
    with bar(args.steps, f"render {compiled.name}", unit="decision") as shown:
        frames = episode_frames(compiled, policy, args.steps, args.frame_step, args.seed, progress=shown)
        count = save_gif(frames, args.output, fps=args.fps)
    print(f"wrote {args.output} ({count} frames)")
    return EXIT_OK


def cmd_schema(args) -> int:
    from ..docsgen.schema import schema_text

    sys.stdout.write(schema_text())
    return EXIT_OK


def cmd_docs(args) -> int:
    from ..docsgen import stale_docs, write_docs

    if args.check and not args.dir.is_dir():
        print(f"hivex: no {args.dir}/ here to check: run `hivex docs --check` in a checkout of hivex-dsl (docs/ is "
              "generated there), or give --dir", file=sys.stderr)
        return EXIT_USAGE
    if args.check:
        stale = stale_docs(args.dir)
        for path in stale:
            print(f"stale: {args.dir / path}", file=sys.stderr)
        if stale:
            print("docs are stale: run `hivex docs` and commit the result", file=sys.stderr)
            return EXIT_FAIL
        print(f"{args.dir} is up to date")
        return EXIT_OK
    changed = write_docs(args.dir)
    print(f"{args.dir}: {len(changed)} file(s) written or removed")
    return EXIT_OK


def cmd_preview(args) -> int:
    from ..docsgen.figures import FIGURES, preview_figure
    from ..evaluation.progress import bar, echo
    from ..sim.render.gif import save_png

    args.output.mkdir(parents=True, exist_ok=True)
    with bar(len(FIGURES), "preview", unit="figure") as shown:
        for rel in FIGURES:
            caption, image = preview_figure(rel)
            path = args.output / Path(rel).name
            save_png(image, path)
            shown.update(1)
            echo(f"wrote {path}: {caption}")
    return EXIT_OK


def cmd_bench(args) -> int:
    from ..evaluation import bench, bench_expressions
    from ..compiler import registry

    available = list(registry.environments())
    unknown = [e for e in args.env or [] if e not in available]
    if unknown:
        raise HivexError(f"unknown environment {unknown[0]!r}; expected one of: {', '.join(available)}")
    if not args.seconds > 0:
        raise HivexError(f"--seconds must be positive, got {args.seconds}")
    reference = not args.no_reference
    if reference and not bench.reference_available():
        raise HivexError("the reference needs the mpe2 package: pip install 'hivex-dsl[bench]' (or pass --no-reference)")
    report = bench.run_benchmarks(args.env or available, args.seconds, args.repeats, args.batch, reference,
                                  progress=lambda what: print(f"measuring {what} ...", file=sys.stderr))
    if bench_expressions.ENVIRONMENT in (args.env or available):
        print("measuring expression terms ...", file=sys.stderr)
        report["expression_terms"] = bench_expressions.run(args.seconds, args.repeats, bench.ONE_CORE)
    text = json.dumps(report, indent=2) + "\n"
    if args.output:
        args.output.parent.mkdir(parents=True, exist_ok=True)
        args.output.write_text(text, encoding="utf-8")
    table = bench.format_table(report)
    if report.get("expression_terms"):
        table += "\n\n" + bench_expressions.format_table(report["expression_terms"])
    sys.stdout.write(text if args.json else table + "\n")
    return EXIT_OK


def cmd_list(args) -> int:
    from ..compiler import registry

    for name in sorted(f"{env_id}/{path.name}" for env_id, entry in registry.environments().items()
                       for path in entry.scenario_files()):
        print(name)
    return EXIT_OK


def cmd_vocab(args) -> int:
    """Every quantity of the scenario's vocabulary: ranges follow its params, so a scenario file gives its own."""
    from ..compiler import registry
    from ..compiler import compile
    from ..sim.reward.vocabulary import vocabulary_of

    environments = registry.environments()
    if args.scenario in environments:
        source = f"{args.scenario}/main"
    elif not Path(args.scenario).exists() and "/" not in args.scenario and not args.scenario.endswith(".yaml"):
        raise HivexError(f"no environment or scenario file {args.scenario!r}"
                         f"{did_you_mean(args.scenario, environments)}; environments: {', '.join(environments)}")
    else:
        source = args.scenario
    compiled = compile(source)
    quantities = vocabulary_of(compiled.environment).quantities(compiled)
    rows = [{"name": q.name, "per": q.per, "kind": q.kind, "unit": q.unit, "low": q.low, "high": q.high,
             "meaning": q.description} for q in quantities.values()]
    if args.json:
        print(json.dumps(rows, indent=2))
        return EXIT_OK
    print(f"{compiled.environment} ({compiled.name}): {len(rows)} quantities; prev(x) and delta(x) read them one "
          "physics step before")
    for row in rows:
        span = "true/false" if row["kind"] == "bool" else f"[{row['low']:g}, {row['high']:g}] {row['unit']}"
        print(f"  {row['name']:34} per {row['per']:5}  {span:28} {row['meaning']}")
    for name, why in vocabulary_of(compiled.environment).not_modelled.items():
        print(f"  {name:34} not modelled: {why}")
    return EXIT_OK
