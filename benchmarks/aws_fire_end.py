"""How much of the island Aerial Wildfire Suppression's fire has burnt when it goes out, under a trained policy.

    python benchmarks/aws_fire_end.py [--grid runs/aws-grid-f3d] [--levels 6,10] [--episodes 8]
                                      [--policy trained|random] [--set fire_cadence=interval ...]

Plays test-seed episodes of the main task, one world at a time (``--policy trained``: the checkpoint of ``--grid``'s
run of that level, played on the params set), and for each episode logs whether the fire went out in it and, the
step before it did (or at the episode's end), the share of the island's trees burnt, wet and still standing. A world
goes on across its planes' episodes (the release's episodes_continue), so an episode may begin with the fire
already burning. Per level it prints each episode and, for the episodes whose fire went out and for the others, the
range of the burnt and standing shares: whether the fire went out because water stopped it or because it had burnt
what it could reach (the reward table's note 'Fire Out, the crashes and the planes still up', issue 52).
"""

from __future__ import annotations

import argparse
import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np

import hivex_dsl
from hivex_dsl.base.errors import HivexError
from hivex_dsl.evaluation.policies import make_policy
from hivex_dsl.runtime.batched import BatchedEnv
from hivex_dsl.sim.fire.engine import TreeState
from hivex_dsl.train.config import parse_assignments

ENVIRONMENT = "aerial_wildfire_suppression"


@dataclass(frozen=True)
class FireEnd:
    """One episode: the step its fire went out (-1: it did not) and the island's trees at that step's start
    (or at the episode's end), as shares of all its trees."""

    out_step: int
    burnt: float
    wet: float
    standing: float
    burning: float

    @property
    def went_out(self) -> bool:
        return self.out_step >= 0


def shares(trees: np.ndarray) -> tuple[float, float, float, float]:
    """(burnt, wet, standing, burning) shares of one world's trees (any shape of tree states)."""
    counts = np.bincount(trees.ravel(), minlength=len(TreeState))
    total = counts[1:].sum()
    return tuple(float(counts[state] / total) for state in (TreeState.BURNT, TreeState.WET, TreeState.EXISTING,
                                                              TreeState.BURNING))


def policy_of(name: str, compiled, core: BatchedEnv, level: int, grid: Path | None):
    if name == "random":
        return make_policy("random", compiled, core.sim.action_space, core.shape, seed=level)
    from hivex_dsl.train.evaluate import checkpoint_policies, level_checkpoint

    if grid is None:
        raise HivexError("--policy trained plays the checkpoints of a `hivex train` level sweep: name it with --grid")
    return checkpoint_policies(level_checkpoint(grid, level))(compiled)


def play(level: int, episodes: int, params: dict, policy: str = "trained", grid: Path | None = None,
         episode_length: int = 3000) -> list[FireEnd]:
    """``episodes`` test-seed episodes of one world at ``level`` under ``params``."""
    compiled = hivex_dsl.compile({"hivex": 1, "environment": ENVIRONMENT, "task": "main", "terrain_level": level,
                                  "episode_length": episode_length, "params": params})
    core = BatchedEnv(compiled, batch=1, split="test")
    act = policy_of(policy, compiled, core, level, grid)
    ends = []
    for episode in range(episodes):
        observations = core.reset() if episode == 0 else core.reset_worlds(np.ones(1, bool))
        out, step, before = -1, 0, shares(core.state.fire.trees[0])
        while core.alive.any() and core.clock.max() < compiled.episode_length:
            before = shares(core.state.fire.trees[0])  # the world resets once its fire is out: read it first
            observations = core.step(act(observations)).observations
            step += 1
            if core.state.fire_went_out[0]:
                out = step
                break
        ends.append(FireEnd(out, *before))
    return ends


def _range(values: list[float]) -> str:
    return f"{min(values):.0%}-{max(values):.0%}" if values else "-"


def report(level: int, ends: list[FireEnd]) -> list[str]:
    lines = [f"L{level} episode {i}: " + (f"out at step {e.out_step}" if e.went_out else "not out") +
             f", burnt {e.burnt:.2f}, wet {e.wet:.2f}, standing {e.standing:.2f}" for i, e in enumerate(ends)]
    out = [e for e in ends if e.went_out]
    rest = [e for e in ends if not e.went_out]
    lines.append(f"L{level}: out in {len(out)} of {len(ends)} episodes, with {_range([e.burnt for e in out])} "
                 f"burnt and {_range([e.standing for e in out])} standing; the others end with "
                 f"{_range([e.burnt for e in rest])} burnt and {_range([e.standing for e in rest])} standing")
    return lines


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--grid", type=Path, default=Path("runs/aws-grid-f3d"))
    parser.add_argument("--levels", default="6,10")
    parser.add_argument("--episodes", type=int, default=8)
    parser.add_argument("--policy", choices=("trained", "random"), default="trained")
    parser.add_argument("--set", action="append", default=[], metavar="KEY=VALUE")
    args = parser.parse_args(argv)
    try:
        params = dict(parse_assignments(args.set).values)
        for level in (int(level) for level in args.levels.split(",")):
            print("\n".join(report(level, play(level, args.episodes, params, args.policy, args.grid))), flush=True)
    except (HivexError, ValueError) as error:
        print(f"aws_fire_end: {error}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
