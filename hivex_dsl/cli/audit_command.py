"""`hivex audit`: its arguments and its command; the work is in :mod:`hivex_dsl.evaluation.audit` (and, for ``--suite``,
:mod:`hivex_dsl.evaluation.fidelity`), a trained policy's in :mod:`hivex_dsl.train.evaluate`."""

from __future__ import annotations

import argparse
import json
import sys
from contextlib import nullcontext
from pathlib import Path

from ..base.errors import HivexError
from .argtypes import positive
from .exits import EXIT_FAIL, EXIT_OK, EXIT_USAGE

FILE_EPISODES = 2  # a scenario FILE's audit: a quick look; the suite's verdicts take more (fidelity.SUITE_EPISODES)


def add_command(sub: argparse._SubParsersAction) -> None:
    """The `audit` subcommand's parser."""
    p = sub.add_parser("audit", help="property-test a scenario's reward terms with all-zeros, random and scripted "
                                     "policies (and a trained one); compare with the published results")
    p.add_argument("file", nargs="?", help="scenario file (every point of a sweep is audited)")
    p.add_argument("--episodes", type=positive, help=f"test episodes per policy (default {FILE_EPISODES}; with --suite, "
                                                     "the suite's standard for a stable verdict)")
    p.add_argument("--checkpoint", type=Path, metavar="CHECKPOINT",
                   help="also audit the policy of a checkpoint `hivex train` wrote (of the scenario's environment; "
                        "needs the train extra)")
    p.add_argument("--json", action="store_true", help="print the audit as JSON")
    p.add_argument("--strict", action="store_true", help="exit 1 when a flag is raised")
    p.add_argument("--suite", action="store_true", help="audit every published cell (every task of every "
                                                        "environment at every published level or pattern, and each "
                                                        "task's first level) instead of FILE: the fidelity page's "
                                                        "numbers")
    p.add_argument("-o", "--output", type=Path, help="with --suite: write the report as JSON to this file")
    p.add_argument("--only", action="append", metavar="ENV", choices=_environment_ids(),
                   help="with --suite: audit only this environment's cells (repeatable); with -o, an existing "
                        "report keeps every other environment's rows, and these are measured at its episode count "
                        "unless --episodes says another")
    p.set_defaults(handler=cmd_audit)


def cmd_audit(args) -> int:
    from ..evaluation.audit import describe

    if args.suite == bool(args.file):
        print("hivex audit: give a scenario FILE or --suite (not both)", file=sys.stderr)
        return EXIT_USAGE
    if args.only and not args.suite:
        raise HivexError("--only picks environments of the --suite; a scenario FILE names its own")
    if args.suite and args.checkpoint:
        raise HivexError("--checkpoint audits a trained policy on a scenario FILE of its environment, not --suite")
    audits = _suite(args) if args.suite else _scenario(args)
    print(json.dumps(audits, indent=2) if args.json else "\n\n".join(describe(a) for a in audits))
    flagged = any(a["flags"] for a in audits)
    return EXIT_FAIL if args.strict and flagged else EXIT_OK


def _suite(args) -> list[dict]:
    """Every suite scenario's audit (written to --output if given)."""
    from ..evaluation.fidelity import SUITE_EPISODES, load_suite, measure_suite, remeasure_suite, write_suite

    stored = load_suite(args.output) if args.output and args.only else None
    if stored is not None:
        report = remeasure_suite(stored, args.only, quiet=args.json, episodes=args.episodes)
        audited = [row for row in report["scenarios"] if row["environment"] in args.only]
    else:
        report = measure_suite(args.episodes or SUITE_EPISODES, args.only, quiet=args.json)
        audited = report["scenarios"]
    if args.output:
        write_suite(report, args.output)
        print(f"wrote {args.output}", file=sys.stderr)
    return audited


def _environment_ids() -> list[str]:
    from ..compiler import registry

    return list(registry.environments())


def _scenario(args) -> list[dict]:
    """The audits of FILE's points, with the checkpoint's policy beside the others if one is given."""
    from ..evaluation.audit import audit_all
    from ..compiler import compile_all

    compiled = compile_all(args.file)
    trained, threads = None, nullcontext()
    if args.checkpoint:
        from .train_commands import require_torch

        require_torch()
        from ..train.evaluate import checkpoint_policies, limited_threads

        trained, threads = checkpoint_policies(args.checkpoint), limited_threads(1)
    with threads:  # one world's few agents are batches too small to share among torch's threads
        audits = [a.as_dict() for a in audit_all(compiled, args.episodes or FILE_EPISODES, quiet=args.json,
                                                    trained=trained)]
    if args.checkpoint:
        for audit in audits:
            audit["checkpoint"] = str(args.checkpoint)
    return audits
