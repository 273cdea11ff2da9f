"""RLlib PPO with one policy shared by every agent, on any bundled HIVEX scenario (one file).

    pip install torch==2.13.0 "hivex-dsl[rllib]"
    python examples/rllib_ppo.py --scenario ocean_plastic_collection/main --iterations 5

RLlib's default models take Box observations and Box/Discrete/MultiDiscrete actions, so the
PettingZoo env is wrapped flat (:mod:`hivex_dsl.adapters.flat`: one Box observation; one Box
action for the hybrid environments). RLlib's multi-agent episodes follow PettingZoo's semantics:
an agent whose episode ends leaves until its world resets. It runs on RLlib's new API stack (RLModule,
Learner, EnvRunner and connectors v2), its default since Ray 2.40; ``main`` refuses the old one.
"""

from __future__ import annotations

import argparse

from ray.rllib.algorithms.ppo import PPOConfig
from ray.rllib.env.wrappers.pettingzoo_env import ParallelPettingZooEnv
from ray.tune.registry import register_env

import hivex_dsl
from hivex_dsl.adapters.flat import FlatParallelEnv
from hivex_dsl.adapters.registration import make_scenario


def parse_args(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--scenario", default="wind_farm_control/main", help="bundled <env>/<name>, or a YAML path")
    p.add_argument("--episode-length", type=int, default=None, help="override the scenario's episode length")
    p.add_argument("--iterations", type=int, default=5, help="PPO training iterations")
    p.add_argument("--batch-size", type=int, default=1000, help="agent-steps per iteration")
    p.add_argument("--seed", type=int, default=1)
    return p.parse_args(argv)


def make_env(config: dict):
    scenario = make_scenario(None, config["scenario"], max_cycles=config.get("episode_length"))
    return ParallelPettingZooEnv(FlatParallelEnv(hivex_dsl.parallel_env(scenario)))


def main(argv=None) -> list[dict]:
    args = parse_args(argv)
    register_env("hivex", make_env)
    config = (
        PPOConfig()
        .environment("hivex", env_config={"scenario": args.scenario, "episode_length": args.episode_length})
        .env_runners(num_env_runners=0)  # step in the driver: one process, no cluster needed
        .multi_agent(policies={"shared"}, policy_mapping_fn=lambda agent_id, *args, **kwargs: "shared")
        .training(train_batch_size=args.batch_size, minibatch_size=min(128, args.batch_size), num_epochs=2)
        .debugging(seed=args.seed)
    )
    if not (config.enable_rl_module_and_learner and config.enable_env_runner_and_connector_v2):
        raise RuntimeError("this example is written for RLlib's new API stack (Ray 2.40 or newer)")
    algo = config.build_algo()
    results = []
    for iteration in range(args.iterations):
        result = algo.train()
        results.append(result)
        episode_return = result.get("env_runners", {}).get("episode_return_mean", float("nan"))
        print(f"iteration {iteration + 1}: mean episode return (all agents) {episode_return}", flush=True)
    algo.stop()
    return results


if __name__ == "__main__":
    main()
