"""Each environment's training compute bound: floating-point work per agent-step, and how fast this machine can do it.

    python benchmarks/compute_bound.py [--env ID ...] [--set NAME=VALUE ...] [-o benchmarks/results/compute_bound.json]

With -o the rows are merged into the file: a row of the same environment, thread count and machine is replaced,
the others are kept.

For each environment's main scenario at the paper's hyperparameters it runs one real training iteration of
`hivex train`'s loop (a rollout of buffer_size agent-steps, the curiosity rewards, advantages, and num_epoch
passes of minibatch PPO and curiosity updates) under torch's FLOP counter (torch.utils.flop_counter, which
counts the matrix products and convolutions, forward and backward, from their shapes), and divides by the
iteration's agent-steps. It then measures the floating-point rate this machine attains on the network's own
heaviest layers at the update's minibatch size (forward and backward, the threads of --set torch_threads, the
default all cores up to 8), so

    compute bound (agent-steps/s) = attained FLOP/s / FLOP per agent-step

is the speed training could reach if nothing but that arithmetic took time. The baselines page sets it beside
the measured throughput (benchmarks/train_throughput.py) of the same machine.
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np
import torch
from torch.utils.flop_counter import FlopCounterMode

from hivex_dsl.compiler import registry
from hivex_dsl.compiler import compile
from hivex_dsl.train.devices import machine
from hivex_dsl.train.config import make_config, parse_assignments
from hivex_dsl.train.curiosity import Curiosity
from hivex_dsl.train.logs import EpisodeLog
from hivex_dsl.train.networks import ActorCritic
from hivex_dsl.train.ppo import (advantages_and_returns, collect, make_env, make_optimizer, start_rollouts, update,
                                 update_due)

SCENARIOS = Path(__file__).resolve().parents[1] / "scenarios"


def iteration_flops(environment: str, overrides) -> dict:
    """FLOPs of one training iteration of ``environment``'s main scenario, split into rollout and update, and
    the iteration's agent-steps; -> also the modules, for :func:`attained_flops`."""
    compiled = compile(SCENARIOS / environment / "main.yaml")
    cfg = make_config(environment, overrides)
    torch.manual_seed(cfg.seed)
    env, obs, infos = make_env(compiled, cfg.num_worlds, "train")
    agent = ActorCritic(env.single_observation_space, env.single_action_space, cfg)
    optimizer, curiosity, trained = make_optimizer(agent, cfg.learning_rate), None, None
    if cfg.curiosity_strength > 0:  # as ppo.train builds it
        curiosity = Curiosity(env.single_observation_space, agent.layout, cfg)
        trained = (curiosity, make_optimizer(curiosity, cfg.curiosity_learning_rate))
    state, buf = start_rollouts(obs, agent, cfg.rollout_length(env.num_envs), infos)
    with FlopCounterMode(display=False) as rollout:
        next_value = collect(env, agent, buf, state, cfg, EpisodeLog(), until=update_due(cfg, env.num_envs))
    with FlopCounterMode(display=False) as learning:
        advantages, returns, _ = advantages_and_returns(buf, next_value, cfg, curiosity)
        update(agent, optimizer, buf, advantages, returns, cfg, cfg.beta, cfg.epsilon, np.random.default_rng(0),
               trained)
    steps = buf.rewards.numel()
    return {"environment": environment, "agent_steps": steps,
            "rollout_flop_per_agent_step": rollout.get_total_flops() / steps,
            "update_flop_per_agent_step": learning.get_total_flops() / steps,
            "flop_per_agent_step": (rollout.get_total_flops() + learning.get_total_flops()) / steps,
            "batch_size": cfg.batch_size, "threads": cfg.threads(), "_agent": agent,
            "_samples": (buf.flat_obs(), buf.flat("cont"), buf.flat("disc"))}


def attained_flops(agent: ActorCritic, samples: tuple, batch: int, repeats: int = 5) -> float:
    """FLOP/s of the policy's forward and backward (``evaluate``, as the PPO loss runs it) on ``batch`` of the
    rollout's samples: the update's own arithmetic at its own shapes, timed after a warm-up, best of ``repeats``."""
    obs, cont, disc = samples
    sample = {k: v[:batch] for k, v in obs.items()}

    def once() -> None:
        agent.zero_grad()
        logp, entropy, value = agent.evaluate(sample, cont[:batch], disc[:batch])
        (logp.mean() + entropy.mean() + value.mean()).backward()

    with FlopCounterMode(display=False) as counter:
        once()
    best = float("inf")
    for _ in range(repeats + 1):
        start = time.perf_counter()
        once()
        best = min(best, time.perf_counter() - start)
    return counter.get_total_flops() / best


def measure(environment: str, overrides) -> dict:
    row = iteration_flops(environment, overrides)
    agent, samples = row.pop("_agent"), row.pop("_samples")
    torch.set_num_threads(row["threads"])
    rate = attained_flops(agent, samples, row["batch_size"])
    return row | {"attained_flop_per_s": rate, "compute_bound_agent_steps_per_s": rate / row["flop_per_agent_step"],
                  "machine": machine()}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--env", action="append", help="environment id (repeatable; default all)")
    parser.add_argument("--set", action="append", default=[], dest="assignments", metavar="NAME=VALUE")
    parser.add_argument("-o", "--output", type=Path)
    args = parser.parse_args()
    overrides = parse_assignments(args.assignments)
    for env in args.env or registry.environments():
        row = measure(env, overrides)
        print(f"{env:32} {row['flop_per_agent_step'] / 1e6:10.1f} MFLOP/agent-step "
              f"(update {100 * row['update_flop_per_agent_step'] / row['flop_per_agent_step']:.0f}%)  "
              f"{row['attained_flop_per_s'] / 1e9:7.1f} GFLOP/s attained  "
              f"bound {row['compute_bound_agent_steps_per_s']:10,.0f} agent-steps/s", flush=True)
        if args.output:  # after each environment, merged: the file keeps every row not measured again
            args.output.write_text(json.dumps(merged(args.output, [row]), indent=2) + "\n")


def merged(path: Path, rows: list[dict]) -> dict:
    """The report at ``path`` (if any) with ``rows`` replacing its rows of the same environment, thread count and
    machine; the others are kept."""
    key = lambda row: (row["machine"], row["environment"], row["threads"])  # noqa: E731
    report = json.loads(path.read_text()) if path.is_file() else {"rows": []}
    fresh = {key(row) for row in rows}
    return {"rows": [row for row in report["rows"] if key(row) not in fresh] + rows}


if __name__ == "__main__":
    main()
