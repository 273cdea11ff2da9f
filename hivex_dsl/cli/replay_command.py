"""`hivex replay`: its arguments and its command; the work is in :mod:`hivex_dsl.replay`."""

from __future__ import annotations

import argparse
from pathlib import Path

from typing import Optional

from ..base.errors import HivexError
from .argtypes import positive, seed
from .exits import EXIT_OK
from .points import one_point


def add_command(sub: argparse._SubParsersAction) -> None:
    """The `replay` subcommand's parser."""
    from ..replay.page import MAX_MB
    from ..replay.record import DEFAULT_SPLIT

    p = sub.add_parser("replay", help="write one self-contained HTML page that plays an episode back with every "
                                      "agent's reward term by term")
    p.add_argument("target", metavar="SCENARIO|CHECKPOINT|RUN_DIR",
                   help="a scenario file (or bundled name), a checkpoint, or a `hivex train` run directory (its "
                        "checkpoint on the scenario it trained on)")
    p.add_argument("-o", "--output", type=Path, default=Path("episode.html"), metavar="HTML",
                   help="the page to write (default episode.html)")
    p.add_argument("--policy", choices=("scripted", "random", "zeros"), default="scripted",
                   help="the policy on a scenario without --checkpoint (default scripted)")
    p.add_argument("--checkpoint", type=Path, metavar="CHECKPOINT",
                   help="play the policy of a checkpoint `hivex train` wrote for this scenario (its actions sampled, "
                        "as `hivex evaluate` samples them)")
    p.add_argument("--point", metavar="INDEX|KEY=VALUE,...", default=None,
                   help="one point of a sweep file: its index (as `hivex compile` numbers them) or its swept values")
    p.add_argument("--seed", type=seed, default=None, help="environment seed (default: the split's first seed)")
    p.add_argument("--split", choices=("train", "test"), default=DEFAULT_SPLIT,
                   help=f"seed split (default {DEFAULT_SPLIT})")
    p.add_argument("--steps", type=positive, default=None, help="decisions to play at most (default: the episode)")
    p.add_argument("--frame-step", type=positive, default=None, metavar="N",
                   help="keep every N-th decision's frame (default 10, more for a long episode: about 100 frames)")
    p.add_argument("--max-mb", type=float, default=MAX_MB, metavar="MB",
                   help=f"refuse a page larger than this (default {MAX_MB:g} MB)")
    p.add_argument("--compare", metavar="SCENARIO|CHECKPOINT|RUN_DIR",
                   help="a second episode on the same seed, on one timeline: another scenario (reward table) of the "
                        "environment for the same policy, or another checkpoint on this scenario")
    p.add_argument("--compare-point", metavar="INDEX|KEY=VALUE,...", default=None,
                   help="the point of a sweep file given to --compare")
    p.add_argument("--trace", type=Path, metavar="JSON",
                   help="also write the recorded data as JSON (format hivex-replay-trace/1, see docs/replay.md)")
    p.set_defaults(handler=cmd_replay)


def cmd_replay(args) -> int:
    from ..evaluation.progress import bar
    from ..replay import replay

    _check_outputs(args)
    if not args.max_mb > 0:
        raise HivexError(f"--max-mb must be positive, got {args.max_mb:g}")
    players = [main_player(args.target, args.point, args.policy, args.checkpoint)]
    if args.compare:
        players.append(compare_player(args.compare, args.compare_point, players[0]))
    elif args.compare_point is not None:
        raise HivexError("--compare-point picks a point of the --compare scenario: give --compare too")
    decisions = sum(min(p.compiled.episode_decisions, args.steps or p.compiled.episode_decisions) for p in players)
    with bar(decisions, f"replay {players[0].compiled.name}", unit="decision") as shown:
        written = replay(players, args.output, args.frame_step, args.seed, args.split, args.steps, args.max_mb,
                         args.trace, progress=shown.update)
    print(f"wrote {written['path']} ({written['bytes'] / 1e6:.1f} MB, {written['decisions']} decisions, "
          f"{written['frames']} frames, one every {written['frame_step']} decisions)")
    if args.trace:
        print(f"wrote {args.trace}")
    return EXIT_OK


def _check_outputs(args) -> None:
    """The page (and the trace) go to files in existing directories, checked before an episode is played."""
    for flag, path, suffixes in (("-o", args.output, (".html", ".htm")), ("--trace", args.trace, (".json",))):
        if path is None:
            continue
        if path.suffix.lower() not in suffixes:
            raise HivexError(f"{flag} {path}: expected a file name ending in {' or '.join(suffixes)}")
        if not path.parent.is_dir():
            raise HivexError(f"{flag} {path}: the directory {path.parent} does not exist")


def main_player(target: str, point: Optional[str], policy: str, checkpoint: Optional[Path]):
    """The episode of `hivex replay TARGET`: a checkpoint (or run directory) on the scenario it trained on, or the
    point ``point`` of a scenario played by ``policy`` or by ``checkpoint``."""
    from ..replay.sources import Player, checkpoint_path, checkpoint_player

    own = checkpoint_path(target)
    if own is not None:
        if checkpoint is not None:
            raise HivexError(f"{target} is a checkpoint (or a run directory) already: give --checkpoint with a "
                             "scenario file, or leave it out")
        if point is not None:
            raise HivexError(f"--point picks a point of a sweep file; the checkpoint {own} plays the one scenario it "
                             "trained on")
        return checkpoint_player(_with_torch(own))
    compiled = one_point(target, point)
    if checkpoint is not None:
        return checkpoint_player(_with_torch(checkpoint_path(checkpoint) or checkpoint), compiled)
    return Player(compiled, policy, {"kind": policy})


def compare_player(other: str, point: Optional[str], first):
    """The second episode of ``--compare OTHER``: another checkpoint (or run directory) on the first scenario, or the
    first policy on another scenario of the same environment and agent count."""
    from ..replay.sources import checkpoint_path, checkpoint_player, same_policy

    path = checkpoint_path(other)
    if path is not None:
        return checkpoint_player(_with_torch(path), first.compiled, own_scenario=False)
    return same_policy(first, one_point(other, point))


def _with_torch(path: Path) -> Path:
    """``path``, once torch and the train extra are known to be there (or a sentence saying what to install)."""
    from .train_commands import require_torch

    require_torch()
    return path
