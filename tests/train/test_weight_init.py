"""``weight_init: ml_agents`` starts every layer as ML-Agents' ``linear_layer`` would (the scales below are read
from mlagents/trainers/torch_entities: layers.py, encoders.py, distributions.py, decoders.py and the curiosity
reward provider), and is the default; ``cleanrl`` keeps the initialisation the baselines recorded before then
trained with."""

from __future__ import annotations

import math

import numpy as np
import pytest
import torch
from gymnasium import spaces
from torch import nn

from hivex_dsl.train.config import make_config
from hivex_dsl.train.curiosity import Curiosity
from hivex_dsl.train.networks import ActorCritic

OBS = spaces.Dict({"camera": spaces.Box(0.0, 1.0, (25, 25, 2), np.float32),
                   "vector": spaces.Box(-1.0, 1.0, (12,), np.float32)})
HYBRID = spaces.Dict({"continuous": spaces.Box(-1.0, 1.0, (2,), np.float32),
                      "discrete": spaces.MultiDiscrete([2, 3])})
HIDDEN = 256  # wide enough that a layer's sample std lies within a few per cent of its scale


def _config(weight_init: str):
    return make_config("ocean_plastic_collection", {"hidden_units": HIDDEN, "weight_init": weight_init,
                                                    "curiosity_encoding_size": HIDDEN})


def _kaiming(layer: nn.Linear, gain: float) -> None:
    """Kaiming-normal for a linear activation times ``gain``: std gain / sqrt(fan_in), zero bias."""
    weight, want = layer.weight.detach(), gain / math.sqrt(layer.in_features)
    assert float(weight.std()) == pytest.approx(want, rel=0.1)
    assert float(weight.mean()) == pytest.approx(0.0, abs=want * 0.1)
    assert not layer.bias.any()


def _xavier(layer: nn.Linear) -> None:
    """Xavier-uniform: within +-sqrt(6 / (fan_in + fan_out)), std that bound / sqrt(3), zero bias."""
    weight, bound = layer.weight.detach(), math.sqrt(6.0 / (layer.in_features + layer.out_features))
    assert float(weight.abs().max()) <= bound
    assert float(weight.std()) == pytest.approx(bound / math.sqrt(3.0), rel=0.15)
    assert not layer.bias.any()


def _body_layers(body) -> tuple[list[nn.Linear], list[nn.Linear]]:
    """(the MLP's linear layers, each camera encoder's dense layer)."""
    return [m for m in body.mlp if isinstance(m, nn.Linear)], [enc[2] for enc in body.cameras.values()]


def test_ml_agents_is_the_default_and_cleanrl_the_earlier_initialisation():
    assert make_config("ocean_plastic_collection").weight_init == "ml_agents"
    torch.manual_seed(0)
    agent = ActorCritic(OBS, HYBRID, _config("cleanrl"))
    mlp, _ = _body_layers(agent.actor)
    assert all(layer.bias.any() for layer in mlp)  # torch's default bias, which ML-Agents zeroes
    # orthogonal rows of norm 0.01: every logit row has exactly that norm
    torch.testing.assert_close(agent.logits.weight.norm(dim=1), torch.full((5,), 0.01))


def test_ml_agents_initialisation_of_the_policy_and_critic():
    torch.manual_seed(0)
    agent = ActorCritic(OBS, HYBRID, _config("ml_agents"))
    for body in (agent.actor, agent.critic):
        mlp, dense = _body_layers(body)
        assert len(mlp) == 2 and len(dense) == 1
        for layer in mlp:
            _kaiming(layer, 1.0)
        _kaiming(dense[0], 1.41)  # ML-Agents' "ReLU gain"
    _kaiming(agent.logits, 0.1)
    _kaiming(agent.mu, 0.2)
    _xavier(agent.value)
    assert not agent.log_std.any()


def test_ml_agents_initialisation_of_the_curiosity_module():
    torch.manual_seed(0)
    agent = ActorCritic(OBS, HYBRID, _config("ml_agents"))
    module = Curiosity(OBS, agent.layout, _config("ml_agents"))
    mlp, dense = _body_layers(module.encoder)
    for layer in mlp:
        _kaiming(layer, 1.0)
    _kaiming(dense[0], 1.41)
    for model in (module.inverse_model, module.forward_model):  # LinearEncoder(inputs, 1, 256), then linear_layer
        *hidden, output = [layer for layer in model if isinstance(layer, nn.Linear)]
        assert len(hidden) == 2
        for layer in hidden:
            _kaiming(layer, 1.0)
        _xavier(output)


def test_an_unknown_initialisation_is_refused():
    from hivex_dsl.train.config import TrainError

    with pytest.raises(TrainError, match="weight_init"):
        make_config("ocean_plastic_collection", {"weight_init": "glorot"})
