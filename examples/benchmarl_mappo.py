"""BenchMARL MAPPO (or IPPO with --ippo) on any HIVEX environment and task (one file).

    pip install torch==2.13.0 "hivex-dsl[benchmarl]"      # the torch pin keeps pip from pulling another torch
    python examples/benchmarl_mappo.py --env ocean_plastic_collection --task group_up --episode-length 300 --iterations 20

The tasks ship in the package (:mod:`hivex_dsl.adapters.benchmarl`): one BenchMARL ``Task`` enum per environment,
one member per task of its reward table (``OceanPlasticCollectionTask.GROUP_UP``...), whose env is TorchRL's
``PettingZooWrapper`` over one world with flat observations, WRM's and OPC's MultiDiscrete actions as one joint
Discrete action and DBR's and AWS's hybrid actions as one Box(-1, 1). BenchMARL batches
``--envs`` copies (a SerialEnv), runs its MAPPO with MLP actor and critic, and logs to ``--folder``. MAPPO's
centralised critic reads the world's global state (every agent's observation and the world's facts no agent
observes). A callback keeps what each iteration
collected and its losses, which ``main`` returns.
"""

from __future__ import annotations

import argparse
import math
import tempfile

import torch
from benchmarl.algorithms import IppoConfig, MappoConfig
from benchmarl.experiment import Callback, Experiment, ExperimentConfig
from benchmarl.models import MlpConfig

from hivex_dsl.adapters.benchmarl import task as hivex_task


def parse_args(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--env", default="wind_farm_control", help="a HIVEX environment")
    p.add_argument("--task", default=None, help="one of its tasks (default: its main scenario's)")
    p.add_argument("--scenario", default=None, help="a bundled scenario's name or a YAML path (default: main)")
    p.add_argument("--episode-length", type=int, default=None, help="override the scenario's episode length")
    p.add_argument("--iterations", type=int, default=10, help="collection + PPO update rounds")
    p.add_argument("--envs", type=int, default=2, help="copies of the world collected from")
    p.add_argument("--frames-per-batch", type=int, default=600, help="env steps (every agent acts) per iteration")
    p.add_argument("--minibatch-size", type=int, default=200)
    p.add_argument("--epochs", type=int, default=4, help="passes over each batch")
    p.add_argument("--hidden", type=int, default=64, help="units of each of the two hidden layers")
    p.add_argument("--lr", type=float, default=3e-4)
    p.add_argument("--ippo", action="store_true", help="a critic per agent's own observation instead of MAPPO's")
    p.add_argument("--evaluate", action="store_true", help="BenchMARL's evaluation rollouts after iterations")
    p.add_argument("--folder", default=None, help="where BenchMARL writes its CSV logs (default: a temporary one)")
    p.add_argument("--seed", type=int, default=0)
    return p.parse_args(argv)


class Progress(Callback):
    """What each iteration collected and its mean losses, printed and kept."""

    def __init__(self):
        super().__init__()
        self.history: list[dict] = []

    def on_batch_collected(self, batch):
        # an agent's episode ended on a step where it was live (mask) and is done after it
        ended = batch["next", "agents", "done"] & batch["agents", "mask"].unsqueeze(-1)
        returns = batch["next", "agents", "episode_reward"][ended]
        self.history.append({"iteration": len(self.history) + 1, "frames": batch.numel(),
                             "episodes": int(ended.sum()), "world_resets": int(batch["next", "done"].sum()),
                             "trajectories": int(batch["collector", "traj_ids"].unique().numel()),
                             "mean_return": returns.mean().item() if returns.numel() else math.nan})

    def on_train_end(self, training_td, group):
        stats = self.history[-1]
        for name in ("loss_objective", "loss_critic", "loss_entropy"):
            stats[name] = training_td[name].mean().item()
        print(f"iteration {stats['iteration']}: {stats['frames']} frames, {stats['episodes']} agent episodes "
              f"ended, mean return {stats['mean_return']:.3f}, critic loss {stats['loss_critic']:.4f}", flush=True)


def main(argv=None) -> list[dict]:
    args = parse_args(argv)
    torch.set_num_threads(1)  # small networks: one thread is fastest on CPU

    task = hivex_task(args.env, args.task, scenario=args.scenario, max_cycles=args.episode_length)

    config = ExperimentConfig.get_from_yaml()  # BenchMARL's defaults, then a small run's sizes
    config.max_n_iters, config.max_n_frames = args.iterations, None
    config.on_policy_collected_frames_per_batch = args.frames_per_batch
    config.on_policy_n_envs_per_worker = args.envs
    config.on_policy_minibatch_size = args.minibatch_size
    config.on_policy_n_minibatch_iters = args.epochs
    config.lr = args.lr
    config.evaluation = args.evaluate
    config.evaluation_interval = args.frames_per_batch * max(1, args.iterations // 2)
    config.evaluation_episodes = 1
    config.render = False
    config.loggers = ["csv"]
    config.create_json = False
    config.checkpoint_interval = 0
    config.save_folder = args.folder or tempfile.mkdtemp(prefix="benchmarl_")

    model = MlpConfig.get_from_yaml()
    model.num_cells = [args.hidden, args.hidden]
    algorithm = (IppoConfig if args.ippo else MappoConfig).get_from_yaml()

    progress = Progress()
    experiment = Experiment(task=task, algorithm_config=algorithm, model_config=model, critic_model_config=model,
                            seed=args.seed, config=config, callbacks=[progress])
    experiment.run()
    print(f"{experiment.total_frames} frames in {experiment.n_iters_performed} iterations; logs in "
          f"{experiment.folder_name}")
    return progress.history


if __name__ == "__main__":
    main()
