"""``value_loss``: ``unclipped`` is the plain squared error, what ML-Agents release_20 computes; ``clipped`` (the
trust region as ML-Agents' code means it) holds each estimate within epsilon of the one its experience was gathered
with and takes the larger error, so an estimate moved past that toward its return gets no gradient."""

from __future__ import annotations

import pytest
import torch
from gymnasium import spaces
from hypothesis import given, settings
from hypothesis import strategies as st

from hivex_dsl.compiler import compile
from hivex_dsl.train.checkpoint import older_defaults
from hivex_dsl.train.config import PPOConfig
from hivex_dsl.train.ppo import ppo_loss

from .conftest import short_scenario, weights_under_each


class Critic:
    """Zero log-probabilities and entropy; the values given, as a leaf whose gradient the test reads."""

    def __init__(self, values: list[float]):
        self.values = torch.tensor(values, requires_grad=True)

    def evaluate(self, obs, cont, disc, mask=None):
        return torch.zeros(len(self.values)), torch.zeros(len(self.values)), self.values


# old estimates 0 and 0; returns 5 and -1; new estimates 3 (moved past epsilon toward its return) and -0.1 (within)
MINIBATCH = {"obs": {}, "cont": None, "disc": None, "old_logp": torch.zeros(2), "adv": torch.zeros(2),
             "old_values": torch.zeros(2), "returns": torch.tensor([5.0, -1.0])}


def test_clipped_holds_each_estimate_within_epsilon_of_its_old_one():
    critic = Critic([3.0, -0.1])
    loss, (_, value_loss, *_) = ppo_loss(critic, MINIBATCH, beta=0.0, epsilon=0.2)
    # by hand: sample 1 max((5 - 3)^2, (5 - 0.2)^2) = 23.04 (the clipped term: no gradient); sample 2 within the
    # region, (-1 + 0.1)^2 = 0.81 either way; the mean 11.925, and the loss 0.5 x that
    assert float(value_loss.detach()) == pytest.approx((23.04 + 0.81) / 2)
    loss.backward()
    # d(0.5 x mean)/dV: 0 for the clipped sample, 0.5 x 2 (-0.1 + 1) / 2 = 0.45 for the other
    assert critic.values.grad.tolist() == pytest.approx([0.0, 0.45])


def test_unclipped_is_the_plain_squared_error():
    critic = Critic([3.0, -0.1])
    loss, (_, value_loss, *_) = ppo_loss(critic, MINIBATCH, beta=0.0, epsilon=0.2, clip_value=False)
    assert float(value_loss.detach()) == pytest.approx((4.0 + 0.81) / 2)
    loss.backward()
    assert critic.values.grad.tolist() == pytest.approx([0.5 * 2 * (3 - 5) / 2, 0.45])


def test_the_choice_reaches_training(tiny, tmp_path):
    # a trust region of 0.001 binds within a few tiny updates whatever the thread count; at 0.2 whether any
    # estimate of these near-zero returns leaves it first depends on torch's last bits
    weights = weights_under_each(compile(short_scenario("ocean_plastic_collection")), tiny | {"epsilon": 0.001},
                                 "value_loss", ("clipped", "unclipped"), tmp_path)
    assert any(not torch.equal(weights["clipped"][k], weights["unclipped"][k]) for k in weights["unclipped"])


# multiples of 1/64 within +-1000: exact in float32, so no square underflows and the ties below are exact
grid = st.integers(-64_000, 64_000).map(lambda n: n / 64)


@settings(max_examples=200, deadline=None)
@given(values=st.lists(grid, min_size=1, max_size=8), returns=st.lists(grid, min_size=8, max_size=8),
       epsilon=st.sampled_from([0.1, 0.2, 0.3]))
def test_the_trust_region_around_the_returns_themselves_is_the_plain_error(values, returns, epsilon):
    """ML-Agents release_20 stores the returns over the value estimates (one buffer key for both), so its trust
    region is centred on each estimate's own target: (R - (R + clamp(V - R))) ^ 2 = min(|V - R|, eps) ^ 2 is never
    above (R - V) ^ 2, and the max is the plain error, loss and gradient alike. (Within the region the two terms
    are one value, and torch's max splits the gradient evenly between two equal paths: the same sum.)"""
    target = torch.tensor(returns[:len(values)])
    batch = MINIBATCH | {"old_logp": torch.zeros(len(values)), "adv": torch.zeros(len(values)),
                         "old_values": target, "returns": target}
    around_returns, plain = Critic(values), Critic(values)
    loss, _ = ppo_loss(around_returns, batch, beta=0.0, epsilon=epsilon, clip_value=True)
    expected, _ = ppo_loss(plain, batch, beta=0.0, epsilon=epsilon, clip_value=False)
    loss.backward()
    expected.backward()
    assert float(loss.detach()) == float(expected.detach())
    assert torch.allclose(around_returns.values.grad, plain.values.grad, rtol=1e-6, atol=0)


def test_unclipped_is_the_default_and_a_critic_from_before_the_key_learned_clipped():
    assert PPOConfig().value_loss == "unclipped"
    assert older_defaults({"seed": 3}, spaces.Discrete(3))["value_loss"] == "clipped"
    assert older_defaults({"value_loss": "unclipped"}, spaces.Discrete(3))["value_loss"] == "unclipped"  # kept
