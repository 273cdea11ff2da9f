"""Throughput of every environment's main scenario on one core, against PettingZoo's MPE.

Each measurement runs in a fresh Python process with the BLAS/OpenMP thread counts set to 1
(they must be set before NumPy loads), so the figures are one core's and the peak resident
memory is that measurement's own. Random actions are drawn in blocks with NumPy for us and for
the reference alike, so action sampling costs the same on both sides; resets are included. A
ParallelEnv run then times its API floor for as long again (see :func:`replay_one_step`).
"""

from __future__ import annotations

import json
import os
import platform
import resource
import statistics
import subprocess
import sys
import time
from dataclasses import asdict, dataclass
from typing import Any, Optional

import numpy as np

ONE_CORE = {name: "1" for name in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS",
                                   "NUMEXPR_NUM_THREADS", "VECLIB_MAXIMUM_THREADS")}
REFERENCE = "mpe2.simple_spread_v3"
RESULTS_FILE = "benchmarks/results/latest.json"
# Targets on one core: ParallelEnv (batch 1) env-steps/s and vector env (batch 256) agent-steps/s.
TARGETS = {
    "wind_farm_control": {"parallel": 20_000, "vector": 1_000_000},
    "wildfire_resource_management": {"parallel": 5_000, "vector": 100_000},
    "ocean_plastic_collection": {"parallel": 5_000, "vector": 200_000},
    "drone_based_reforestation": {"parallel": 5_000, "vector": 200_000},
    "aerial_wildfire_suppression": {"parallel": 2_000, "vector": 30_000},
}
MEMORY_LIMIT_MB = 2_048
ACTION_BLOCK = 256  # random actions are drawn this many steps at a time


@dataclass(frozen=True)
class Measurement:
    """One timed run: steps of the environment, and of all its agents, per second."""

    target: str  # environment id or REFERENCE
    adapter: str  # "parallel" (batch 1) or "vector"
    batch: int
    agents: int
    env_steps_per_s: float
    agent_steps_per_s: float
    peak_memory_mb: float
    # parallel only: microseconds per step of the same loop with the environment's own work replayed
    # (see replay_one_step): the environment's own work costs the step time minus this
    api_floor_us: Optional[float] = None


def _peak_memory_mb() -> float:
    peak_kb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss  # kilobytes on Linux
    return peak_kb / 1024.0


def _timed(step, reset, seconds: float) -> tuple[int, float]:
    """(steps, elapsed seconds) of stepping for about ``seconds`` after one untimed warm-up step.

    ``reset(seed)`` is called once with seed 0 (untimed), then with None whenever ``step`` returns
    False (the episode is over): those resets continue the seed stream, as in training, and are timed.
    """
    reset(0)
    step()
    steps, start = 0, time.perf_counter()
    while time.perf_counter() - start < seconds:
        for _ in range(64):
            if not step():
                reset(None)
            steps += 1
    return steps, time.perf_counter() - start


def _live_only(actions: dict, live: list) -> dict:
    """The actions of the agents still playing (all of them on most steps: then the dict as it is)."""
    if len(live) == len(actions):
        return actions
    playing = set(live)
    return {a: x for a, x in actions.items() if a in playing}


def bench_scenario(env_id: str):
    """The environment's bundled main scenario, its cameras drawn where it has them (``camera_images: rendered``):
    the blank default skips the drawing, so the benchmark times the costlier path a researcher may ask for."""
    from ..adapters.registration import make_scenario
    from ..compiler import compile

    compiled = compile(f"{env_id}/main")
    if "camera_images" not in type(compiled.params).model_fields:
        return compiled
    return make_scenario(env_id, "main", params={"camera_images": "rendered"})  # the main files set no params


def measure_parallel(env_id: str, seconds: float) -> Measurement:
    """PettingZoo ParallelEnv (batch 1) of the environment's bundled main scenario, random actions; then
    the same loop with the environment's work replayed (:func:`replay_one_step`) for ``api_floor_us``."""
    from ..adapters.factory import parallel_env
    from ..sim.spaces import stack_agent_actions
    from .policies import random_policy

    compiled = bench_scenario(env_id)
    env = parallel_env(compiled)
    names = list(env.possible_agents)
    draw = random_policy(env.core.sim.action_space, (ACTION_BLOCK, len(names)), np.random.default_rng(0))
    block = {"actions": None, "at": ACTION_BLOCK}

    def next_actions() -> dict:
        if block["at"] == ACTION_BLOCK:
            block["actions"], block["at"] = draw(None), 0
        t, block["at"] = block["at"], block["at"] + 1
        acts = block["actions"]
        if isinstance(acts, dict):
            rows = [{k: v[t, i] for k, v in acts.items()} for i in range(len(names))]
        else:
            rows = list(acts[t])
        return _live_only(dict(zip(names, rows)), env.agents)

    def step() -> bool:
        env.step(next_actions())
        return bool(env.agents)

    reset = lambda seed: env.reset(seed=seed)  # noqa: E731
    steps, elapsed = _timed(step, reset, seconds)
    rate = steps / elapsed
    memory = _peak_memory_mb()
    env.reset(seed=0)
    replay_one_step(env, stack_agent_actions(env.core.sim.action_space, next_actions(), names))
    floor_steps, floor_elapsed = _timed(step, reset, seconds)
    return Measurement(env_id, "parallel", 1, len(names), rate, rate * len(names), memory,
                       api_floor_us=floor_elapsed / floor_steps * 1e6)


class _ReplayedSimulator:
    """A simulator that returns one recorded step's state, outcome and observations whatever it is asked."""

    def __init__(self, sim: Any, state: Any, outcome: Any, observations: Any):
        self.agents, self.action_meanings, self.render_fps = sim.agents, sim.action_meanings, sim.render_fps
        self.observation_space, self.action_space = sim.observation_space, sim.action_space
        self.state, self.outcome, self.observations = state, outcome, observations

    def reset(self, rng: np.random.Generator, batch: int) -> Any:
        return self.state

    def reset_where(self, state: Any, mask: np.ndarray, rng: np.random.Generator) -> Any:
        return self.state

    def step(self, state: Any, actions: Any, rng: np.random.Generator) -> tuple[Any, Any]:
        return self.state, self.outcome

    def observe(self, state: Any) -> Any:
        return self.observations


class _ReplayedComposer:
    """A reward composer that returns one recorded step's rewards and term values whatever it is asked; the rest
    of the real composer (its weights, active terms, clock) stays readable, as the runtime reads it every step
    (the running-mean statistics weigh the terms with ``weights``)."""

    def __init__(self, composer: Any, rewards: np.ndarray, terms: dict):
        self._composer, self._rewards, self._terms = composer, rewards, terms

    def __call__(self, prev: Any, new: Any, actions: Any, params: Any, shape: tuple) -> tuple[np.ndarray, dict]:
        return self._rewards, self._terms

    def __getattr__(self, name: str) -> Any:
        return getattr(self._composer, name)


def replay_one_step(env: Any, actions: Any) -> None:
    """Make a ParallelEnv's engine replay one real step with (1, agents, ...) ``actions`` from now on.

    Its simulator and reward composer are replaced by stand-ins returning that step's state, outcome,
    observations, rewards and term values (same shapes, names and dtypes), so timing the env measures the
    API layer alone: action checks, the runtime's bookkeeping (clocks, returns, term sums, endings) and
    the per-agent dicts of the parallel API. ``env`` is only good for that afterwards.
    """
    core = env.core
    state, outcome = core.sim.step(core.state, actions, core.rng)
    rewards, terms = core.composer(core.state, state, actions, core.compiled.params, core.shape)
    core.sim = _ReplayedSimulator(core.sim, state, outcome, core.sim.observe(state))
    core.composer = _ReplayedComposer(core.composer, rewards, terms)
    core.state = state


def measure_vector(env_id: str, seconds: float, batch: int) -> Measurement:
    """Gymnasium vector env of ``batch`` worlds (autoreset included), random actions for every slot."""
    from ..adapters.factory import vector_env
    from .policies import random_policy

    compiled = bench_scenario(env_id)
    env = vector_env(compiled, num_worlds=batch)
    draw = random_policy(env.single_action_space, (env.num_envs,), np.random.default_rng(0))

    def step() -> bool:
        env.step(draw(None))
        return True

    steps, elapsed = _timed(step, lambda seed: env.reset(seed=seed), seconds)
    rate = steps / elapsed
    agents = compiled.agents
    return Measurement(env_id, "vector", batch, agents, rate, rate * batch * agents, _peak_memory_mb())


def measure_reference(seconds: float) -> Measurement:
    """PettingZoo MPE simple_spread_v3 (3 agents, 25-step episodes) through its ParallelEnv."""
    from mpe2 import simple_spread_v3

    env = simple_spread_v3.parallel_env(max_cycles=25)
    env.reset(seed=0)
    names = list(env.possible_agents)
    rng = np.random.default_rng(0)
    block = {"actions": None, "at": ACTION_BLOCK}

    def step() -> bool:
        if block["at"] == ACTION_BLOCK:
            block["actions"], block["at"] = rng.integers(0, 5, (ACTION_BLOCK, len(names))), 0
        t, block["at"] = block["at"], block["at"] + 1
        env.step(_live_only(dict(zip(names, block["actions"][t].tolist())), env.agents))
        return bool(env.agents)

    steps, elapsed = _timed(step, lambda seed: env.reset(seed=seed), seconds)
    rate = steps / elapsed
    return Measurement(REFERENCE, "parallel", 1, len(names), rate, rate * len(names), _peak_memory_mb())


def _child(kind: str, target: str, seconds: float, batch: int) -> dict[str, Any]:
    """Run one measurement in a fresh one-core process and return its fields."""
    code = ("import json, sys; from hivex_dsl.evaluation import bench; "
            "print(json.dumps(bench._measure_here(*json.loads(sys.argv[1]))))")
    env = dict(os.environ, **ONE_CORE)
    out = subprocess.run([sys.executable, "-c", code, json.dumps([kind, target, seconds, batch])],
                         env=env, capture_output=True, text=True, check=False)
    if out.returncode != 0:
        raise RuntimeError(f"benchmark {kind} {target} failed:\n{out.stderr.strip()}")
    return json.loads(out.stdout.strip().splitlines()[-1])


def _measure_here(kind: str, target: str, seconds: float, batch: int) -> dict[str, Any]:
    if kind == "parallel":
        return asdict(measure_parallel(target, seconds))
    if kind == "vector":
        return asdict(measure_vector(target, seconds, batch))
    return asdict(measure_reference(seconds))


def reference_available() -> bool:
    try:
        import mpe2  # noqa: F401
    except ImportError:
        return False
    return True


def median_of(runs: list[dict[str, Any]]) -> dict[str, Any]:
    """Median rates and peak memory of repeated runs of one measurement."""
    out = dict(runs[0])
    for key in ("env_steps_per_s", "agent_steps_per_s", "peak_memory_mb", "api_floor_us"):
        if out.get(key) is not None:
            out[key] = statistics.median(r[key] for r in runs)
    out["runs"] = len(runs)
    return out


def machine() -> dict[str, Any]:
    return {"platform": platform.platform(), "processor": platform.processor() or platform.machine(),
            "python": platform.python_version(), "numpy": np.__version__, "cpu_count": os.cpu_count(),
            "threads": 1}


def run_benchmarks(env_ids: list[str], seconds: float, repeats: int, batch: int, reference: bool,
                   progress: Optional[Any] = None) -> dict[str, Any]:
    """Every measurement ``repeats`` times; medians, and each of ours divided by the reference's rate."""
    plan = [("parallel", e) for e in env_ids] + [("vector", e) for e in env_ids]
    if reference:
        plan.append(("reference", REFERENCE))
    results = []
    for kind, target in plan:
        if progress:
            progress(f"{kind} {target}")
        results.append(median_of([_child(kind, target, seconds, batch) for _ in range(repeats)]))
    ref = next((r for r in results if r["target"] == REFERENCE), None)
    for r in results:
        if ref and r["target"] != REFERENCE:
            r["env_steps_vs_reference"] = r["env_steps_per_s"] / ref["env_steps_per_s"]
            r["agent_steps_vs_reference"] = r["agent_steps_per_s"] / ref["agent_steps_per_s"]
        target = TARGETS.get(r["target"], {}).get(r["adapter"])
        if target is not None:
            measured = r["env_steps_per_s"] if r["adapter"] == "parallel" else r["agent_steps_per_s"]
            r["target_rate"] = target
            r["meets_target"] = bool(measured >= target and r["peak_memory_mb"] <= MEMORY_LIMIT_MB)
    return {"machine": machine(), "seconds_per_run": seconds, "repeats": repeats, "results": results}


def _goal(result: dict[str, Any]) -> str:
    if "target_rate" not in result:
        return ""
    return f"{'ok' if result['meets_target'] else 'MISSED'} {result['target_rate'] / 1000:g}k"


def format_table(report: dict[str, Any]) -> str:
    """A fixed-width table of the report's medians."""
    head = f"{'target':<32} {'adapter':<8} {'batch':>5} {'agents':>6} {'env-steps/s':>12} {'agent-steps/s':>14} " \
           f"{'us/step':>8} {'API us':>7} {'peak MB':>8} {'x MPE':>7} {'goal':>10}"
    lines = [head, "-" * len(head)]
    for r in report["results"]:
        ratio = r.get("env_steps_vs_reference") if r["adapter"] == "parallel" else r.get("agent_steps_vs_reference")
        floor = r.get("api_floor_us")
        lines.append(f"{r['target']:<32} {r['adapter']:<8} {r['batch']:>5} {r['agents']:>6} "
                     f"{r['env_steps_per_s']:>12,.0f} {r['agent_steps_per_s']:>14,.0f} {step_us(r):>8,.1f} "
                     f"{'' if floor is None else f'{floor:.1f}':>7} {r['peak_memory_mb']:>8,.0f} "
                     f"{'' if ratio is None else f'{ratio:.1f}':>7} {_goal(r):>10}")
    return "\n".join(lines)


def step_us(result: dict[str, Any]) -> float:
    """Microseconds per (batched) step of a measurement."""
    return 1e6 / result["env_steps_per_s"]
