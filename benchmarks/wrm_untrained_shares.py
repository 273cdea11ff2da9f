"""Wildfire Resource Management: what an untrained policy earns for keeping and for giving, here and in the original.

    python benchmarks/wrm_untrained_shares.py [--inits 8] [--worlds 4] [--decisions 400] [--levels 1,5,10]

The first training point of every original cell is (mostly) its untrained policy: one network (every config that
ran has env_settings.seed 5000) on the same fires in all three tasks, whose first points agree. Two ratios of that
point read how its towers shared their resources, whatever the fire: Reward for Moving Resources to Self over
Individual Performance (keeping) and Reward for Moving Resources to Neighbours over Individual Performance (giving),
each paid statistic divided by its task's weight (Keep All pays keeping x10, Distribute All giving x10). Beside them,
this toolkit's untrained policies: networks initialised as `hivex train` initialises them (ML-Agents' layers, one per
--inits seed, each on training worlds of its own), each playing its first --decisions decisions, the episodes that end
pooled as ML-Agents pools a summary point. The reward table's note 'The untrained towers' records what it printed.
"""

from __future__ import annotations

import argparse
import sys

import numpy as np

import hivex_dsl
from hivex_dsl.base.errors import HivexError
from hivex_dsl.evaluation.original.curves import original_curves

ENVIRONMENT = "wildfire_resource_management"
SELF, NEIGHBOURS = "Reward for Moving Resources to Self", "Reward for Moving Resources to Neighbours"
INDIVIDUAL, COUNT = "Individual Performance", "Individual Resource Count"
TASK_WEIGHTS = {0: (1.0, 1.0), 1: (10.0, 1.0), 2: (1.0, 10.0)}  # (keeping, giving): the reward table's matrix


def shares(keep: float, give: float, individual: float, task: int = 0) -> tuple[float, float]:
    """(keeping, giving) over Individual Performance from one point's paid statistics, each divided by the
    ``task``'s weight of its term."""
    keep_weight, give_weight = TASK_WEIGHTS[task]
    return keep / keep_weight / individual, give / give_weight / individual


def original_first_point(task: int, level: int) -> tuple[float, float, float]:
    """(keeping, giving, Individual Resource Count) at the first training point of the original's cell (the mean of
    its three runs)."""
    cell = original_curves(ENVIRONMENT, task, level)
    if cell is None:
        raise HivexError(f"no original cell for task {task} at level {level}")

    def first(panel: str) -> float:
        curve = cell.panel(panel).training
        return float(curve.mean_at(curve.band_steps[0]))

    return (*shares(first(SELF), first(NEIGHBOURS), first(INDIVIDUAL), task), first(COUNT))


def untrained_shares(level: int, seed: int, worlds: int = 4, decisions: int = 400) -> tuple[float, float]:
    """(keeping, giving) of this toolkit's untrained policy of training ``seed`` (its network as `hivex train` builds
    it, sampling its actions) at ``level``, on training worlds 5000 + ``seed``: ``worlds`` worlds of the main task
    play ``decisions`` decisions, and the episodes that end are pooled."""
    import torch

    from hivex_dsl.train.config import make_config
    from hivex_dsl.train.logs import episode_summaries
    from hivex_dsl.train.networks import ActorCritic, to_tensors
    from hivex_dsl.train.ppo import make_env

    compiled = hivex_dsl.compile({"hivex": 1, "environment": ENVIRONMENT, "terrain_level": level})
    cfg = make_config(ENVIRONMENT, {"seed": seed})
    torch.manual_seed(seed)  # as ppo.train seeds torch before it builds the network
    env, obs, _ = make_env(compiled, worlds, "train", cfg.ended_agents, 5000 + seed)
    agent = ActorCritic(env.single_observation_space, env.single_action_space, cfg)
    ended: dict[str, list[np.ndarray]] = {SELF: [], NEIGHBOURS: [], INDIVIDUAL: []}
    for _ in range(decisions):
        with torch.no_grad():
            cont, disc, _ = agent.act(to_tensors(obs))
        obs, _, _, _, infos = env.step(agent.layout.to_env(cont, disc))
        summary = episode_summaries(infos)
        if summary is not None:
            for name, sums in ended.items():
                sums.append(summary["statistics"][name])
    means = {name: np.concatenate(sums).mean() if sums else np.nan for name, sums in ended.items()}
    if not np.isfinite(means[INDIVIDUAL]) or means[INDIVIDUAL] <= 0:
        raise HivexError(f"no episode with a fire near a tower ended within {decisions} decisions at level {level}")
    return shares(means[SELF], means[NEIGHBOURS], means[INDIVIDUAL])


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--inits", type=int, default=8, help="untrained networks a level (training seeds 0..N-1)")
    parser.add_argument("--worlds", type=int, default=4, help="worlds each network plays (default 4)")
    parser.add_argument("--decisions", type=int, default=400, help="decisions each plays (default 400)")
    parser.add_argument("--levels", default="1,5,10", help="terrain levels, comma-separated")
    args = parser.parse_args(argv)
    try:
        if args.inits < 1 or args.worlds < 1 or args.decisions < 1:
            raise HivexError("--inits, --worlds and --decisions must be at least 1")
        levels = [int(level) for level in args.levels.split(",")]
        print("level  original keeping (tasks 0-2)  giving (tasks 0-2)  count  |  ours keeping  giving (min-max)")
        for level in levels:
            theirs = np.array([original_first_point(task, level) for task in TASK_WEIGHTS])
            ours = np.array([untrained_shares(level, seed, args.worlds, args.decisions) for seed in range(args.inits)])
            print(f"{level:5d}  {' '.join(f'{v:.3f}' for v in theirs[:, 0]):>28}  "
                  f"{' '.join(f'{v:.2f}' for v in theirs[:, 1]):>18}  {theirs[0, 2]:.2f}  |  "
                  f"{ours[:, 0].min():.3f}-{ours[:, 0].max():.3f}  {ours[:, 1].min():.2f}-{ours[:, 1].max():.2f}",
                  flush=True)
    except (HivexError, ValueError) as error:
        print(f"error: {error}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
