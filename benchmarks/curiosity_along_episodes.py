"""Where in its agent-episodes a trained run's curiosity module meets what it cannot predict.

    python benchmarks/curiosity_along_episodes.py RUN [--episodes 2] [--bins 0 10 50 100 200 300 400]

The run's checkpoint (its policy and its curiosity module, as they ended) plays ``--episodes`` episodes of one world of
the scenario it trained on, in its training worlds and as the trainer steps them (its ``ended_agents``). Each
transition the trainer would learn from (the agent acted: ``acting_mask``, so no agent waiting out its world and no
step across a reset) is kept with its forward error e (the module's reward before strength and cap, so reward =
min(strength x e, 1)) and its decision's index in its agent-episode. Per bin of that index (``--bins``' edges, the
last bin running on to the longest agent-episode's end) it prints the transitions, the mean and median e, the
curiosity reward the bin adds to an agent-episode, and the mean absolute change of each vector component. The
original's Curiosity Reward panel (a sum over an agent-episode) reads beside the total: Drone-Based Reforestation's
note 'Where the module's error lies along a drone-episode'.
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import NamedTuple

import numpy as np
import torch

from hivex_dsl.adapters.gymnasium import HivexVectorEnv
from hivex_dsl.train.checkpoint import load_checkpoint, policy_for
from hivex_dsl.train.curiosity import Curiosity
from hivex_dsl.train.networks import fixed_weights, to_tensors
from hivex_dsl.train.ppo import acting_mask, action_mask


class Transitions(NamedTuple):
    """The kept transitions of the played episodes: ``index`` (N,) the decision's place in its agent-episode (0 for
    the first), ``error`` (N,) the forward error, ``change`` (N, F) |next vector - vector|, ``episodes`` the
    agent-episodes that ended, and the module's ``strength``."""

    index: np.ndarray
    error: np.ndarray
    change: np.ndarray
    episodes: int
    strength: float


def play(run: Path, episodes: int, seed: int = 0) -> Transitions:
    """The checkpoint of ``run`` playing one training world until each of its agents has ended ``episodes``
    agent-episodes; the transitions of those agent-episodes are kept, none of a later one."""
    data = load_checkpoint(run / "checkpoint.pt")
    compiled, cfg = data["compiled"], data["config"]
    if data["training"] is None or data["training"].get("curiosity") is None:
        raise SystemExit(f"{run / 'checkpoint.pt'} holds no curiosity module: its run trained without one")
    agent = policy_for(data, compiled)
    env = HivexVectorEnv(compiled, num_worlds=1, split="train", ended_agents=cfg.ended_agents)
    module = Curiosity(env.single_observation_space, agent.layout, cfg)
    module.load_state_dict(data["training"]["curiosity"])
    torch.manual_seed(seed)
    obs, infos = env.reset(seed=seed)
    done = np.zeros(env.num_envs, bool)
    active = np.ones(env.num_envs, bool)
    age = np.zeros(env.num_envs, int)
    ended = np.zeros(env.num_envs, int)
    kept = []
    with torch.no_grad(), fixed_weights():
        for _ in range(2 * (episodes + 1) * compiled.episode_decisions):  # every episode ends by its time limit
            if ended.min() >= episodes:
                break
            valid = acting_mask(done, active) & (ended < episodes)
            now = to_tensors(obs)
            cont, disc, _ = agent.act(now, mask=action_mask(infos, agent))
            obs, _, terminated, truncated, infos = env.step(agent.layout.to_env(cont, disc))
            following = to_tensors(obs)
            error = module._forward_error(module._encode(now), module._encode(following),
                                          module._action_input(cont, disc)).numpy()
            change = (following["vector"] - now["vector"]).abs().numpy()
            kept.append((age[valid], error[valid], change[valid]))
            done = terminated | truncated
            active = np.asarray(infos.get("active", np.ones_like(done)), dtype=bool)
            ended += done & valid
            age = np.where(done, 0, age + valid)
    index, error, change = (np.concatenate(part) for part in zip(*kept))
    return Transitions(index, error, change, int(ended.sum()), module.strength)


def by_index(found: Transitions, edges: list[int]) -> list[dict]:
    """Per bin [edges[k], edges[k + 1]) of the decision index: transitions, mean and median e, the capped reward the
    bin adds to an agent-episode (its sum over the played agent-episodes, shared out), and each component's mean
    change."""
    rows = []
    reward = np.minimum(found.strength * found.error, 1.0)
    for low, high in zip(edges, edges[1:]):
        inside = (found.index >= low) & (found.index < high)
        if inside.any():
            rows.append({"from": low, "to": high, "transitions": int(inside.sum()),
                         "mean_error": float(found.error[inside].mean()),
                         "median_error": float(np.median(found.error[inside])),
                         "reward_per_episode": float(reward[inside].sum() / max(found.episodes, 1)),
                         "change": found.change[inside].mean(0)})
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("run", type=Path, help="a run directory of `hivex train` with curiosity")
    parser.add_argument("--episodes", type=int, default=2)
    parser.add_argument("--bins", type=int, nargs="+", default=[0, 10, 50, 100, 200, 300, 400])
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()
    found = play(args.run, args.episodes, args.seed)
    total = np.minimum(found.strength * found.error, 1.0).sum() / max(found.episodes, 1)
    print(f"{args.run}: {len(found.error)} transitions, {found.episodes} agent-episodes ended; curiosity reward "
          f"{total:.3f} an agent-episode, mean e {found.error.mean():.4f}, median {np.median(found.error):.4f}")
    with np.printoptions(precision=3, suppress=True, linewidth=200):
        for row in by_index(found, sorted(set(args.bins) | {int(found.index.max()) + 1})):  # the last bin to the end
            print(f"decisions {row['from']}-{row['to']}: {row['transitions']} transitions, e mean "
                  f"{row['mean_error']:.4f} median {row['median_error']:.4f}, reward {row['reward_per_episode']:.3f} "
                  f"an agent-episode; change {row['change']}")


if __name__ == "__main__":
    main()
