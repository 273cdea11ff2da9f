"""Parameter-shared PPO in the style of CleanRL (one file, torch) on any bundled HIVEX scenario.

Every agent of every world is one slot of :func:`hivex_dsl.vector_env`; one actor-critic acts for all.
It reads vector and visual observations (an MLP and a small CNN) and acts in discrete,
multi-discrete, continuous or hybrid (continuous + discrete) action spaces.

    pip install "hivex-dsl[train]"        # torch (install torch==2.13.0 first for the CPU wheel)
    python examples/cleanrl_ppo.py --scenario ocean_plastic_collection/main --total-timesteps 20000

SAME_STEP autoreset makes CleanRL's bootstrapping rule exact: a slot that ended returns its next
episode's first observation at once, so ``next_done`` masks the value of the step after an ending.
Per-agent episode returns come from ``infos["hivex_episode"]``.
"""

from __future__ import annotations

import argparse
import time

import numpy as np
import torch
import torch.nn as nn
from gymnasium import spaces
from torch.distributions import Categorical, Normal

import hivex_dsl
from hivex_dsl.adapters.registration import make_scenario


def parse_args(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--scenario", default="wind_farm_control/main", help="bundled <env>/<name>, or a YAML path")
    p.add_argument("--num-worlds", type=int, default=2)
    p.add_argument("--episode-length", type=int, default=None, help="override the scenario's episode length")
    p.add_argument("--total-timesteps", type=int, default=50_000, help="agent-steps over all slots")
    p.add_argument("--num-steps", type=int, default=128, help="steps per slot per rollout")
    p.add_argument("--learning-rate", type=float, default=3e-4)
    p.add_argument("--gamma", type=float, default=0.99)
    p.add_argument("--gae-lambda", type=float, default=0.95)
    p.add_argument("--update-epochs", type=int, default=4)
    p.add_argument("--num-minibatches", type=int, default=4)
    p.add_argument("--clip-coef", type=float, default=0.2)
    p.add_argument("--ent-coef", type=float, default=0.01)
    p.add_argument("--vf-coef", type=float, default=0.5)
    p.add_argument("--max-grad-norm", type=float, default=0.5)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--threads", type=int, default=1, help="torch CPU threads (small nets: 1 is fastest)")
    return p.parse_args(argv)


def layer(module: nn.Module, std: float = np.sqrt(2)) -> nn.Module:
    nn.init.orthogonal_(module.weight, std)
    nn.init.constant_(module.bias, 0.0)
    return module


class Encoder(nn.Module):
    """Box observation -> MLP; {"vector", "visual"} -> MLP(vector) + CNN(visual), concatenated."""

    def __init__(self, space: spaces.Space):
        super().__init__()
        vector = space["vector"] if isinstance(space, spaces.Dict) else space
        self.vector = nn.Sequential(layer(nn.Linear(int(np.prod(vector.shape)), 64)), nn.Tanh())
        self.visual = None
        size = 64
        if isinstance(space, spaces.Dict) and "visual" in space.spaces:
            height, width, channels = space["visual"].shape
            self.visual = nn.Sequential(
                layer(nn.Conv2d(channels, 16, 3, stride=2)), nn.ReLU(),
                layer(nn.Conv2d(16, 32, 3, stride=2)), nn.ReLU(), nn.Flatten())
            with torch.no_grad():
                size += self.visual(torch.zeros(1, channels, height, width)).shape[1]
        self.size = size

    def forward(self, obs) -> torch.Tensor:
        if self.visual is None:
            return self.vector(obs.flatten(1))
        pixels = obs["visual"].permute(0, 3, 1, 2)  # (N, H, W, C) -> (N, C, H, W)
        return torch.cat([self.vector(obs["vector"]), self.visual(pixels)], dim=1)


class Heads(nn.Module):
    """Distributions over one action space: categorical parts and a diagonal Gaussian part."""

    def __init__(self, space: spaces.Space, size: int):
        super().__init__()
        parts = space.spaces if isinstance(space, spaces.Dict) else {"action": space}
        self.kinds, self.nvec, self.logits, self.mean, self.log_std = {}, {}, nn.ModuleDict(), nn.ModuleDict(), {}
        for key, sub in parts.items():
            if isinstance(sub, spaces.Box):
                self.kinds[key] = "box"
                self.mean[key] = layer(nn.Linear(size, sub.shape[0]), 0.01)
                self.register_parameter(f"log_std_{key}", nn.Parameter(torch.zeros(sub.shape[0])))
            else:
                nvec = [int(sub.n)] if isinstance(sub, spaces.Discrete) else [int(n) for n in sub.nvec]
                self.kinds[key], self.nvec[key] = ("discrete" if isinstance(sub, spaces.Discrete) else "multi"), nvec
                self.logits[key] = layer(nn.Linear(size, sum(nvec)), 0.01)
        self.space = space

    def dists(self, hidden: torch.Tensor) -> dict:
        out = {}
        for key, kind in self.kinds.items():
            if kind == "box":
                out[key] = [Normal(self.mean[key](hidden), getattr(self, f"log_std_{key}").exp())]
            else:
                out[key] = [Categorical(logits=chunk) for chunk in self.logits[key](hidden).split(self.nvec[key], 1)]
        return out

    def sample(self, dists: dict) -> dict:
        return {key: (parts[0].sample() if self.kinds[key] == "box" else torch.stack([d.sample() for d in parts], 1))
                for key, parts in dists.items()}

    def log_prob_entropy(self, dists: dict, actions: dict) -> tuple[torch.Tensor, torch.Tensor]:
        log_prob, entropy = 0.0, 0.0
        for key, parts in dists.items():
            if self.kinds[key] == "box":
                log_prob = log_prob + parts[0].log_prob(actions[key]).sum(1)
                entropy = entropy + parts[0].entropy().sum(1)
            else:
                for i, d in enumerate(parts):
                    log_prob = log_prob + d.log_prob(actions[key][:, i])
                    entropy = entropy + d.entropy()
        return log_prob, entropy

    def to_env(self, actions: dict):
        """Torch actions -> what the vector env takes (Box actions clipped into their bounds)."""
        out = {}
        for key, value in actions.items():
            value = value.cpu().numpy()
            sub = self.space[key] if isinstance(self.space, spaces.Dict) else self.space
            if self.kinds[key] == "box":
                value = np.clip(value, sub.low, sub.high).astype(np.float32)
            elif self.kinds[key] == "discrete":
                value = value[:, 0]
            out[key] = value
        return out if isinstance(self.space, spaces.Dict) else out["action"]


class Agent(nn.Module):
    def __init__(self, obs_space: spaces.Space, act_space: spaces.Space):
        super().__init__()
        self.encoder = Encoder(obs_space)
        self.body = nn.Sequential(layer(nn.Linear(self.encoder.size, 64)), nn.Tanh())
        self.critic = layer(nn.Linear(64, 1), 1.0)
        self.heads = Heads(act_space, 64)

    def value(self, obs) -> torch.Tensor:
        return self.critic(self.body(self.encoder(obs))).squeeze(1)

    def act(self, obs, actions=None):
        hidden = self.body(self.encoder(obs))
        dists = self.heads.dists(hidden)
        actions = self.heads.sample(dists) if actions is None else actions
        log_prob, entropy = self.heads.log_prob_entropy(dists, actions)
        return actions, log_prob, entropy, self.critic(hidden).squeeze(1)


def tree_map(fn, tree):
    return {k: tree_map(fn, v) for k, v in tree.items()} if isinstance(tree, dict) else fn(tree)


def tensor(tree):
    return tree_map(lambda x: torch.as_tensor(x, dtype=torch.float32), tree)


def main(argv=None) -> list[float]:
    args = parse_args(argv)
    torch.manual_seed(args.seed)
    torch.set_num_threads(args.threads)
    scenario = make_scenario(None, args.scenario, max_cycles=args.episode_length)
    envs = hivex_dsl.vector_env(scenario, num_worlds=args.num_worlds, autoreset_mode="same_step")
    slots, steps = envs.num_envs, args.num_steps
    agent = Agent(envs.single_observation_space, envs.single_action_space)
    optimizer = torch.optim.Adam(agent.parameters(), lr=args.learning_rate, eps=1e-5)

    obs_buf, act_buf = [None] * steps, [None] * steps
    logprobs, rewards, dones, values = (torch.zeros(steps, slots) for _ in range(4))
    next_obs, _ = envs.reset(seed=args.seed)
    next_obs, next_done = tensor(next_obs), torch.zeros(slots)
    returns_seen: list[float] = []
    updates = max(1, args.total_timesteps // (steps * slots))
    start = time.time()
    for update in range(updates):
        for t in range(steps):
            obs_buf[t], dones[t] = next_obs, next_done
            with torch.no_grad():
                action, logprob, _, value = agent.act(next_obs)
            act_buf[t], logprobs[t], values[t] = action, logprob, value
            next_obs, reward, terminated, truncated, infos = envs.step(agent.heads.to_env(action))
            rewards[t] = torch.as_tensor(reward, dtype=torch.float32)
            next_obs, next_done = tensor(next_obs), torch.as_tensor(terminated | truncated, dtype=torch.float32)
            if "hivex_episode" in infos:
                returns_seen.extend(infos["hivex_episode"]["return"][infos["_hivex_episode"]].tolist())

        with torch.no_grad():  # generalised advantage estimation
            next_value = agent.value(next_obs)
            advantages, last = torch.zeros_like(rewards), torch.zeros(slots)
            for t in reversed(range(steps)):
                nonterminal = 1.0 - (next_done if t == steps - 1 else dones[t + 1])
                following = next_value if t == steps - 1 else values[t + 1]
                delta = rewards[t] + args.gamma * following * nonterminal - values[t]
                advantages[t] = last = delta + args.gamma * args.gae_lambda * nonterminal * last
            targets = advantages + values

        def flat(index, tree_list):
            stacked = {k: torch.stack([o[k] for o in tree_list]) for k in tree_list[0]} if isinstance(tree_list[0], dict) \
                else torch.stack(tree_list)
            return tree_map(lambda x: x.reshape((-1,) + x.shape[2:])[index], stacked)

        batch = steps * slots
        minibatch = max(1, batch // args.num_minibatches)
        b_adv, b_targets, b_logprobs = advantages.reshape(-1), targets.reshape(-1), logprobs.reshape(-1)
        for _ in range(args.update_epochs):
            order = torch.randperm(batch)
            for first in range(0, batch, minibatch):
                index = order[first:first + minibatch]
                _, new_logprob, entropy, new_value = agent.act(flat(index, obs_buf), flat(index, act_buf))
                ratio = (new_logprob - b_logprobs[index]).exp()
                adv = b_adv[index]
                adv = (adv - adv.mean()) / (adv.std() + 1e-8)
                policy_loss = torch.max(-adv * ratio, -adv * ratio.clamp(1 - args.clip_coef, 1 + args.clip_coef)).mean()
                value_loss = 0.5 * ((new_value - b_targets[index]) ** 2).mean()
                loss = policy_loss - args.ent_coef * entropy.mean() + args.vf_coef * value_loss
                optimizer.zero_grad()
                loss.backward()
                nn.utils.clip_grad_norm_(agent.parameters(), args.max_grad_norm)
                optimizer.step()
        recent = np.mean(returns_seen[-20:]) if returns_seen else float("nan")
        print(f"update {update + 1}/{updates}  agent-steps {(update + 1) * batch}  "
              f"mean episode return (last 20) {recent:.3f}  {time.time() - start:.0f}s", flush=True)
    envs.close()
    return returns_seen


if __name__ == "__main__":
    main()
