"""The curiosity module's losses on random-play transitions, with the vector observation at its scale or scaled up.

    python benchmarks/curiosity_losses.py drone_based_reforestation [--scale 1 10] [--steps 600] [--decisions 600]
    python benchmarks/curiosity_losses.py ocean_plastic_collection --steps 300 --decisions 150 --set camera_source=blank
    python benchmarks/curiosity_losses.py drone_based_reforestation --scale 1 --noise 0 0.1 0.3 \
        --set vector_observation_gain=1

The module (hivex_dsl.train.curiosity, the environment's default hyperparameters) is trained offline on the
transitions of random play in the main scenario's training worlds (8 worlds; continuous actions drawn from N(0, 1) as
the untrained policy samples them and sent as ML-Agents sends them, clip(a, -3, 3) / 3; each discrete choice uniform
among the open ones), minibatches of 256,
and its forward and inverse losses printed every 100 steps, with each continuous action dimension's share of variance
the inverse model leaves. The original's Curiosity Forward and Inverse Loss panels read beside these (the reward
tables' notes 'The curiosity losses'): how much a decision changes the observation against its scale sets them.
``--noise`` adds Gaussian noise of each standard deviation to every vector frame (a frame keeps its noise when it
moves to the older stack), to ask whether observations the module cannot predict raise its forward loss.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
import torch
import yaml

import hivex_dsl
from hivex_dsl.adapters.gymnasium import HivexVectorEnv
from hivex_dsl.train.config import make_config
from hivex_dsl.train.curiosity import Curiosity
from hivex_dsl.train.networks import ActionLayout

SCENARIOS = Path(__file__).resolve().parents[1] / "scenarios"


def random_transitions(environment: str, params: dict, decisions: int, worlds: int = 8, seed: int = 0):
    """(env, obs, next_obs, continuous actions, discrete actions, entropy) of random play in the main scenario's
    training worlds, the steps that ended an episode left out, observations as dicts of tensors (N, ...). A discrete
    choice is drawn among the open ones where the environment masks (as a masked untrained policy draws it);
    ``entropy`` is the mean entropy of those draws in nats, the discrete inverse loss of a model that sees nothing of
    the action (the original's Entropy panel beside its Curiosity Inverse Loss reads the same gap)."""
    scenario = yaml.safe_load((SCENARIOS / environment / "main.yaml").read_text())
    env = HivexVectorEnv(hivex_dsl.compile(scenario | {"params": params}), num_worlds=worlds)
    layout = ActionLayout.of(env.single_action_space)
    rng = np.random.default_rng(seed)
    obs, infos = env.reset(seed=seed)
    obs = as_dict(obs)
    before, after, conts, discs, entropies = [], [], [], [], []
    for _ in range(decisions):
        cont = rng.normal(size=(env.num_envs, layout.continuous)).astype(np.float32)
        disc = open_choices(rng, layout.nvec, infos.get("action_mask"), env.num_envs)
        entropy = open_entropy(layout.nvec, infos.get("action_mask"), env.num_envs)
        following, _, terminated, truncated, infos = env.step(
            layout.to_env(torch.as_tensor(cont), torch.as_tensor(disc)))
        following = as_dict(following)
        kept = ~(terminated | truncated)
        before.append({k: v[kept] for k, v in obs.items()})
        after.append({k: v[kept] for k, v in following.items()})
        conts.append(cont[kept])
        discs.append(disc[kept])
        entropies.append(entropy[kept])
        obs = following
    return env, joined(before), joined(after), torch.as_tensor(np.concatenate(conts)), \
        torch.as_tensor(np.concatenate(discs)), float(np.concatenate(entropies).mean())


def as_dict(observations) -> dict[str, np.ndarray]:
    """A vector env's observations keyed as the trainer keys them: a Box's array as "obs" (Wildfire Resource
    Management), a Dict's arrays by their own keys ("vector", "visual")."""
    return observations if isinstance(observations, dict) else {"obs": observations}


def vector_key(obs: dict) -> str:
    """The key of the vector observation: "vector" in a Dict space, "obs" for a Box."""
    return "vector" if "vector" in obs else "obs"


def joined(frames: list[dict]) -> dict[str, torch.Tensor]:
    """Per-step observation dicts -> one dict of tensors, the steps' rows one after another."""
    return {k: torch.as_tensor(np.concatenate([f[k] for f in frames])) for k in frames[0]}


def open_choices(rng: np.random.Generator, nvec, mask: np.ndarray | None, slots: int) -> np.ndarray:
    """(slots, branches) int64: each branch's choice uniform among its open ones (all open without a mask)."""
    columns, start = [], 0
    for n in nvec:
        allowed = np.ones((slots, n), bool) if mask is None else np.asarray(mask, bool)[:, start:start + n]
        weights = allowed / allowed.sum(axis=1, keepdims=True)
        columns.append((weights.cumsum(axis=1) > rng.random((slots, 1))).argmax(axis=1))
        start += n
    return np.stack(columns, axis=1).astype(np.int64) if columns else np.zeros((slots, 0), np.int64)


def open_entropy(nvec, mask: np.ndarray | None, slots: int) -> np.ndarray:
    """(slots,) the entropy in nats of :func:`open_choices`' draw: the sum over branches of log(open choices)."""
    if mask is None:
        return np.full(slots, float(np.log(np.asarray(nvec, float)).sum()))
    counts = np.add.reduceat(np.asarray(mask, bool).astype(np.int64), np.cumsum([0, *nvec[:-1]]), axis=1)
    return np.log(counts).sum(axis=1)


def with_noise(obs: dict, following: dict, sigma: float, stacks: int = 2, seed: int = 1) -> tuple[dict, dict]:
    """The transitions with N(0, sigma) noise on each vector frame (N, stacks x frame, newest first; two stacks, as
    the camera environments observe): the newest frame of ``obs`` carries the same noise as the older stack of
    ``following`` (one frame, observed twice), and an older stack of zeros (a first observation's) stays zeros."""
    if stacks != 2:
        raise ValueError(f"with_noise takes two stacks, not {stacks}")
    key = vector_key(obs)
    vector, later = obs[key].clone(), following[key].clone()
    frame = vector.shape[1] // stacks
    gen = torch.Generator().manual_seed(seed)
    older, shared, newest = (torch.randn(len(vector), frame, generator=gen) * sigma for _ in range(3))
    vector[:, frame:] += older * vector[:, frame:].abs().sum(1, keepdim=True).gt(0)
    vector[:, :frame] += shared
    later[:, frame:] += shared
    later[:, :frame] += newest
    return {**obs, key: vector}, {**following, key: later}


def train_module(environment, env, obs, following, cont, disc, scale: float, steps: int) -> None:
    """Train a fresh module (torch seed 0) on the transitions with the vector observation times ``scale``; print."""
    torch.manual_seed(0)
    cfg = make_config(environment)
    module = Curiosity(env.single_observation_space, ActionLayout.of(env.single_action_space), cfg)
    optimizer = torch.optim.Adam(module.parameters(), lr=cfg.curiosity_learning_rate)
    key = vector_key(obs)
    scaled = [{**o, key: o[key] * scale} for o in (obs, following)]
    for step in range(steps + 1):
        rows = torch.randint(0, len(disc), (256,))
        total, forward, inverse = module.loss(*({k: v[rows] for k, v in o.items()} for o in scaled), cont[rows], disc[rows])
        optimizer.zero_grad()
        total.backward()
        optimizer.step()
        if step % 100 == 0:
            print(f"scale {scale:g} step {step}: forward {float(forward):.4f} inverse {float(inverse):.3f}"
                  f"{left_variance(module, scaled, cont)}", flush=True)


def left_variance(module: Curiosity, scaled: list[dict], cont: torch.Tensor) -> str:
    """Each continuous action dimension's mean squared error of the inverse model over its variance ('' without)."""
    if cont.shape[1] == 0:
        return ""
    with torch.no_grad():
        predicted = module.inverse_model(torch.cat([module._encode(scaled[0]), module._encode(scaled[1])], dim=1))
        share = (predicted[:, :cont.shape[1]] - cont).square().mean(0) / cont.var(0)
    return "; continuous variance left " + " ".join(f"{s:.2f}" for s in share.tolist())


def scenario_params(items: list[str]) -> dict:
    """``--set`` items (PARAM=VALUE) as a scenario's params, each value read as YAML reads it (18 a number, blank a
    string), so a numeric param passes the scenario's checks."""
    pairs = [item.split("=", 1) for item in items]
    return {key: yaml.safe_load(value) for key, value in pairs}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("environment", choices=["drone_based_reforestation", "ocean_plastic_collection",
                                                "wildfire_resource_management"])
    parser.add_argument("--scale", type=float, nargs="+", default=[1.0, 10.0])
    parser.add_argument("--steps", type=int, default=600)
    parser.add_argument("--decisions", type=int, default=600)
    parser.add_argument("--noise", type=float, nargs="+", default=[0.0], metavar="SIGMA",
                        help="Gaussian noise's standard deviation on every vector frame (each in turn)")
    parser.add_argument("--set", action="append", default=[], metavar="PARAM=VALUE", help="a scenario param")
    args = parser.parse_args()
    torch.set_num_threads(1)
    params = scenario_params(args.set)
    env, obs, following, cont, disc, entropy = random_transitions(args.environment, params, args.decisions)
    if disc.shape[1]:
        print(f"the random draws' entropy {entropy:.3f} nats: the discrete inverse loss of a model that sees nothing "
              "of the action")
    print(f"{len(disc)} transitions; vector observation's change a decision, std by component: "
          + " ".join(f"{v:.4f}" for v in (following[vector_key(obs)] - obs[vector_key(obs)]).std(0).tolist()))
    for sigma in args.noise:
        noisy = with_noise(obs, following, sigma, env.core.sim.observation_stacks) if sigma > 0 else (obs, following)
        if len(args.noise) > 1:
            print(f"noise {sigma:g}")
        for scale in args.scale:
            train_module(args.environment, env, *noisy, cont, disc, scale, args.steps)


if __name__ == "__main__":
    main()
