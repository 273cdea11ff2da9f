"""Ocean Plastic Collection: how a nearly random policy lives long, and what a trained one decides where (issue 52).

The original's vessel-episodes lived 150-219 decisions at 75,000-125,000 agent-steps of the main task while its
policy's entropy was still 1.58-1.67 (uniform: ln 2 + ln 3 = 1.79) and it collected at random play's pace (Local
over Episode Length 0.49-0.61); this toolkit's seeds lived 51-156 there. Two questions, two modes:

    python benchmarks/opc_early_lives.py policies [--worlds N]
        hand-made policies over N test worlds: uniform play; a brake (throttle less often); a curl (steer one way
        more often); a border reflex (uniform play, but within a band of the border and heading out, steer for the
        centre with probability q). Each row: the policy's mean entropy over the decisions it took, decisions a
        vessel-episode, Local (pebbles collected), pace (pebbles a decision) and return.
    python benchmarks/opc_early_lives.py checkpoint CHECKPOINT [...] [--worlds N]
        a trained policy played (sampling) on N training worlds; its decisions split into 'risky' (within the
        reflex's band of the border, heading out) and the rest: the share, mean entropy, probability of throttle,
        of steering for the centre, and of its likeliest steer.

Everything is seeded (the worlds by the split's seed stream, the policies' draws by --seed), so a row reproduces.
"""

from __future__ import annotations

import argparse
from typing import Callable

import numpy as np

import hivex_dsl
from hivex_dsl.envs.ocean_plastic_collection.scripted import bearing_of, steer_toward
from hivex_dsl.evaluation.rollout import rollout

BAND = 0.2  # the border's band, as a fraction of the half extent (the vector observation's position is position / H)
UNIFORM = (1 / 3, 1 / 3, 1 / 3)
# (name, p(throttle), steer probabilities (noop, right, left) away from the border, reflex band, p(steer home) in it)
POLICIES = (("uniform", 0.5, UNIFORM, 0.0, 0.0),
            ("brake 0.25", 0.25, UNIFORM, 0.0, 0.0),
            ("curl 0.6", 0.5, (0.2, 0.6, 0.2), 0.0, 0.0),
            ("curl 0.8", 0.5, (0.1, 0.8, 0.1), 0.0, 0.0),
            ("reflex 0.1 / 0.8", 0.5, UNIFORM, 0.1, 0.8),
            ("reflex 0.2 / 0.6", 0.5, UNIFORM, 0.2, 0.6),
            ("reflex 0.2 / 0.8", 0.5, UNIFORM, 0.2, 0.8),
            ("reflex 0.3 / 0.9", 0.5, UNIFORM, 0.3, 0.9))


def main_task() -> hivex_dsl.CompiledScenario:
    return hivex_dsl.compile({"hivex": 1, "environment": "ocean_plastic_collection", "task": 0, "agents": 3,
                              "episode_length": 5000, "seeds": {"train": 5000, "test": 6000}})


def risky_and_home(vector: np.ndarray, band: float) -> tuple[np.ndarray, np.ndarray]:
    """vector (A, 12), the newest frame first -> (A,) bool: within ``band`` of the border and heading out; (A,) the
    steer action (0 hold, 1 right, 2 left) that turns for the world's centre."""
    position, direction = vector[:, 0:2], vector[:, 2:4]
    risky = ((np.abs(position) > 1 - band) & (position * direction > 0)).any(-1)
    return risky, steer_toward(bearing_of(direction[None], -position[None]))[0]


def entropy(probabilities: np.ndarray) -> np.ndarray:
    """(..., n) -> (...): each distribution's entropy in nats."""
    return -(probabilities * np.log(np.clip(probabilities, 1e-12, 1.0))).sum(-1)


def draw(rng: np.random.Generator, probabilities: np.ndarray) -> np.ndarray:
    """(A, n) rows that each sum to 1 -> (A,) one choice a row, drawn with ``rng``."""
    return (rng.random(len(probabilities))[:, None] > probabilities.cumsum(-1)).sum(-1)


def hand_made(throttle: float, steer: tuple, band: float, home: float, seed: int) -> Callable:
    """A batched policy (observations (1, A, ...) -> actions (1, A, 2)) that records each decision's entropy."""
    rng, steer = np.random.default_rng(seed), np.asarray(steer)
    reflex = np.eye(3) * home + (1 - np.eye(3)) * (1 - home) / 2  # row k: steer k with p = home, the others evenly

    def act(observations):
        risky, toward = risky_and_home(np.asarray(observations["vector"])[0], band)
        probabilities = np.where(risky[:, None], reflex[toward], steer)
        choice = draw(rng, probabilities)
        act.entropies.extend(entropy(probabilities) + entropy(np.array([throttle, 1 - throttle])))
        return np.stack([(rng.random(len(risky)) < throttle).astype(np.int64), choice], -1)[None]

    act.entropies = []
    return act


def policies(worlds: int, seed: int) -> None:
    compiled = main_task()
    print(f"{'policy':18s} {'entropy':>8s} {'decisions':>10s} {'Local':>7s} {'pace':>6s} {'return':>8s}   "
          f"({worlds} test worlds)")
    for name, throttle, steer, band, home in POLICIES:
        act = hand_made(throttle, steer, band, home, seed)
        played = rollout(compiled, act, worlds, seed=seed)
        decisions = played.lengths / compiled.decision_period
        local = played.statistics["Local Reward"]
        print(f"{name:18s} {np.mean(act.entropies):8.2f} {decisions.mean():10.1f} {local.mean():7.1f} "
              f"{local.sum() / decisions.sum():6.2f} {played.returns.mean():8.1f}", flush=True)


def checkpoint(path: str, worlds: int, seed: int) -> None:
    import torch

    from hivex_dsl.train.checkpoint import load_checkpoint, policy_for
    from hivex_dsl.train.networks import to_tensors

    compiled = main_task()
    agent, rng, rows = policy_for(load_checkpoint(path), compiled), np.random.default_rng(seed), []

    def act(observations):
        tensors = to_tensors({key: np.asarray(value[0], np.float32) for key, value in observations.items()})
        with torch.no_grad():
            _, log_probs = agent._heads(tensors, agent._normalised(tensors))
        throttle, steer = (lp.exp().double().numpy() for lp in log_probs)
        risky, toward = risky_and_home(np.asarray(observations["vector"])[0], BAND)
        rows.extend(zip(risky, entropy(throttle) + entropy(steer), throttle[:, 1],
                        steer[np.arange(len(steer)), toward], steer.max(-1)))
        picks = [draw(rng, p / p.sum(-1, keepdims=True)) for p in (throttle, steer)]
        return np.stack(picks, -1)[None]

    played = rollout(compiled, act, worlds, split="train", seed=seed)
    decisions = played.lengths / compiled.decision_period
    local = played.statistics["Local Reward"]
    table = np.array(rows, dtype=float)
    print(f"{path}: {worlds} training worlds, {decisions.mean():.1f} decisions a vessel-episode, Local "
          f"{local.mean():.1f}, pace {local.sum() / decisions.sum():.2f}, return {played.returns.mean():.1f}")
    for name, where in (("all", np.ones(len(table), bool)), ("risky", table[:, 0] > 0), ("interior", table[:, 0] == 0)):
        part = table[where]
        print(f"  {name:8s} share {where.mean():.3f}  entropy {part[:, 1].mean():.2f}  p(throttle) "
              f"{part[:, 2].mean():.2f}  p(steer home) {part[:, 3].mean():.2f}  "
              f"p(likeliest steer) {part[:, 4].mean():.2f}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("mode", choices=("policies", "checkpoint"))
    parser.add_argument("checkpoints", nargs="*", help="checkpoint files (mode checkpoint)")
    parser.add_argument("--worlds", type=int, default=60, help="worlds (episodes) a row plays (default 60)")
    parser.add_argument("--seed", type=int, default=1, help="the split's seed stream and the policies' draws")
    args = parser.parse_args()
    if args.mode == "policies":
        policies(args.worlds, args.seed)
    elif not args.checkpoints:
        parser.error("mode checkpoint needs at least one checkpoint file")
    else:
        for path in args.checkpoints:
            checkpoint(path, args.worlds, args.seed)


if __name__ == "__main__":
    main()
