"""Stable-Baselines3 PPO, parameter-shared, on any bundled HIVEX scenario (one file).

    pip install "hivex-dsl[sb3]"      # install torch==2.13.0 first for the CPU wheel
    python examples/sb3_ppo.py --scenario aerial_wildfire_suppression/main --total-timesteps 20000

Every agent of every world is one SB3 slot (:class:`hivex_dsl.adapters.sb3.SB3VecEnv`: SAME_STEP
autoreset, ``terminal_observation`` in the infos); flat observations and, for the hybrid
environments, one flat Box action (mapping: :mod:`hivex_dsl.adapters.flat`) let SB3's default
``MlpPolicy`` run; ``VecMonitor`` counts per-agent episode returns and lengths (agents that end
alone are respawned, so each agent's episodes are counted as they are).
"""

from __future__ import annotations

import argparse

import torch
from stable_baselines3 import PPO
from stable_baselines3.common.vec_env import VecMonitor

from hivex_dsl.adapters.registration import make_scenario
from hivex_dsl.adapters.sb3 import SB3VecEnv


def parse_args(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--scenario", default="wind_farm_control/main", help="bundled <env>/<name>, or a YAML path")
    p.add_argument("--num-worlds", type=int, default=2)
    p.add_argument("--episode-length", type=int, default=None, help="override the scenario's episode length")
    p.add_argument("--total-timesteps", type=int, default=50_000, help="agent-steps over all slots")
    p.add_argument("--n-steps", type=int, default=256, help="steps per slot per rollout")
    p.add_argument("--seed", type=int, default=1)
    return p.parse_args(argv)


def main(argv=None) -> PPO:
    args = parse_args(argv)
    torch.set_num_threads(1)  # small networks: one thread is fastest on CPU
    scenario = make_scenario(None, args.scenario, max_cycles=args.episode_length)
    venv = VecMonitor(SB3VecEnv(scenario, num_worlds=args.num_worlds))
    model = PPO("MlpPolicy", venv, n_steps=args.n_steps, batch_size=min(256, args.n_steps * venv.num_envs),
                seed=args.seed, verbose=1)
    model.learn(total_timesteps=args.total_timesteps)
    venv.close()
    return model


if __name__ == "__main__":
    main()
