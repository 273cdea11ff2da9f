"""PPO hyperparameters: the paper's per-environment values as data, overridable from YAML and the command line.

The paper trained with ML-Agents; its appendix lists one trainer config per environment. They ship in
``hyperparams/<environment>.yaml`` with ML-Agents' own key names and are the defaults of `hivex train`.
How each maps onto the PPO of ``ppo.py`` (parameter-shared over every (world, agent) slot):

- ``max_steps``: agent-steps (experiences over all agents), as ML-Agents counts them; every slot-step
  counts, the masked reset steps after an ending included.
- ``buffer_size``: experiences collected over all slots before an update. A rollout is
  ``buffer_size // slots`` steps of every slot (slots = ``num_worlds * agents``), at most ``time_horizon``.
- ``time_horizon``: ML-Agents cuts trajectories there and bootstraps from the value; our rollouts are
  never longer and always bootstrap at their end, so it only caps the rollout length.
- ``batch_size``: minibatch size of one gradient step; ``num_epoch``: passes over the buffer (its valid
  experiences; an epoch's last, smaller minibatch is trained on too, where ML-Agents drops it).
- ``learning_rate`` + ``learning_rate_schedule``: ``linear`` decays the rate to 0 over ``max_steps``
  (ML-Agents also decays epsilon to 0.1 and beta to 1e-5 on the same schedule; so do we).
- ``beta``: entropy coefficient; ``epsilon``: PPO clip range of the ratio and of the value (ML-Agents
  clips both); ``lambd``: GAE lambda; ``gamma``: the extrinsic signal's discount; ``reward_strength``:
  the extrinsic signal's strength (a reward scale).
- ``hidden_units`` x ``num_layers``: the MLP after the encoders, separate for actor and critic as in
  ML-Agents, and counted as its ``LinearEncoder`` counts them (1 builds two layers, as 2 does);
  ``vis_encode_type``: ``simple`` (2 conv layers) or ``resnet`` (ML-Agents' IMPALA-style stack), both layer
  for layer as ML-Agents builds them; ``normalize``: running mean/std of vector observations.
- ``reward_signals.curiosity`` (WRM, DBR, OPC) flattened: ``curiosity_strength`` (0 turns the signal off),
  ``curiosity_gamma``, ``curiosity_encoding_size``, ``curiosity_learning_rate``; its encoder uses the run's
  ``vis_encode_type`` and ``num_layers`` (the paper's curiosity network_settings name the same encoder).
  ``curiosity.py`` is ML-Agents' module; the critic gets a second value head for it.

Ours (ML-Agents has no such key): ``num_worlds`` (parallel copies of the scenario; the paper's AWS config
runs 12 environments), ``max_grad_norm`` (gradient clipping; 0, the default, clips none, as ML-Agents; the
baselines recorded before it became the default clipped at 0.5 and their commands say so), ``checkpoint_every``
and ``keep_checkpoints`` (agent-steps between checkpoints, how many are kept), ``seed`` (torch and sampling;
the environment's seeds are the scenario's), ``device``, ``torch_threads`` (1: small networks on a shared
machine lose more to thread hand-offs than they gain).

Choices where this toolkit first did otherwise than ML-Agents. Each defaults to ML-Agents; the named earlier
choice is what the baselines recorded before the default changed trained with (their commands set it), and a
checkpoint or record written before its key existed reads as that choice where it changes the policy
(``checkpoint.older_defaults``):

- ``weight_init``: ``ml_agents`` (its ``linear_layer`` choices: Kaiming-normal body and camera dense layers
  with gains 1 and 1.41, Xavier-uniform value heads, Kaiming-normal policy heads with gains 0.2 for Gaussian
  means and 0.1 for categorical branches, zero biases; the curiosity module's layers too) or ``cleanrl``
  (torch's defaults, orthogonal policy and value heads with gains 0.01 and 1).
- ``curiosity_module``: ``ml_agents`` (ML-Agents' CuriosityNetwork, whose inverse and forward models are two
  Swish layers of 256 and whose inverse loss of continuous actions is their summed squared error) or
  ``hivex_v1`` (this project's first module: one layer, half that error).
- ``continuous_actions``: how a Gaussian sample becomes a Box action, ``ml_agents`` (clamp(sample, -3, 3) / 3
  onto the Box, as ML-Agents sends it, so the initial log-std 0 explores gently) or ``clip`` (the sample
  clipped into the Box, saturating at one standard deviation).
- ``policy_loss``: ``ml_agents`` (as ML-Agents' trust_region_policy_loss, one probability ratio per action
  dimension, each continuous dimension and each discrete branch, clipped on its own against the shared
  advantage and averaged, and the Gaussian part's entropy the mean over its dimensions) or ``joint`` (textbook
  PPO: one ratio of the joint probability, every entropy summed; with one action dimension they are the same).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any, Literal, Mapping, Sequence

import yaml
from pydantic import Field, ValidationError

from ..errors import HivexError
from ..spec.common import StrictModel

HYPERPARAMS = Path(__file__).resolve().parent / "hyperparams"


class TrainError(HivexError, ValueError):
    """Bad training input: an unknown hyperparameter, a value out of range, a checkpoint that does not fit."""


class PPOConfig(StrictModel):
    """Every knob of one training run; defaults are those of the paper's WFC config."""

    batch_size: int = Field(256, ge=1)
    buffer_size: int = Field(2048, ge=1)
    learning_rate: float = Field(3.0e-4, ge=0.0, le=1.0)
    learning_rate_schedule: Literal["linear", "constant"] = "linear"
    beta: float = Field(5.0e-3, ge=0.0, le=1.0)
    epsilon: float = Field(0.2, gt=0.0, le=1.0)
    lambd: float = Field(0.95, ge=0.0, le=1.0)
    num_epoch: int = Field(3, ge=1, le=1000)
    gamma: float = Field(0.9, ge=0.0, le=1.0)
    reward_strength: float = Field(1.0, gt=0.0)
    normalize: bool = False
    hidden_units: int = Field(64, ge=1, le=8192)
    num_layers: int = Field(2, ge=1, le=16)
    vis_encode_type: Literal["simple", "resnet"] = "simple"
    time_horizon: int = Field(2048, ge=1)
    max_steps: int = Field(8_000_000, ge=1)
    num_worlds: int = Field(4, ge=1, le=4096)
    max_grad_norm: float = Field(0.0, ge=0.0)
    checkpoint_every: int = Field(500_000, ge=1)
    keep_checkpoints: int = Field(5, ge=1)
    seed: int = Field(0, ge=0, le=2**32 - 1)
    device: str = "cpu"
    torch_threads: int = Field(1, ge=1, le=256)
    curiosity_strength: float = Field(0.0, ge=0.0, le=1.0)
    curiosity_gamma: float = Field(0.99, ge=0.0, le=1.0)
    curiosity_encoding_size: int = Field(256, ge=1, le=8192)
    curiosity_learning_rate: float = Field(3.0e-4, ge=0.0, le=1.0)
    weight_init: Literal["ml_agents", "cleanrl"] = "ml_agents"
    curiosity_module: Literal["ml_agents", "hivex_v1"] = "ml_agents"
    continuous_actions: Literal["ml_agents", "clip"] = "ml_agents"
    policy_loss: Literal["ml_agents", "joint"] = "ml_agents"

    def rollout_length(self, slots: int) -> int:
        """Steps of every slot per update: ``buffer_size // slots`` (at least 1), at most ``time_horizon``."""
        return max(1, min(self.time_horizon, self.buffer_size // slots))


def paper_defaults(environment: str) -> dict[str, Any]:
    """The paper's hyperparameters of one environment, as written in its YAML file."""
    path = HYPERPARAMS / f"{environment}.yaml"
    if not path.is_file():
        raise TrainError(f"no paper hyperparameters for environment {environment!r}")
    return yaml.safe_load(path.read_text(encoding="utf-8"))


def read_overrides(path: str | Path) -> dict[str, Any]:
    """A YAML file of hyperparameters (a flat mapping, ML-Agents' key names)."""
    try:
        data = yaml.safe_load(Path(path).read_text(encoding="utf-8"))
    except OSError as exc:
        raise TrainError(f"cannot read hyperparameters {path}: {exc.strerror or exc}") from None
    except yaml.YAMLError as exc:
        raise TrainError(f"hyperparameters {path} are not valid YAML: {exc}") from None
    if data is None:
        return {}
    if not isinstance(data, dict):
        raise TrainError(f"hyperparameters {path} must be a mapping of name: value")
    return data


def parse_assignments(assignments: Sequence[str]) -> dict[str, Any]:
    """``["gamma=0.99", "normalize=true"]`` -> ``{"gamma": 0.99, "normalize": True}`` (values read as YAML)."""
    out: dict[str, Any] = {}
    for text in assignments:
        key, sep, value = text.partition("=")
        if not sep or not key.strip():
            raise TrainError(f"expected NAME=VALUE, got {text!r}")
        out[key.strip()] = yaml.safe_load(value) if value.strip() else None
    return out


def make_config(environment: str, *layers: Mapping[str, Any]) -> PPOConfig:
    """The paper's values for ``environment`` with each override layer applied in turn."""
    merged = paper_defaults(environment)
    for layer in layers:
        merged.update({k: v for k, v in layer.items() if v is not None})
    try:
        return PPOConfig(**merged)
    except ValidationError as exc:
        problems = "; ".join(f"{'.'.join(map(str, e['loc'])) or 'config'}: {e['msg']}" for e in exc.errors())
        raise TrainError(f"bad hyperparameters: {problems}") from None
