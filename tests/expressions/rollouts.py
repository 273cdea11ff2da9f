"""Quantity values of short random rollouts, shared by the vocabulary and totality tests."""

from __future__ import annotations

import numpy as np

import hivex_dsl
from hivex_dsl.evaluation.policies import random_policy
from hivex_dsl.sim.reward.vocabulary import QuantityFeed, vocabulary_of
from hivex_dsl.runtime import BatchedEnv


def recorded(env_id: str, extra: dict, steps: int, batch: int = 2, seed: int = 11):
    """(quantities, [(now, before) after each step]) of a random rollout; worlds whose agents all ended restart."""
    compiled = hivex_dsl.compile({"hivex": 1, "environment": env_id, **extra})
    vocabulary = vocabulary_of(env_id)
    quantities = vocabulary.quantities(compiled)
    env = BatchedEnv(compiled, batch=batch)
    feed = QuantityFeed(vocabulary, quantities, env.shape, compiled)
    policy = random_policy(env.sim.action_space, env.shape, np.random.default_rng(3))
    env.reset(seed=seed)
    feed.start(env.state)
    pairs = []
    for _ in range(steps):
        ended = env.step(policy(None)).ended.all(axis=1)
        feed.advance(env.state, {})  # every environment keeps its events in its state
        pairs.append((feed.now, feed.before))
        if ended.any():
            env.reset_worlds(ended)
            feed.start(env.state, ended)
    return quantities, pairs
