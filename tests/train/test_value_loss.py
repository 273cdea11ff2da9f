"""``value_loss``: ``clipped`` (ML-Agents' trust region) holds each estimate within epsilon of the one its
experience was gathered with and takes the larger error, so an estimate moved past that toward its return gets no
gradient; ``unclipped`` is the plain squared error."""

from __future__ import annotations

import pytest
import torch

from hivex_dsl.compiler import compile
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
    weights = weights_under_each(compile(short_scenario("ocean_plastic_collection")), tiny, "value_loss",
                                 ("clipped", "unclipped"), tmp_path)
    assert any(not torch.equal(weights["clipped"][k], weights["unclipped"][k]) for k in weights["unclipped"])
