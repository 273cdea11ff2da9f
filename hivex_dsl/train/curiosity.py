"""ML-Agents' curiosity reward signal (an intrinsic curiosity module, Pathak et al. 2017), which the paper's
WRM (strength 0.02), DBR and OPC (0.1) configs add to the extrinsic reward.

An encoder phi (the cameras through the run's visual encoder, then ``num_layers`` x ``encoding_size``) is
trained by two heads on every valid transition (s, a, s'):

- the inverse model predicts a from (phi(s), phi(s')): cross-entropy per categorical branch, the summed
  squared error of the continuous part;
- the forward model predicts phi(s') from (phi(s), a) (a as its continuous part and one-hot branches);
  its error e = 0.5 * |f(phi(s), a) - phi(s')|^2 is both its loss and the curiosity reward.

Loss = 10 * (0.2 * forward + 0.8 * inverse), its own Adam at ``curiosity_learning_rate`` (ML-Agents'
constants). The reward of a transition is min(strength * e, 1), and 0 until the module has been updated
once; it has its own value head and discount (``curiosity_gamma``) in the critic, and the advantages of
both signals are summed, as ML-Agents does.

Both models' hidden part is ML-Agents' ``LinearEncoder(inputs, 1, 256)``, which (its loop adds a last layer
after ``num_layers - 2`` middle ones) is two Swish layers of 256 (mlagents/trainers/torch_entities/layers.py and
components/reward_providers/curiosity_reward_provider.py). ``curiosity_module: hivex_v1`` keeps this project's
first module, with one such layer and half the continuous squared error, which the WRM, DBR and OPC baselines
recorded before the option existed trained with.
"""

from __future__ import annotations

import torch
from gymnasium import spaces
from torch import nn

from .buffer import CHUNK, in_chunks
from .config import PPOConfig
from .networks import ActionLayout, Body, linear_encoder, ml_agents_linear, observation_keys, swish_mlp, vector_part

FORWARD_WEIGHT = 0.2  # ML-Agents' CuriosityRewardProvider.beta
LOSS_MULTIPLIER = 10.0  # ML-Agents' CuriosityRewardProvider.loss_multiplier
MODEL_UNITS = 256  # ML-Agents' width of the inverse and forward models


def _model(inputs: int, outputs: int, variant: str) -> nn.Sequential:
    """(B, inputs) -> (B, outputs): ML-Agents' ``LinearEncoder(inputs, 1, 256)`` (two Swish layers) or hivex_v1's
    one Swish layer of 256, then a linear output layer."""
    hidden = linear_encoder(inputs, 1, MODEL_UNITS) if variant == "ml_agents" else swish_mlp(inputs, MODEL_UNITS, 1)
    return nn.Sequential(*hidden, nn.Linear(MODEL_UNITS, outputs))


class Curiosity(nn.Module):
    def __init__(self, observation_space: spaces.Space, layout: ActionLayout, cfg: PPOConfig):
        super().__init__()
        keys = observation_keys(observation_space)
        size = cfg.curiosity_encoding_size
        self.encoder = Body(keys, cfg.model_copy(update={"hidden_units": size}))
        self.layout, self.strength = layout, cfg.curiosity_strength
        actions = layout.continuous + sum(layout.nvec)
        self.continuous_error_scale = 1.0 if cfg.curiosity_module == "ml_agents" else 0.5
        self.inverse_model = _model(2 * size, actions, cfg.curiosity_module)
        self.forward_model = _model(size + actions, size, cfg.curiosity_module)
        self.register_buffer("updated", torch.tensor(False))
        if cfg.weight_init == "ml_agents":
            self.encoder.init_like_ml_agents()
            for model in (self.inverse_model, self.forward_model):  # LinearEncoder layers, then a linear_layer
                linears = [layer for layer in model if isinstance(layer, nn.Linear)]
                for layer in linears[:-1]:
                    ml_agents_linear(layer, "kaiming")
                ml_agents_linear(linears[-1], "xavier")

    def _device(self) -> torch.device:
        return self.forward_model[0].weight.device

    def _encode(self, obs: dict[str, torch.Tensor]) -> torch.Tensor:
        obs = {k: v.to(self._device()) for k, v in obs.items()}
        return self.encoder(obs, vector_part(obs, self.encoder.vectors))

    def _action_input(self, cont: torch.Tensor, disc: torch.Tensor) -> torch.Tensor:
        """(B, continuous + sum(nvec)): the continuous part, then each branch one-hot."""
        cont, disc = cont.to(self._device()), disc.to(self._device())
        parts = [cont] + [nn.functional.one_hot(disc[:, i], n).float() for i, n in enumerate(self.layout.nvec)]
        return torch.cat(parts, dim=1)

    def _forward_error(self, phi: torch.Tensor, phi_next: torch.Tensor, action: torch.Tensor) -> torch.Tensor:
        predicted = self.forward_model(torch.cat([phi, action], dim=1))
        return 0.5 * (predicted - phi_next).square().sum(1)

    def loss(self, obs: dict[str, torch.Tensor], next_obs: dict[str, torch.Tensor], cont: torch.Tensor,
             disc: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor, torch.Tensor]:
        """-> (total loss, forward loss, inverse loss) of a minibatch of valid transitions."""
        phi, phi_next = self._encode(obs), self._encode(next_obs)
        cont, disc = cont.to(self._device()), disc.to(self._device())  # the inverse model's targets too
        forward = self._forward_error(phi, phi_next, self._action_input(cont, disc)).mean()
        predicted = self.inverse_model(torch.cat([phi, phi_next], dim=1))
        inverse = predicted.new_zeros(())
        if self.layout.continuous:
            error = (predicted[:, :self.layout.continuous] - cont).square().sum(1).mean()
            inverse = inverse + self.continuous_error_scale * error
        logits = torch.split(predicted[:, self.layout.continuous:], self.layout.nvec, dim=1)
        for i, branch in enumerate(logits):
            inverse = inverse + nn.functional.cross_entropy(branch, disc[:, i])
        total = LOSS_MULTIPLIER * (FORWARD_WEIGHT * forward + (1.0 - FORWARD_WEIGHT) * inverse)
        return total, forward.detach(), inverse.detach()

    @torch.no_grad()
    def rewards(self, obs: dict[str, torch.Tensor], next_obs: dict[str, torch.Tensor], cont: torch.Tensor,
                disc: torch.Tensor) -> torch.Tensor:
        """(N,) curiosity rewards min(strength * e, 1) of N transitions (flat observations), 0 before any update."""
        if not bool(self.updated):
            return torch.zeros(cont.shape[0])
        return self._rewarded(in_chunks(self._encode, obs), in_chunks(self._encode, next_obs), cont, disc)

    @torch.no_grad()
    def rollout_rewards(self, frames: dict[str, torch.Tensor], cont: torch.Tensor, disc: torch.Tensor
                        ) -> torch.Tensor:
        """(T * S,) the rewards of a rollout's transitions from its ``frames`` ((T + 1) * S rows: each step's
        observations, then the last next observations), each frame encoded once: a step's next observation is
        the following step's observation. Equal to :meth:`rewards` of the same transitions."""
        transitions = cont.shape[0]
        if not bool(self.updated):
            return torch.zeros(transitions)
        phi = in_chunks(self._encode, frames)
        slots = phi.shape[0] - transitions
        return self._rewarded(phi[:transitions], phi[slots:], cont, disc)

    def _rewarded(self, phi: torch.Tensor, phi_next: torch.Tensor, cont: torch.Tensor, disc: torch.Tensor
                  ) -> torch.Tensor:
        """min(strength * forward error, 1) of encoded transitions, the forward model run CHUNK rows at a time."""
        errors = [self._forward_error(phi[part], phi_next[part], self._action_input(cont[part], disc[part]))
                  for part in (slice(start, start + CHUNK) for start in range(0, cont.shape[0], CHUNK))]
        return (self.strength * torch.cat(errors)).clamp(max=1.0).cpu()
