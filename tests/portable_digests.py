"""Digests of what each environment computes, for tests/test_portable_math.py to compare between processors.

    python tests/portable_digests.py ENV [ENV ...]   # one JSON object on stdout: {name: sha256 hex}

Run in a fresh Python whose NumPy takes the kernels of the processor imitated (NPY_DISABLE_CPU_FEATURES). Per
environment, its main scenario's training worlds from two seeds: every state after reset (terrain, forest, maps),
then a uniform random and the scripted policy, each for DECISIONS decisions, every observation, reward, reward term,
global state and the state they end in; the same for :data:`VARIANTS`, params that take other paths. Beside them,
NumPy's own functions that take processor-dependent kernels and :mod:`hivex_dsl.base.portable`'s, on one sample.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import sys
from pathlib import Path
from typing import Any

import numpy as np
import yaml

from hivex_dsl.base import portable
from hivex_dsl.compiler import compile
from hivex_dsl.evaluation.policies import make_policy
from hivex_dsl.runtime.batched import BatchedEnv
from hivex_dsl.runtime.global_state import GlobalState

ROOT = Path(__file__).resolve().parents[1]
DECISIONS = 120
SEEDS = (3, 14)
# params that take another path through the portable functions than the main scenario's: name -> (environment, params)
VARIANTS = {
    "wind_farm_control, the release's wind law": ("wind_farm_control", {"wind_original_law": 1}),
}


def feed(digest: Any, value: Any) -> None:
    """Every array (its dtype, shape and bytes) and number in ``value``, in a fixed order."""
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        for field in dataclasses.fields(value):
            feed(digest, getattr(value, field.name))
    elif isinstance(value, dict):
        for key in sorted(value):
            digest.update(str(key).encode())
            feed(digest, value[key])
    elif isinstance(value, (list, tuple)):
        for item in value:
            feed(digest, item)
    elif isinstance(value, np.ndarray):
        digest.update(f"{value.dtype}{value.shape}".encode())
        digest.update(np.ascontiguousarray(value).tobytes())
    elif isinstance(value, (bool, int, float, np.generic)):
        digest.update(repr(value).encode())


def environment_digest(environment: str, params: dict | None = None) -> str:
    scenario = yaml.safe_load((ROOT / "scenarios" / environment / "main.yaml").read_text(encoding="utf-8"))
    compiled = compile(scenario | {"params": {**scenario.get("params", {}), **(params or {})}})
    core = BatchedEnv(compiled, batch=2, split="train")
    world_state = GlobalState.of(core)
    digest = hashlib.sha256()
    for policy, seed in zip(("random", "scripted"), SEEDS):
        observations = core.reset(seed)
        feed(digest, core.state)
        act = make_policy(policy, compiled, core.sim.action_space, core.shape, seed=seed)
        for _ in range(DECISIONS):
            step = core.step(act(observations))
            feed(digest, (step.observations, step.rewards, step.terms, world_state(core)))
            observations = step.observations
            ended = core.world_endings(step)
            if ended.any():
                core.reset_worlds(ended)
                observations = core.observe()
        feed(digest, core.state)
    return digest.hexdigest()


def function_digests() -> dict[str, str]:
    """NumPy's processor-dependent functions and the portable ones, each on the same sample."""
    rng = np.random.default_rng(0)
    x, y = rng.uniform(0.0, 3.0, 4096), rng.uniform(-4.0, 4.0, 4096)
    results = {"numpy power": x ** 5.0, "numpy exp": np.exp(y), "numpy arctan2": np.arctan2(y, x - 1.5),
               "portable power": portable.power(x, 5.0), "portable exp": portable.exp(y),
               "portable log": portable.log(x), "portable arctan2": portable.arctan2(y, x - 1.5)}
    return {name: hashlib.sha256(values.tobytes()).hexdigest() for name, values in results.items()}


if __name__ == "__main__":
    environments = sys.argv[1:]
    variants = {name: environment_digest(*variant) for name, variant in VARIANTS.items() if variant[0] in environments}
    print(json.dumps({**function_digests(), **{name: environment_digest(name) for name in environments}, **variants}))
