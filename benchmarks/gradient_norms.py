"""How much gradient clipping scales a run's PPO steps: actor and critic gradient norms per minibatch.

    python benchmarks/gradient_norms.py CHECKPOINT [--rollouts 3]

From a `hivex train` checkpoint it collects rollouts on the train seed with the checkpoint's policy and
hyperparameters, and for every minibatch of one shuffled epoch computes the PPO loss's gradient (no step is
taken) and reports the norms of the actor's part (body and policy heads) and of the critic's, and the factor
``max_grad_norm`` clipping would scale the whole gradient by, split by whether the minibatch holds a reward at or
below --penalty (a crash). Adam divides each parameter's step by its running gradient scale, so a factor that
barely varies changes little; one that swings with the minibatch's content reweights it.
"""

from __future__ import annotations

import argparse

import numpy as np
import torch

from hivex_dsl.train import ppo
from hivex_dsl.train.checkpoint import load_checkpoint, policy_for
from hivex_dsl.train.curiosity import Curiosity
from hivex_dsl.train.logs import EpisodeLog


def actor_and_critic(agent) -> tuple[list, list]:
    """The network's parameters split into the actor's (body, policy heads, log-std) and the critic's."""
    critic = {id(p) for module in (agent.critic, agent.value) for p in module.parameters()}
    params = list(agent.parameters())
    return [p for p in params if id(p) not in critic], [p for p in params if id(p) in critic]


def grad_norm(params) -> float:
    grads = [p.grad for p in params if p.grad is not None]
    return float(torch.linalg.vector_norm(torch.stack([g.norm() for g in grads]))) if grads else 0.0


def minibatch_rows(agent, cfg, buf, advantages, returns, rng) -> list[tuple[float, float, float]]:
    """(actor norm, critic norm, lowest reward) of each minibatch of one shuffled epoch, as ppo.update builds it."""
    data, valid = ppo.update_data(buf, advantages, returns)
    data["reward"] = buf.flat("rewards")
    rows = []
    actor, critic = actor_and_critic(agent)
    for mb in ppo.minibatches(data, valid, cfg.batch_size, rng):
        loss, _ = ppo.ppo_loss(agent, mb, cfg.beta, cfg.epsilon)
        agent.zero_grad()
        loss.backward()
        rows.append((grad_norm(actor), grad_norm(critic), float(mb["reward"].min())))
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("checkpoint")
    parser.add_argument("--rollouts", type=int, default=3)
    parser.add_argument("--penalty", type=float, default=-50.0, help="a reward at or below this is a crash")
    args = parser.parse_args()
    torch.set_num_threads(1)
    torch.manual_seed(0)
    checkpoint = load_checkpoint(args.checkpoint)
    cfg, compiled = checkpoint["config"], checkpoint["compiled"]
    agent = policy_for(checkpoint, compiled).train()
    env, obs, infos = ppo.make_env(compiled, cfg.num_worlds, "train")
    curiosity = None
    if cfg.curiosity_strength > 0:
        curiosity = Curiosity(env.single_observation_space, agent.layout, cfg)
        if "training" in checkpoint:  # a run directory's checkpoint.pt; checkpoints/step_*.pt hold weights only
            curiosity.load_state_dict(checkpoint["training"]["curiosity"])
        else:
            print("the checkpoint holds no curiosity module: a fresh one rewards the rollouts")
    state, buf = ppo.start_rollouts(obs, agent, cfg.rollout_length(env.num_envs), infos)
    rows, rng = [], np.random.default_rng(0)
    for _ in range(args.rollouts):
        next_value = ppo.collect(env, agent, buf, state, cfg, EpisodeLog(), until=ppo.update_due(cfg, env.num_envs))
        advantages, returns, _ = ppo.advantages_and_returns(buf, next_value, cfg, curiosity)
        rows += minibatch_rows(agent, cfg, buf, advantages, returns, rng)
    actor, critic, lowest = (np.array(column) for column in zip(*rows))
    factor = np.minimum(1.0, cfg.max_grad_norm / (np.hypot(actor, critic) + 1e-6)) if cfg.max_grad_norm > 0 \
        else np.ones_like(actor)
    print(f"{len(rows)} minibatches of {cfg.batch_size}; max_grad_norm {cfg.max_grad_norm}")
    print(f"actor gradient norm   median {np.median(actor):.3f}  90th percentile {np.percentile(actor, 90):.3f}")
    print(f"critic gradient norm  median {np.median(critic):.3f}  90th percentile {np.percentile(critic, 90):.3f}")
    for name, rows_of in (("without a crash", lowest > args.penalty), ("with a crash", lowest <= args.penalty)):
        if rows_of.any():
            f = factor[rows_of]
            print(f"clip factor, {rows_of.sum():3d} minibatches {name}: median {np.median(f):.4f}, "
                  f"range {f.min():.4f} to {f.max():.4f}")


if __name__ == "__main__":
    main()
