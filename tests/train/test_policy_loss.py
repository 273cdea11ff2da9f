"""``policy_loss``: ML-Agents' surrogate clips one probability ratio per action dimension (its
trust_region_policy_loss over ActionLogProbs.flatten()); ``joint`` clips the ratio of the joint probability."""

from __future__ import annotations

import pytest
import torch

from hivex_dsl.compiler import compile
from hivex_dsl.train.ppo import ppo_loss

from .conftest import short_scenario, weights_under_each

# two samples, two action dimensions: ratios (1.5, 0.9) with advantage 2 and (1.5, 0.5) with advantage -1
OLD = torch.zeros(2, 2)
NEW = torch.log(torch.tensor([[1.5, 0.9], [1.5, 0.5]]))
ADVANTAGES = torch.tensor([2.0, -1.0])


class FixedPolicy:
    """Returns the given log-probabilities, zero entropy and zero values, whatever it is asked."""

    def __init__(self, logp: torch.Tensor):
        self.logp = logp

    def evaluate(self, obs, cont, disc, mask=None):
        return self.logp, torch.zeros(2), torch.zeros(2)


def _minibatch(old_logp: torch.Tensor) -> dict:
    return {"obs": {}, "cont": None, "disc": None, "old_logp": old_logp, "adv": ADVANTAGES,
            "old_values": torch.zeros(2), "returns": torch.zeros(2)}


def test_ml_agents_clips_each_dimension_s_ratio_against_the_shared_advantage():
    _, (policy_loss, *_) = ppo_loss(FixedPolicy(NEW), _minibatch(OLD), beta=0.0, epsilon=0.2)
    # by hand, min(r A, clip(r, 0.8, 1.2) A) per dimension: 2.4, 1.8 | -1.5, -0.8; the loss is minus their mean
    assert float(policy_loss) == pytest.approx(-(2.4 + 1.8 - 1.5 - 0.8) / 4)


def test_joint_clips_the_ratio_of_the_joint_probability():
    _, (policy_loss, *_) = ppo_loss(FixedPolicy(NEW.sum(1)), _minibatch(OLD.sum(1)), beta=0.0, epsilon=0.2)
    # joint ratios 1.5 x 0.9 = 1.35 and 1.5 x 0.5 = 0.75: min(2.7, 2.4) = 2.4 and min(-0.75, -0.8) = -0.8
    assert float(policy_loss) == pytest.approx(-(2.4 - 0.8) / 2)


def test_with_one_action_dimension_both_losses_train_the_same_weights(tiny, tmp_path):
    """Wind Farm Control's one Discrete(3) branch: ML-Agents' per-dimension loss is the joint one."""
    weights = weights_under_each(compile(short_scenario("wind_farm_control")), tiny, "policy_loss",
                                 ("ml_agents", "joint"), tmp_path)
    assert weights["ml_agents"].keys() == weights["joint"].keys()
    assert all(torch.equal(weights["ml_agents"][k], weights["joint"][k]) for k in weights["joint"])


def test_with_several_dimensions_the_losses_train_different_weights(tiny, tmp_path):
    opc = compile(short_scenario("ocean_plastic_collection"))  # MultiDiscrete([2, 3]): two branches
    small = tiny | {"curiosity_strength": 0.0, "vis_encode_type": "simple", "hidden_units": 8}
    weights = weights_under_each(opc, small, "policy_loss", ("ml_agents", "joint"), tmp_path)
    assert not all(torch.equal(weights["ml_agents"][k], weights["joint"][k]) for k in weights["joint"])
