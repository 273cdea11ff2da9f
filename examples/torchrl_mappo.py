"""TorchRL multi-agent PPO (MAPPO, or IPPO with --ippo) on any bundled HIVEX scenario (one file).

    pip install torch==2.13.0 "hivex-dsl[torchrl]"      # the torch pin keeps pip from pulling another torch
    python examples/torchrl_mappo.py --env aerial_wildfire_suppression --episode-length 300 --iterations 20

It follows TorchRL's multi-agent PPO tutorial: a ``Collector`` over the env, a ``MultiAgentMLP`` policy
shared by every agent (a categorical head for Discrete actions, a TanhNormal one for Box actions), a
critic that is centralised (MAPPO: one MLP reads the world's global state, every agent's observation and the
world's facts no agent observes, and gives each agent its value) or not (IPPO: a ``MultiAgentMLP`` over each
agent's own observation), GAE and ``ClipPPOLoss`` from ``torchrl.objectives``.

The env is :func:`hivex_dsl.adapters.torchrl.torchrl_env`: TorchRL's ``PettingZooWrapper(env, use_mask=True,
done_on_any=False)`` over one world, every agent in the group ``"agents"``, flat observations (OPC's, DBR's and
AWS's images are flattened after the vector), WRM's and OPC's MultiDiscrete actions as one joint Discrete action
and DBR's and AWS's hybrid actions as one Box(-1, 1) (see the module). An agent whose own episode ended (a crash,
an empty battery) is masked out (``("agents", "mask")`` False) until its world resets; its steps get no advantage.
Episodes of the bundled scenarios are long (500 to 5000 steps): ``--episode-length`` shortens them.
"""

from __future__ import annotations

import argparse
import math

import torch
from tensordict.nn import TensorDictModule
from tensordict.nn.distributions import NormalParamExtractor
from torch import nn
from torchrl.collectors import Collector
from torchrl.data import Categorical as CategoricalSpec
from torchrl.data import LazyTensorStorage, ReplayBuffer
from torchrl.data.replay_buffers.samplers import SamplerWithoutReplacement
from torchrl.envs import RewardSum, TransformedEnv
from torchrl.modules import MLP, MultiAgentMLP, ProbabilisticActor, TanhNormal
from torchrl.objectives import ClipPPOLoss, ValueEstimators

from hivex_dsl.adapters.torchrl import torchrl_env


def parse_args(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--scenario", default=None, help="bundled <env>/<name>, or a YAML path")
    p.add_argument("--env", default="wind_farm_control", help="an environment (its main scenario) if no --scenario")
    p.add_argument("--task", default=None, help="one of the environment's tasks instead of the scenario's")
    p.add_argument("--episode-length", type=int, default=None, help="override the scenario's episode length")
    p.add_argument("--iterations", type=int, default=10, help="collection + PPO update rounds")
    p.add_argument("--frames-per-batch", type=int, default=600, help="env steps (every agent acts) per iteration")
    p.add_argument("--minibatch-size", type=int, default=200)
    p.add_argument("--epochs", type=int, default=4, help="passes over each batch")
    p.add_argument("--hidden", type=int, default=64, help="units of each of the two hidden layers")
    p.add_argument("--lr", type=float, default=3e-4)
    p.add_argument("--gamma", type=float, default=0.99)
    p.add_argument("--lmbda", type=float, default=0.95)
    p.add_argument("--clip-epsilon", type=float, default=0.2)
    p.add_argument("--entropy-coef", type=float, default=1e-3)
    p.add_argument("--max-grad-norm", type=float, default=1.0)
    p.add_argument("--ippo", action="store_true", help="a critic per agent's own observation instead of MAPPO's")
    p.add_argument("--seed", type=int, default=0)
    return p.parse_args(argv)


def main(argv=None) -> list[dict]:
    args = parse_args(argv)
    torch.manual_seed(args.seed)
    torch.set_num_threads(1)  # small networks: one thread is fastest on CPU

    # --- the environment: one world, every agent in the group "agents"; RewardSum keeps each episode's return
    env = torchrl_env(args.scenario or f"{args.env}/main", task=args.task, max_cycles=args.episode_length,
                      seed=args.seed)
    env = TransformedEnv(env, RewardSum(in_keys=[env.reward_key], out_keys=[("agents", "episode_reward")]))
    n_agents = len(env.group_map["agents"])
    n_obs = env.observation_spec["agents", "observation"].shape[-1]
    action_spec = env.full_action_spec_unbatched["agents", "action"]
    discrete = isinstance(action_spec, CategoricalSpec)

    # --- the policy: one MLP shared by every agent; logits of a Categorical or loc/scale of a TanhNormal
    def mlp(n_outputs: int, centralised: bool) -> MultiAgentMLP:
        return MultiAgentMLP(n_agent_inputs=n_obs, n_agent_outputs=n_outputs, n_agents=n_agents,
                             centralised=centralised, share_params=True, depth=2, num_cells=args.hidden,
                             activation_class=nn.Tanh)

    if discrete:
        actor_net = TensorDictModule(mlp(action_spec.space.n, centralised=False),
                                     in_keys=[("agents", "observation")], out_keys=[("agents", "logits")])
        policy = ProbabilisticActor(actor_net, spec=env.full_action_spec_unbatched, in_keys=[("agents", "logits")],
                                    out_keys=[env.action_key], distribution_class=torch.distributions.Categorical,
                                    return_log_prob=True)
    else:
        actor_net = TensorDictModule(nn.Sequential(mlp(2 * action_spec.shape[-1], centralised=False),
                                                   NormalParamExtractor()),
                                     in_keys=[("agents", "observation")],
                                     out_keys=[("agents", "loc"), ("agents", "scale")])
        policy = ProbabilisticActor(actor_net, spec=env.full_action_spec_unbatched,
                                    in_keys=[("agents", "loc"), ("agents", "scale")], out_keys=[env.action_key],
                                    distribution_class=TanhNormal,
                                    distribution_kwargs={"low": action_spec.space.low, "high": action_spec.space.high},
                                    return_log_prob=True)

    # --- the critic: MAPPO's reads the world's global state and gives every agent a value; IPPO's each agent's own
    if args.ippo:
        critic = TensorDictModule(mlp(1, centralised=False), in_keys=[("agents", "observation")],
                                  out_keys=[("agents", "state_value")])
    else:
        n_state = env.observation_spec["state"].shape[-1]
        critic = TensorDictModule(nn.Sequential(MLP(in_features=n_state, out_features=n_agents, depth=2,
                                                    num_cells=args.hidden, activation_class=nn.Tanh),
                                                nn.Unflatten(-1, (n_agents, 1))),
                                  in_keys=["state"], out_keys=[("agents", "state_value")])

    # --- collection, the PPO loss with GAE, and the optimiser
    collector = Collector(env, policy, frames_per_batch=args.frames_per_batch,
                          total_frames=args.frames_per_batch * args.iterations)
    buffer = ReplayBuffer(storage=LazyTensorStorage(args.frames_per_batch), sampler=SamplerWithoutReplacement(),
                          batch_size=args.minibatch_size)
    loss_module = ClipPPOLoss(actor_network=policy, critic_network=critic, clip_epsilon=args.clip_epsilon,
                              entropy_coeff=args.entropy_coef, normalize_advantage=False)
    loss_module.set_keys(reward=env.reward_key, action=env.action_key, value=("agents", "state_value"),
                         done=("agents", "done"), terminated=("agents", "terminated"))
    loss_module.make_value_estimator(ValueEstimators.GAE, gamma=args.gamma, lmbda=args.lmbda)
    optimiser = torch.optim.Adam(loss_module.parameters(), args.lr)

    history = []
    for iteration, data in enumerate(collector):
        with torch.no_grad():
            loss_module.value_estimator(data, params=loss_module.critic_network_params,
                                        target_params=loss_module.target_critic_network_params)
        # steps of agents that had already ended (masked out: done, zero observation and reward) move no policy;
        # the critic learns their value target, 0, which is what an ended agent's value is
        live = data["agents", "mask"].unsqueeze(-1)
        data["advantage"] = data["advantage"] * live
        buffer.extend(data.reshape(-1))

        losses = []
        for _ in range(args.epochs):
            for _ in range(args.frames_per_batch // args.minibatch_size):
                values = loss_module(buffer.sample())
                loss = values["loss_objective"] + values["loss_critic"] + values["loss_entropy"]
                loss.backward()
                nn.utils.clip_grad_norm_(loss_module.parameters(), args.max_grad_norm)
                optimiser.step()
                optimiser.zero_grad()
                losses.append(loss.item())
        collector.update_policy_weights_()

        # an agent's episode ended on a step where it was live and is done after it
        ended = data["next", "agents", "done"] & live
        returns = data["next", "agents", "episode_reward"][ended]
        stats = {"iteration": iteration + 1, "frames": data.numel(), "loss": sum(losses) / len(losses),
                 "episodes": int(ended.sum()), "world_resets": int(data["next", "done"].sum()),
                 "trajectories": int(data["collector", "traj_ids"].unique().numel()),
                 "mean_return": returns.mean().item() if returns.numel() else math.nan}
        history.append(stats)
        print(f"iteration {stats['iteration']}: {stats['frames']} frames, loss {stats['loss']:.4f}, "
              f"{stats['episodes']} agent episodes ended, mean return {stats['mean_return']:.3f}", flush=True)
    collector.shutdown()
    return history


if __name__ == "__main__":
    main()
