"""Wildfire Resource Management: what untrained and trained towers earn keeping and giving, here and in the original.

    python benchmarks/wrm_untrained_shares.py [--inits 8] [--worlds 4] [--decisions 400] [--levels 1,5,10]
                                              [--as-printed]   # the terms as this project read them until session 74
    python benchmarks/wrm_untrained_shares.py --readings [--levels 1,5,10]   # uniform random play, other readings
    python benchmarks/wrm_untrained_shares.py --model   # the nine towers' allocations alone, other mechanics
    python benchmarks/wrm_untrained_shares.py --trained   # the last tenth of training, the original's and the grid's
    python benchmarks/wrm_untrained_shares.py --holdings RUN/checkpoint.pt [...]   # what each trained tower holds

The first training point of every original cell is (mostly) its untrained policy: one network (every config that
ran has env_settings.seed 5000) on the same fires in all three tasks, whose first points agree. Two ratios of that
point read how its towers shared their resources, whatever the fire: Reward for Moving Resources to Self over
Individual Performance (keeping) and Reward for Moving Resources to Neighbours over Individual Performance (giving),
each paid statistic divided by its task's weight (Keep All pays keeping x10, Distribute All giving x10). Beside them,
this toolkit's untrained policies: networks initialised as `hivex train` initialises them (ML-Agents' layers, one per
--inits seed, each on training worlds of its own), each playing its first --decisions decisions, the episodes that end
pooled as ML-Agents pools a summary point; with --as-printed, under the terms' readings before session 74
(own_term_weight kept_squared, neighbour_term_weight given_total). With --readings, uniform random play at each level
read seven ways: keeping as P r_self^2 (``self_squared``), as P times the share held times r_self (``self_held``),
as P times the share allocated times r_self (``self_allocated``) or as P r_self (``self_kept``), giving as the
neighbours' summed P times the share given (``given_total``), each neighbour's P times the share given it
(``given_each``) or each neighbour's P times the share it holds times the share given it (``given_each_held``).
With --model, the allocations alone (no fire: P alike at every tower and step, so keeping is E[r_self^2] / E[held]
and giving 3 E[given] / E[held], the readings before session 74) under uniform random play, as the environment moves
its tenths and with a tower's 'Sub from Self' taking back what its neighbours gave it, first or in proportion to what
it holds, each from nothing or from nine tenths on the tower itself. With --trained, keeping over the last tenth of
training, per task and level: the original's runs (their mean and band) and every seed of the committed grid's point. With
--holdings, what each of the nine towers keeps and holds under trained checkpoints (6 test episodes). The reward
table's notes 'The untrained towers' and 'The terms read what the towers hold' record what it printed.
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
AS_PRINTED = {"own_term_weight": "kept_squared", "neighbour_term_weight": "given_total"}  # the readings before


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


def original_trained_keeping(task: int, level: int) -> tuple[float, float, float, float]:
    """Over the last tenth of the original's training at ``task`` and ``level``: (keeping of the runs' mean, of the
    band's lower and upper edges, giving of the mean). The band is seaborn's bootstrap interval over three runs,
    whose edges at a point are (nearly) its lowest and highest run; each edge of Reward for Moving Resources to Self
    is read over the runs' mean Individual Performance."""
    cell = original_curves(ENVIRONMENT, task, level)
    if cell is None:
        raise HivexError(f"no original cell for task {task} at level {level}")
    kept = cell.panel(SELF).training
    steps = kept.band_steps[kept.band_steps >= 0.9 * kept.last_step]

    def mean(panel: str) -> float:
        return float(cell.panel(panel).training.mean_at(steps).mean())

    at = np.isin(kept.band_steps, steps)
    lower, upper = (float(edge[at].mean()) for edge in (kept.lower, kept.upper))
    keep_weight, give_weight = TASK_WEIGHTS[task]
    individual = mean(INDIVIDUAL)
    keeping, giving = shares(mean(SELF), mean(NEIGHBOURS), individual, task)
    return keeping, lower / keep_weight / individual, upper / keep_weight / individual, giving


def recorded_trained_keeping(panels: dict[str, list[float]], task: int) -> float:
    """Keeping over the last tenth of a recorded training curve (a baseline's ``curve_panels``): the paid statistic's
    sum over its points over Individual Performance's, as :func:`original_trained_keeping` reads the original's."""
    individual, kept = (np.asarray(panels[name], dtype=float) for name in (INDIVIDUAL, SELF))  # None: no episode
    last = slice(len(individual) - max(1, len(individual) // 10), None)
    return shares(float(np.nansum(kept[last])), 0.0, float(np.nansum(individual[last])), task)[0]


def tower_holdings(checkpoint: str, episodes: int = 6) -> tuple[np.ndarray, np.ndarray]:
    """(kept, held), each (9,): the shares a trained policy's towers keep for themselves and hold (what every agent
    gives them, their own included), averaged over its decisions in its scenario's first ``episodes`` test episodes
    (actions sampled, torch seeded 0 as `hivex evaluate` seeds it). Towers are numbered 3 x row + column, the
    centre 4."""
    import torch

    from hivex_dsl.envs.wildfire_resource_management.resources import TENTHS
    from hivex_dsl.evaluation.policies import decide
    from hivex_dsl.runtime.batched import BatchedEnv
    from hivex_dsl.train.checkpoint import load_checkpoint, policy_for
    from hivex_dsl.train.evaluate import limited_threads, network_policy

    loaded = load_checkpoint(checkpoint)
    compiled = loaded["compiled"]
    if compiled.environment != ENVIRONMENT:
        raise HivexError(f"{checkpoint} trained {compiled.environment}, not {ENVIRONMENT}: it has no towers to read")
    act = network_policy(policy_for(loaded, compiled), compiled.agents)
    core = BatchedEnv(compiled, batch=1, split="test")
    kept, held = [], []
    torch.manual_seed(0)
    with limited_threads(1):
        for episode in range(episodes):
            observations = core.reset(0 if episode == 0 else None)
            while core.alive.any():
                observations = core.step(decide(act, observations, core)).observations
                kept.append(core.state.allocation[0, :, 0])
                held.append(core.state.support[0])
    return np.mean(kept, axis=0) / TENTHS, np.mean(held, axis=0) / TENTHS


def grid_trained_keeping(point: dict, task: int) -> list[float]:
    """Keeping over the last tenth of training of every seed a grid record's ``point`` holds (its own, then its
    ``other_seeds``, :mod:`hivex_dsl.train.grid_seeds`)."""
    return [recorded_trained_keeping(run["curve_panels"], task) for run in (point, *point.get("other_seeds", []))]


def print_trained_keeping() -> None:
    """Per task and level, keeping over the last tenth of training: the original's runs' mean (its band's edges) and
    every seed of the committed grid's point (benchmarks/baselines/grids/wildfire_resource_management.json), with
    their mean where it holds more than one."""
    import json
    from pathlib import Path

    grid = Path(__file__).resolve().parent / "baselines" / "grids" / f"{ENVIRONMENT}.json"
    points = {(p["task_index"], p["level"]): p for p in json.loads(grid.read_text())["points"]}
    print("task  level  original keeping (band)  |  grid seeds (mean)")
    for (task, level), point in sorted(points.items()):
        keeping, lower, upper, _ = original_trained_keeping(task, level)
        ours = grid_trained_keeping(point, task)
        mean = f" ({np.mean(ours):.3f})" if len(ours) > 1 else ""
        print(f"{task:4d}  {level:5d}  {keeping:8.3f} ({lower:.3f}-{upper:.3f})  |  "
              f"{' '.join(f'{v:.3f}' for v in ours)}{mean}", flush=True)


def untrained_shares(level: int, seed: int, worlds: int = 4, decisions: int = 400,
                     params: dict | None = None) -> tuple[float, float]:
    """(keeping, giving) of this toolkit's untrained policy of training ``seed`` (its network as `hivex train` builds
    it, sampling its actions) at ``level``, on training worlds 5000 + ``seed``: ``worlds`` worlds of the main task
    play ``decisions`` decisions, and the episodes that end are pooled. ``params`` override the environment's."""
    import torch

    from hivex_dsl.train.config import make_config
    from hivex_dsl.train.logs import episode_summaries
    from hivex_dsl.train.networks import ActorCritic, to_tensors
    from hivex_dsl.train.ppo import make_env

    compiled = hivex_dsl.compile({"hivex": 1, "environment": ENVIRONMENT, "terrain_level": level,
                                  "params": dict(params or {})})
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


def readings(level: int, worlds: int = 16, steps: int = 1200, seed: int = 1) -> dict[str, float]:
    """Uniform random play (actions from ``seed``) at ``level`` on the training seed's stream, each step's terms (the
    environment's own, under seven params) summed over the episodes that end, each over Individual Performance (P
    times the share held): keeping as ``self_squared`` (P r_self^2, the equation as printed), ``self_held`` (P
    times the share held times r_self, the default of sessions 74-76), ``self_allocated`` (P times the share
    allocated times r_self, the default of sessions 77-78) or ``self_kept`` (P r_self, the default since session
    79), giving as ``given_total`` (the neighbours' summed P times the share given), ``given_each`` (each
    neighbour's P times the share given it) or ``given_each_held`` (each neighbour's P times the share it holds
    times the share given it, the default since session 74)."""
    from hivex_dsl.envs.wildfire_resource_management.statistics import individual_performance
    from hivex_dsl.envs.wildfire_resource_management.terms import neighbour_performance, watch_tower_performance
    from hivex_dsl.runtime.batched import BatchedEnv

    compiled = hivex_dsl.compile({"hivex": 1, "environment": ENVIRONMENT, "terrain_level": level})
    env = BatchedEnv(compiled, batch=worlds, split="train")
    env.reset()
    rng = np.random.default_rng(seed)
    params = env.sim.params
    read = {  # name -> (term, the params that read it so): the environment's own terms, each reading a param
        "individual": (individual_performance, params),
        "self_squared": (watch_tower_performance, params.model_copy(update={"own_term_weight": "kept_squared"})),
        "self_held": (watch_tower_performance, params.model_copy(update={"own_term_weight": "held_kept"})),
        "self_allocated": (watch_tower_performance, params.model_copy(update={"own_term_weight": "allocated_kept"})),
        "self_kept": (watch_tower_performance, params.model_copy(update={"own_term_weight": "kept"})),
        "given_total": (neighbour_performance, params.model_copy(update={"neighbour_term_weight": "given_total"})),
        "given_each": (neighbour_performance, params.model_copy(update={"neighbour_term_weight": "given_each",
                                                                        "performance_weight": "none"})),
        "given_each_held": (neighbour_performance, params.model_copy(update={"neighbour_term_weight": "given_each"})),
    }
    running = {name: np.zeros((worlds, compiled.agents)) for name in read}
    ended = dict.fromkeys(read, 0.0)
    for _ in range(steps):
        env.step(rng.integers(0, 3, (worlds, compiled.agents, 4)))
        for name, (term, reading) in read.items():
            running[name] += term(None, env.state, None, reading)
        done = ~env.alive.any(axis=1)
        if done.any():
            for name in read:
                ended[name] += running[name][done].sum()
                running[name][done] = 0.0
            env.reset_worlds(done)
    return {name: ended[name] / ended["individual"] for name in read if name != "individual"}


TAKE_BACKS = ("none", "received_first", "proportional")


def allocation_model(take_back: str = "none", initial_self_tenths: int = 0, worlds: int = 4000, steps: int = 160,
                     skip: int = 20, seed: int = 0) -> tuple[float, float, float]:
    """(keeping, giving, held) of the nine towers' allocations alone under uniform random play: keeping
    E[r_self^2] / E[held], giving 3 E[given] / E[held] and held E[held] over the steps after ``skip`` of ``worlds``
    worlds of ``steps`` steps (with P alike at every tower and step, keeping and giving as the terms here read them).
    Tenths move as the environment moves them (resources.apply_actions, its default allocatable_tenths); with
    ``take_back`` a tower's 'Sub from Self' instead returns a tenth its neighbours gave it to its giver, first
    ('received_first': before its own) or with the chance of its share of what the tower holds ('proportional')."""
    from hivex_dsl.envs.wildfire_resource_management.params import WildfireResourceParams
    from hivex_dsl.envs.wildfire_resource_management.resources import (SUBTRACT, TENTHS, TOWERS, apply_actions,
                                                                       initial_resources, total_support)

    if take_back not in TAKE_BACKS:
        raise HivexError(f"take_back must be one of {', '.join(TAKE_BACKS)}, not {take_back!r}")
    rng = np.random.default_rng(seed)
    allocation, budget = initial_resources(worlds, TOWERS, initial_self_tenths)
    held_back = TENTHS - WildfireResourceParams().allocatable_tenths  # the tenths no add can take, as the env's
    sums = np.zeros(3)
    for step in range(steps):
        actions = rng.integers(0, 3, (worlds, TOWERS, 4))
        if take_back != "none":
            asks = actions[..., 0] == SUBTRACT
            _take_back(allocation, budget, asks, take_back, rng)
            actions[..., 0][asks] = 0  # the tower's subtraction is spent
        allocation, free, _ = apply_actions(allocation, budget - held_back, actions)
        budget = free + held_back
        if step >= skip:
            kept, given = allocation[..., 0] / TENTHS, allocation[..., 1:].sum(-1) / TENTHS
            held = total_support(allocation) / TENTHS
            sums += ((kept * kept).mean(), given.mean(), held.mean())
    squared, given, held = sums / (steps - skip)
    return squared / held, 3 * given / held, held


def _take_back(allocation: np.ndarray, budget: np.ndarray, asks: np.ndarray, mode: str,
               rng: np.random.Generator) -> None:
    """In place: every tower that ``asks`` (worlds, 9) gives back a tenth it holds, one a neighbour gave it (to that
    giver's budget, the first giver in index order that gave one) or its own (to its own budget), as ``mode`` says."""
    from hivex_dsl.envs.wildfire_resource_management.resources import NEIGHBOURS as TABLE, TOWERS

    for tower in range(TOWERS):
        givers = [(giver, 1 + slot) for giver in range(TOWERS) for slot in range(TABLE.shape[1])
                  if TABLE[giver, slot] == tower]
        received = sum(allocation[:, giver, slot] for giver, slot in givers).astype(float)
        own = allocation[:, tower, 0].astype(float)
        from_received = asks[:, tower] & (received > 0)
        if mode == "proportional":
            from_received &= rng.random(len(own)) < received / np.maximum(own + received, 1.0)
        from_own = asks[:, tower] & ~from_received & (own > 0)
        allocation[from_own, tower, 0] -= 1
        budget[from_own, tower] += 1
        for giver, slot in givers:  # the first giver holding a tenth here returns it
            hit = from_received & (allocation[:, giver, slot] > 0)
            allocation[hit, giver, slot] -= 1
            budget[hit, giver] += 1
            from_received &= ~hit


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--inits", type=int, default=8, help="untrained networks a level (training seeds 0..N-1)")
    parser.add_argument("--worlds", type=int, default=4, help="worlds each network plays (default 4)")
    parser.add_argument("--decisions", type=int, default=400, help="decisions each plays (default 400)")
    parser.add_argument("--levels", default="1,5,10", help="terrain levels, comma-separated")
    parser.add_argument("--readings", action="store_true", help="uniform random play read seven ways, per level")
    parser.add_argument("--model", action="store_true", help="the allocations alone under other mechanics")
    parser.add_argument("--as-printed", action="store_true",
                        help="the untrained networks under the terms' readings before session 74")
    parser.add_argument("--trained", action="store_true",
                        help="keeping over the last tenth of training, the original's runs and the committed grid")
    parser.add_argument("--holdings", nargs="+", metavar="CHECKPOINT",
                        help="what each tower keeps and holds under trained checkpoints (6 test episodes)")
    args = parser.parse_args(argv)
    try:
        if args.inits < 1 or args.worlds < 1 or args.decisions < 1:
            raise HivexError("--inits, --worlds and --decisions must be at least 1")
        levels = [int(level) for level in args.levels.split(",")]
        if args.holdings:
            for checkpoint in args.holdings:
                kept, held = tower_holdings(checkpoint)
                print(f"{checkpoint}\n  kept {np.round(kept, 2)}\n  held {np.round(held, 2)}", flush=True)
            return 0
        if args.trained:
            print_trained_keeping()
            return 0
        if args.model:
            print("take back        from  keeping  giving  held")
            for take_back in TAKE_BACKS:
                for start in (0, 9):
                    keeping, giving, held = allocation_model(take_back, start)
                    print(f"{take_back:15s}  {start:4d}  {keeping:7.3f}  {giving:6.2f}  {held:4.2f}", flush=True)
            return 0
        if args.readings:
            print("level  keeping: P r^2  P held r  P allocated r  P r  |  giving: summed  each  each held")
            for level in levels:
                r = readings(level)
                print(f"{level:5d}  {r['self_squared']:14.3f}  {r['self_held']:8.3f}  {r['self_allocated']:13.3f}  "
                      f"{r['self_kept']:5.3f}  |  "
                      f"{r['given_total']:14.2f}  "
                      f"{r['given_each']:4.2f}  {r['given_each_held']:9.2f}", flush=True)
            return 0
        print("level  original keeping (tasks 0-2)  giving (tasks 0-2)  count  |  ours keeping  giving (min-max)")
        for level in levels:
            theirs = np.array([original_first_point(task, level) for task in TASK_WEIGHTS])
            params = AS_PRINTED if args.as_printed else None
            ours = np.array([untrained_shares(level, seed, args.worlds, args.decisions, params)
                             for seed in range(args.inits)])
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
