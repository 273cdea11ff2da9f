"""Policies used by `hivex run`, `hivex render`, `hivex audit` and the tests: scripted (per environment),
random and all-zeros."""

from __future__ import annotations

from typing import Any, Callable

import numpy as np
from gymnasium import spaces

from ..compiler import CompiledScenario
from ..sim.spaces import placeholder_actions

Policy = Callable[[Any], Any]
POLICIES = ("scripted", "random", "zeros")


def random_policy(space: spaces.Space, shape: tuple[int, int], rng: np.random.Generator) -> Policy:
    """Uniform random actions shaped ``shape + space.shape`` for any Box/Discrete/MultiDiscrete/Dict space."""

    def sample(sub: spaces.Space) -> Any:
        if isinstance(sub, spaces.Dict):
            return {k: sample(s) for k, s in sub.spaces.items()}
        if isinstance(sub, spaces.Discrete):
            return rng.integers(sub.start, sub.start + sub.n, shape)
        if isinstance(sub, spaces.MultiDiscrete):
            return rng.integers(sub.start, sub.start + sub.nvec, shape + sub.nvec.shape)
        if isinstance(sub, spaces.Box):
            return rng.uniform(sub.low, sub.high, shape + sub.shape).astype(sub.dtype)
        raise TypeError(f"no random policy for {sub}")

    return lambda observations: sample(space)


def zeros_policy(space: spaces.Space, shape: tuple[int, int]) -> Policy:
    """The all-zeros action (0 clipped into the space; a Discrete's start) for every agent, every step."""

    def tile(sample: Any) -> Any:
        if isinstance(sample, dict):
            return {k: tile(v) for k, v in sample.items()}
        return np.broadcast_to(sample, shape + sample.shape)

    actions = tile(placeholder_actions(space))
    return lambda observations: actions


def decide(act: Policy, observations: Any, core: Any) -> Any:
    """``act``'s actions for ``observations`` of the :class:`~hivex_dsl.runtime.BatchedEnv` ``core``: a policy with a
    true ``takes_action_mask`` attribute (a trained network's) is given the environment's action mask, (batch, agents,
    N) int8 or None, as its second argument; the others see the observations alone."""
    if getattr(act, "takes_action_mask", False):
        return act(observations, core.action_mask())
    return act(observations)


def in_float64(observations: Any) -> Any:
    """``observations`` (an array or a dict of them) with every float32 array as float64, for the scripted
    policies. Their trigonometry on float32 differed by CPU: numpy's float32 arctan2 is not correctly rounded
    (16% of random angles on an AVX2 machine) and takes another SIMD path on AVX-512 ones, and a last-bit
    difference near a threshold flips a hold-or-turn decision (WFC's scripted return moved by 3.5e-5 between
    two machines). In float64 a last bit is 5e8 times smaller (2.2e-16 against 1.2e-7), and the policies take
    their angles from :func:`hivex_dsl.base.portable.arctan2`, libm's on every processor, where NumPy's float64
    arctan2 differs too."""
    if isinstance(observations, dict):
        return {key: in_float64(value) for key, value in observations.items()}
    if isinstance(observations, np.ndarray) and observations.dtype == np.float32:
        return observations.astype(np.float64)
    return observations


def make_policy(name: str, compiled: CompiledScenario, space: spaces.Space, shape: tuple[int, int],
                seed: int = 0) -> Policy:
    """A batched policy: observations (batch, agents, ...) -> actions (batch, agents, ...)."""
    if name == "scripted":
        scripted = compiled.entry.scripted_policy(compiled)
        return lambda observations: scripted(in_float64(observations))
    if name == "random":
        return random_policy(space, shape, np.random.default_rng(seed))
    if name == "zeros":
        return zeros_policy(space, shape)
    raise ValueError(f"unknown policy {name!r}; expected one of {', '.join(POLICIES)}")
