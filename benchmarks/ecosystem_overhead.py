"""What each library integration costs: agent-steps/s of the raw vector env and, on the same worlds, of each integration.

    python benchmarks/ecosystem_overhead.py [--env ID ...] [--steps 500] [--worlds 1] [--repeats 3]
                                            [--episode-length 50] [-o benchmarks/results/ecosystem.json]

Per environment (its main scenario, with --episode-length decisions per episode so resets are in) it builds the raw
vector env (``hivex_dsl.vector_env``) and every integration that is installed, each over --worlds worlds:

- ``parallel``: the PettingZoo parallel env (``hivex_dsl.parallel_env``), one per world, stepped in turn;
- ``flat``: the flat view of the vector env (``hivex_dsl.adapters.flat.flat_vector_env``);
- ``supersuit``: ``supersuit.pettingzoo_env_to_vec_env_v1`` over the flat parallel env (``respawn=True``),
  concatenated with ``concat_vec_envs_v1`` for several worlds;
- ``sb3``: Stable-Baselines3's VecEnv (``hivex_dsl.adapters.sb3.SB3VecEnv``);
- ``torchrl``: TorchRL's wrapper (``hivex_dsl.adapters.torchrl.torchrl_env``), one per world, each ``rollout``.

Each steps --steps decisions of random actions, drawn before the clock starts (TorchRL's rollout draws its own, as
it does in use); the runs are interleaved, --repeats rounds, and each keeps its best round (the least disturbed
by other work on the machine). A rate counts agent-steps (the parallel env counts the agents still playing); an
integration's ratio is its rate over the raw env's. BLAS and OpenMP run one thread, as `hivex bench` measures.
The report (machine, date, settings, versions, rates, ratios, what was skipped) feeds docs/ecosystem.md.
"""

from __future__ import annotations

import os

if __name__ == "__main__":  # one thread, as `hivex bench` measures: set before NumPy loads
    for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "NUMEXPR_NUM_THREADS"):
        os.environ.setdefault(_var, "1")

import argparse
import datetime
import importlib.metadata
import importlib.util
import json
import platform
import time
from pathlib import Path
from typing import Callable

import numpy as np

import hivex_dsl
from hivex_dsl.compiler import registry
from hivex_dsl.adapters.registration import make_scenario

OUT = Path(__file__).resolve().parent / "results" / "ecosystem.json"
BANK = 16  # distinct random action batches, cycled
WARMUP = 3  # untimed decisions after building each runner
# key -> (the module it needs, or None; its column title; what it measures)
INTEGRATIONS = {
    "parallel": (None, "PettingZoo parallel env", "`hivex_dsl.parallel_env`, one per world, stepped in turn"),
    "flat": (None, "flat view", "`flat_vector_env(hivex_dsl.vector_env(...))`"),
    "supersuit": ("supersuit", "SuperSuit",
                  "`supersuit.pettingzoo_env_to_vec_env_v1(FlatParallelEnv(parallel_env(..., respawn=True)))`, "
                  "`concat_vec_envs_v1` over several worlds"),
    "sb3": ("stable_baselines3", "SB3 VecEnv", "`hivex_dsl.adapters.sb3.SB3VecEnv` (flat, SAME_STEP autoreset)"),
    "torchrl": ("torchrl", "TorchRL rollout",
                "`hivex_dsl.adapters.torchrl.torchrl_env`, one per world, each `rollout(steps)` with TorchRL's "
                "random actions"),
}
Runner = Callable[[int], int]  # run(decisions) -> agent-steps taken


def _vector_runner(env, bank: list) -> Runner:
    """Steps a Gymnasium-style vector env (autoresetting) through the action bank; every slot is an agent-step."""

    def run(steps: int) -> int:
        for t in range(steps):
            env.step(bank[t % BANK])
        return steps * env.num_envs

    return run


def _slot_bank(space, slots: int) -> list:
    """BANK batches of ``slots`` actions of one slot's ``space`` (SB3's and SuperSuit's spaces are one slot's)."""
    space.seed(0)
    return [np.stack([space.sample() for _ in range(slots)]) for _ in range(BANK)]


def raw(compiled, worlds: int) -> Runner:
    """The raw vector env."""
    env = hivex_dsl.vector_env(compiled, num_worlds=worlds)
    env.reset(seed=0)
    env.action_space.seed(0)
    return _vector_runner(env, [env.action_space.sample() for _ in range(BANK)])


def flat(compiled, worlds: int) -> Runner:
    """The flat view of the vector env."""
    from hivex_dsl.adapters.flat import flat_vector_env

    env = flat_vector_env(hivex_dsl.vector_env(compiled, num_worlds=worlds))
    env.reset(seed=0)
    env.action_space.seed(0)
    return _vector_runner(env, [env.action_space.sample() for _ in range(BANK)])


def parallel(compiled, worlds: int) -> Runner:
    """One PettingZoo parallel env per world, stepped in turn, each reset when its world ends."""
    envs = [hivex_dsl.parallel_env(compiled) for _ in range(worlds)]
    for i, env in enumerate(envs):
        env.reset(seed=i)
    agents = envs[0].possible_agents
    space = envs[0].action_space(agents[0])
    space.seed(0)
    bank = [{agent: space.sample() for agent in agents} for _ in range(BANK)]

    def run(steps: int) -> int:
        count = 0
        for t in range(steps):
            for env in envs:
                count += len(env.agents)
                env.step(bank[t % BANK])  # an action for an agent that left is ignored
                if not env.agents:
                    env.reset()
        return count

    return run


def supersuit(compiled, worlds: int) -> Runner:
    """SuperSuit's vector conversion of the flat parallel env (concatenated copies for several worlds)."""
    import supersuit as ss

    from hivex_dsl.adapters.flat import FlatParallelEnv

    env = ss.pettingzoo_env_to_vec_env_v1(FlatParallelEnv(hivex_dsl.parallel_env(compiled, respawn=True)))
    if worlds > 1:
        env = ss.concat_vec_envs_v1(env, worlds, base_class="gymnasium")
    env.reset(seed=0)
    return _vector_runner(env, _slot_bank(env.action_space, env.num_envs))


def sb3(compiled, worlds: int) -> Runner:
    """Stable-Baselines3's VecEnv."""
    from hivex_dsl.adapters.sb3 import SB3VecEnv

    env = SB3VecEnv(compiled, num_worlds=worlds)
    env.seed(0)
    env.reset()
    return _vector_runner(env, _slot_bank(env.action_space, env.num_envs))


def torchrl(compiled, worlds: int) -> Runner:
    """TorchRL's wrapper, one per world, each rolled out with TorchRL's own random actions."""
    import torch

    from hivex_dsl.adapters.torchrl import torchrl_env

    torch.set_num_threads(1)
    envs = [torchrl_env(compiled, seed=i) for i in range(worlds)]
    agents = len(hivex_dsl.parallel_env(compiled).possible_agents)

    def run(steps: int) -> int:
        for env in envs:
            env.rollout(steps, break_when_any_done=False)
        return steps * agents * worlds

    return run


BUILDERS = {"parallel": parallel, "flat": flat, "supersuit": supersuit, "sb3": sb3, "torchrl": torchrl}


def available(keys: list[str]) -> tuple[list[str], dict[str, str]]:
    """The integrations among ``keys`` whose library is installed, and why each other one is skipped."""
    ready, skipped = [], {}
    for key in keys:
        module = INTEGRATIONS[key][0]
        if module is None or importlib.util.find_spec(module) is not None:
            ready.append(key)
        else:
            skipped[key] = f"{module} is not installed"
    return ready, skipped


def measure(env_id: str, keys: list[str], steps: int, worlds: int, repeats: int, episode_length: int) -> dict:
    """One environment: the best agent-steps/s of the raw env and each integration over interleaved rounds."""
    compiled = make_scenario(env_id, "main", max_cycles=episode_length)
    runners = {"raw": raw(compiled, worlds)} | {key: BUILDERS[key](compiled, worlds) for key in keys}
    best = dict.fromkeys(runners, 0.0)
    for run in runners.values():
        run(WARMUP)
    for _ in range(repeats):
        for key, run in runners.items():
            start = time.perf_counter()
            taken = run(steps)
            best[key] = max(best[key], taken / (time.perf_counter() - start))
    return {"environment": env_id, "agents": len(hivex_dsl.parallel_env(compiled).possible_agents),
            "raw_agent_steps_per_s": best["raw"],
            "integrations": {key: {"agent_steps_per_s": best[key], "ratio": best[key] / best["raw"]} for key in keys}}


def machine() -> str:
    """The machine in words: processor, cores, OS, Python."""
    processor = platform.processor() or platform.machine()
    return f"{processor}, {os.cpu_count()} cores, {platform.system()}, Python {platform.python_version()}"


def versions(keys: list[str]) -> dict[str, str]:
    """Versions of NumPy, hivex-dsl and the measured libraries (and torch, under TorchRL)."""
    names = ["numpy", "hivex-dsl", "gymnasium", "pettingzoo"] + [INTEGRATIONS[k][0] for k in keys if INTEGRATIONS[k][0]]
    names += ["torch"] * ("torchrl" in keys)
    found = {}
    for name in names:
        try:
            found[name] = importlib.metadata.version(name)
        except importlib.metadata.PackageNotFoundError:
            pass
    return found


def run_all(env_ids: list[str], keys: list[str], steps: int, worlds: int, repeats: int, episode_length: int,
            progress: Callable[[str], None] = lambda _: None) -> dict:
    """The whole report over ``env_ids`` for the installed integrations among ``keys``."""
    ready, skipped = available(keys)
    results = []
    for env_id in env_ids:
        progress(env_id)
        results.append(measure(env_id, ready, steps, worlds, repeats, episode_length))
    return {"machine": machine(), "date": datetime.date.today().isoformat(), "steps": steps, "worlds": worlds,
            "repeats": repeats, "episode_length": episode_length, "threads": 1, "versions": versions(ready),
            "integrations": {k: {"label": INTEGRATIONS[k][1], "what": INTEGRATIONS[k][2]} for k in ready},
            "skipped": skipped, "results": results}


def format_table(report: dict) -> str:
    """The report's rates and ratios, one line per environment."""
    keys = list(report["integrations"])
    lines = [f"{'environment':<30} {'raw/s':>10} " + " ".join(f"{k:>9}" for k in keys)]
    for r in report["results"]:
        ratios = " ".join(f"{r['integrations'][k]['ratio']:>9.2f}" for k in keys)
        lines.append(f"{r['environment']:<30} {r['raw_agent_steps_per_s']:>10,.0f} {ratios}")
    lines += [f"skipped {k}: {why}" for k, why in report["skipped"].items()]
    return "\n".join(lines)


def parse_args(argv=None) -> argparse.Namespace:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--env", action="append", choices=list(registry.environments()),
                   help="an environment to measure (repeat for several; default all)")
    p.add_argument("--integration", action="append", choices=list(INTEGRATIONS),
                   help="an integration to measure (repeat for several; default all that are installed)")
    p.add_argument("--steps", type=int, default=500, help="decisions per run (default 500)")
    p.add_argument("--worlds", type=int, default=1, help="worlds every env steps at once (default 1)")
    p.add_argument("--repeats", type=int, default=3, help="interleaved rounds, the best kept (default 3)")
    p.add_argument("--episode-length", type=int, default=50, help="decisions per world episode (default 50)")
    p.add_argument("-o", "--output", type=Path, default=OUT, help=f"the JSON report (default {OUT.name} in results/)")
    return p.parse_args(argv)


def main(argv=None) -> dict:
    args = parse_args(argv)
    report = run_all(args.env or list(registry.environments()), args.integration or list(INTEGRATIONS), args.steps,
                     args.worlds, args.repeats, args.episode_length, progress=lambda e: print(e, flush=True))
    args.output.parent.mkdir(parents=True, exist_ok=True)
    args.output.write_text(json.dumps(report, indent=2) + "\n", encoding="utf-8")
    print(format_table(report))
    print(f"wrote {args.output}")
    return report


if __name__ == "__main__":
    main()
