"""`hivex curves`: a run's learning curves beside the original's (hivex_dsl/evaluation/original/compare.py)."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import TYPE_CHECKING

from .argtypes import positive

if TYPE_CHECKING:
    from ..evaluation.original.runs import Run


def add_command(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("curves", help="a run's learning curves against the original's (mean and band of its 3 runs) "
                                      "at 10, 25, 50 and 100%% of the original's budget, and pooled over its last tenth; "
                                      "-o draws them")
    p.add_argument("run", type=Path, metavar="RUN",
                   help="a run directory of `hivex train`, or a baseline record (benchmarks/baselines/<env>.json)")
    p.add_argument("scenario", nargs="?", metavar="SCENARIO",
                   help="compare with the original's cell of this scenario (default: the cell the run trained)")
    p.add_argument("--with", dest="more", action="append", type=Path, default=[], metavar="RUN",
                   help="another training seed's run of the same cell (repeatable): each measured too, then every "
                        "seed and their mean")
    p.add_argument("--point", metavar="SELECTOR", help="with a sweep SCENARIO: its point, as `hivex evaluate` takes it")
    p.add_argument("--page-task", type=int, metavar="N",
                   help="the original page's own task index, where it differs from the paper's (Drone-Based "
                        "Reforestation's tasks past 1)")
    p.add_argument("-o", "--output", type=Path, metavar="PNG",
                   help="draw every panel both log, ours over the original's mean and band (needs matplotlib)")
    p.add_argument("--columns", type=positive, default=3, help="panels a row in the figure (default 3)")
    p.set_defaults(handler=cmd_curves)


def cmd_curves(args: argparse.Namespace) -> int:
    from ..evaluation.original import compare
    from ..evaluation.original.runs import read_run
    from ..evaluation.original.seeds import among_words, measure_seeds, seeds_table, swings_words
    from ..evaluation.original.tail import tail_seeds, tail_table

    run = read_run(args.run)
    others = list(run.others)
    for path in args.more:
        more = read_run(path)
        if (more.environment, more.task_index, more.level) != (run.environment, run.task_index, run.level):
            raise compare.CompareError(f"{path} trained {_cell(more)}, {args.run} {_cell(run)}: --with takes other "
                                       "seeds of the same cell")
        others += [more.curve, *more.others]
    environment, task_index, level = run.environment, run.task_index, run.level
    if args.scenario is not None:
        from .points import one_point

        compiled = one_point(args.scenario, args.point)
        environment, level = compiled.environment, compiled.level
        task_index = compare.paper_task_index(environment, compiled.task_index)
        if environment != run.environment:
            raise compare.CompareError(f"{args.run} trained {run.environment}, {args.scenario} is of {environment}: "
                                       "give a scenario of the run's environment")
    cell = compare.original_cell(environment, task_index, level, args.page_task)
    budget = max(p.training.last_step for p in cell.panels.values() if p.training is not None)
    sys.stdout.write(f"{run.curve.label} against the original's {cell.file} ({cell.title}); the original trained "
                     f"{budget:,} agent-steps, this run {run.curve.last_step:,}\n\n")
    sys.stdout.write(compare.table(compare.measure(run.curve, cell)) + "\n")
    for other in others:
        sys.stdout.write(f"\n{other.label}:\n\n" + compare.table(compare.measure(other, cell)) + "\n")
    seeds = [run.curve, *others]
    labels = [s.label.removeprefix("this toolkit, ") for s in seeds]
    if others:
        rows = measure_seeds(seeds, cell)
        sys.stdout.write("\nevery seed and their mean:\n\n" + seeds_table(rows, labels) + "\n\n"
                         + among_words(rows, len(seeds)) + "\n")
        swings = swings_words(seeds)
        if swings:
            sys.stdout.write(swings + "\n")
    ends = tail_seeds(seeds, cell)
    sys.stdout.write(f"\npooled over the last tenth of the original's budget (from {ends[0].start:,} agent-steps), "
                     "in parentheses over the original's:\n\n" + tail_table(ends, labels) + "\n")
    if args.output is not None:
        from ..evaluation.original.figure import plot

        path = plot(run.curve, cell, args.output, columns=args.columns, others=tuple(others))
        sys.stdout.write(f"\nwrote {path}\n")
    return 0


def _cell(run: "Run") -> str:
    """A run's cell in words: environment, the paper's task index and level."""
    return f"{run.environment} task {run.task_index}" + ("" if run.level is None else f" level {run.level}")
