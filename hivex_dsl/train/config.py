"""PPO hyperparameters: the paper's per-environment values as data, overridable from YAML and the command line.

The paper trained with ML-Agents; its appendix lists one trainer config per environment, and the original's
repository holds the configs that ran (``../shared/paper/original-configs/train``), which differ from the
appendix for Drone-Based Reforestation (max_steps 1.2M, not 2M; summary_freq 6,000; buffer_size and time_horizon
8,192) and Wildfire Resource Management (max_steps 450k, not 4.5M). The original's plots' step axes follow the
configs that ran, so ``hyperparams/<environment>.yaml`` holds those, with ML-Agents' own key names, as the
defaults of `hivex train`; each file's ``appendix:`` block names the appendix's values where they differ
(:func:`appendix`; documentation, never trained with); an environment without such a file (one added to the
catalogue) trains on :class:`PPOConfig`'s own defaults. How each key maps onto the PPO of ``ppo.py``
(parameter-shared over every (world, agent) slot):

- ``max_steps``: agent-steps (experiences over all agents), as ML-Agents counts them; every slot-step
  counts, the masked reset steps after an ending included. A step is a decision: with a scenario's
  ``decision_period`` k it spans k physics steps, and so do ``checkpoint_every`` and the curves.
- ``summary_freq``: agent-steps between two points of the learning curve (curve.json and the TensorBoard
  episode scalars): as in ML-Agents, a point is written at the first update that reaches the next multiple
  and holds the mean of every episode ended since the last point; the run's last update writes one too.
  Logging only: what the policy learns is the same at any value (the losses are logged every update).
  Runs and records from before the key existed wrote a point every update, which ``summary_freq: 1`` does.
- ``buffer_size``: experiences collected over all slots before an update. With ``buffer_fill: rollout`` (the
  default) a rollout is ``buffer_size // slots`` steps of every slot (slots = ``num_worlds * agents``), at most
  ``time_horizon``; with ``buffer_fill: trajectories`` it fills as ML-Agents' does (below).
- ``time_horizon``: ML-Agents cuts trajectories there and bootstraps from the value; our rollouts always
  bootstrap at their end. With ``buffer_fill: rollout`` it only caps the rollout length.
- ``buffer_fill`` (ours: ML-Agents has one way): ``trajectories`` updates as ML-Agents does. A slot's trajectory
  is handed to the trainer when it holds ``time_horizon`` experiences or its episode ends, and an update comes
  once the finished trajectories hold more than ``buffer_size`` experiences (:class:`.buffer.FinishedTrajectories`);
  with every slot in step, an update's experiences are then at least those of one trajectory of every slot, so
  they grow with ``num_worlds`` (each world is one Unity environment of ML-Agents' ``--num-envs``) and the updates
  come as often as the original's only at its number of environments. The rollout ends there, unfinished
  trajectories included (ML-Agents carries them into the next buffer; they differ only where slots fall out of
  step), and at most ``time_horizon + buffer_size // slots + 1`` steps. ``rollout``, the default, is the fixed
  rollout above; Wind Farm Control's, Aerial Wildfire Suppression's and Wildfire Resource Management's files set
  ``trajectories`` with one world, as every config that ran trained (none names ``num_envs``, mlagents-learn's
  default 1). Wind Farm Control's config updated at 2,048, 4,096 and 5,000 steps of each 5,000-step episode of its one
  environment of 8 turbines (16,384, 16,384 and 7,232 experiences: 600 updates in 8M agent-steps, read from its logged
  epsilon), as ``trajectories`` with one world does, where ``rollout`` with 8 worlds updated every 2,048 (3,906
  updates), learned about 1.5-2 times as fast and ended far more decided (rewards/wind_farm_control.yaml).
- ``policy_lag_steps`` (ML-Agents' ``threaded``, true in every config that ran, read as steps): the first N steps of
  each rollout act with the weights from before the last update, as the environment stepped on while ML-Agents'
  trainer thread updated (``lag.py`` gives the original's timing); 0, the default, acts with the current weights.
- ``ended_agents`` (ours: in ML-Agents the environment's code decides): what the training vector env does with an
  agent whose episode ended while its world goes on (a battery run out, a crash). ``respawn``, the default, starts
  it again at once in its running world, so its next episode is cut at the world's end (a short tail); ``wait``
  keeps it out of play until its world restarts (a world whose agents have all ended restarts then), its slot
  masked out of the loss and no episode logged for it, as ``hivex evaluate``'s rollouts play it. Drone-Based
  Reforestation's file sets ``wait``: the original's Out of Energy Count (0.86-0.98 at the end of its main task's
  training) is above what any training with tails could log (rewards/drone_based_reforestation.yaml). The masked
  steps of a waiting slot count in ``max_steps`` as the reset steps do.
- ``batch_size``: minibatch size of one gradient step, at most ``buffer_size`` (ML-Agents would train nothing
  over it); ``num_epoch``: passes over the buffer (its valid experiences; an epoch's last, smaller minibatch is
  trained on too, where ML-Agents drops it).
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
  ``curiosity_encoding_size`` is the width ML-Agents built, not always the config's ``encoding_size``: where a
  curiosity block also names ``network_settings`` (DBR's and OPC's), release_20 ignores ``encoding_size`` and
  takes ``network_settings.hidden_units``, 128 by default (tests/train/test_budgets.py reads the configs so).
  ``curiosity.py`` is ML-Agents' module; the critic gets a second value head for it.

Ours (ML-Agents has no such key): ``num_worlds`` (parallel copies of the scenario; the paper appendix's AWS config
runs 12 environments, the configs that ran one), ``max_grad_norm`` (gradient clipping; 0, the default, clips none,
as ML-Agents; the baselines recorded before it became the default clipped at 0.5 and their commands say so),
``checkpoint_every`` and ``keep_checkpoints`` (agent-steps between checkpoints, how many are kept), ``seed`` (torch
and sampling), ``world_seed`` (the stream of the training worlds: ``scenario``, the default, is the scenario's
``seeds.train``, as every run of a cell in the original shared its config's ``env_settings.seed``; an integer trains
on worlds of its own, so seeds that differ in it differ in the worlds they met as well as in their weights, what the
seeds' measure of ``evaluation.original.seeds`` needs where the worlds more than the policy set a curve's points;
the test split is always the scenario's ``seeds.test``), ``device``, ``torch_threads`` (``auto``, the default: the
machine's free cores up to 8, :func:`free_cores`: those this process may use less the share the 1-minute load
average keeps busy, since threads beyond the free cores slow a run down many times over; on 2 quiet cores the camera
environments train 1.4-1.8x faster on both than on one; set 1 for concurrent runs on a shared machine, and a number
to reproduce a record exactly, since the thread count can change the last bits of torch's reductions; a record
reproduces to the digit only on a processor that takes the same kernels too, which its machine names), ``precision``
(``exact``, the default: float32 everywhere; ``bf16``: the update's and the rollout's forward passes under bfloat16
autocast, on CPU or GPU, not bit-identical; on 2 CPU cores it trained OPC (ResNet encoders, curiosity) 1.4x faster
(372 -> 514 agent-steps/s), DBR 1.1x and AWS (simple encoder) no faster; ``tf32``: float32 storage with
TensorFloat-32 matrix products and convolutions, a GPU mode. An approximate run says so in its config.json and on
the baselines page), ``cpu_kernels`` (``native``, the default and what every record trained with: MKL, ATen and oneDNN
take the processor's own kernels, the fastest, and a run reproduces to the digit on alike processors only;
``portable``: MKL's compatible code path, ATen's default kernels and no oneDNN, pinned in the training process
before its first product, which trained alike on the Intel and AMD processors measured, at a cost in speed;
``kernels.py`` says what each pins and what is measured).

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
- ``value_loss``: ``unclipped`` (the plain squared error of each value head, which is what ML-Agents release_20
  computes: its buffer files a trajectory's value estimates under the returns' key,
  ``RewardSignalUtil.value_estimates_key`` returning ``RewardSignalKeyPrefix.RETURNS`` since its buffer-key enums,
  Unity-Technologies/ml-agents PR #4907 of February 2021, still so in issue #6281 of 2026, so the returns
  overwrite them and trust_region_value_loss clips each estimate within ``epsilon`` of its own target, a term never
  larger than the plain error, which the max then takes) or ``clipped`` (the trust region as that code means it:
  the estimate clipped within ``epsilon`` of the one the experience was gathered with, the larger error taken, so
  an update moves an estimate little more than ``epsilon`` toward its return). The original's Extrinsic Value
  Estimate panels move as the unclipped critic does, several units an update where the clipped one moves tenths
  (the reward tables' notes 'The critic's pace').
- ``action_masks``: ``true`` (as ML-Agents: where the environment says which discrete choices are open, Drone-Based
  Reforestation's and Aerial Wildfire Suppression's drop, ``infos["action_mask"]``, a closed choice's logit is
  -1e8, so the policy never picks it, its probability and entropy are 0, and the update evaluates each experience
  under the mask it was taken with) or ``false`` (the masks ignored: every choice open at every decision). Without
  masks in the environment both are the same; the records of those two environments trained before the key
  existed trained ``false``.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path
from typing import Annotated, Any, Callable, Literal, Mapping, Sequence, Union

from pydantic import Field, ValidationError

from ..adapters.gymnasium import EndedAgents
from ..base.errors import HivexError, ScenarioError, got
from ..lang.loader import Document, load_file, load_text
from ..lang.spec.common import StrictModel
from ..lang.spec.validate import describe

HYPERPARAMS = Path(__file__).resolve().parent / "hyperparams"


class TrainError(HivexError, ValueError):
    """Bad training input: an unknown hyperparameter, a value out of range, a checkpoint that does not fit."""

    @classmethod
    def listing(cls, problems: Sequence[str]) -> TrainError:
        """Bad hyperparameters: a heading, then one problem a line (each starting with where it was written)."""
        return cls("bad hyperparameters\n" + "\n".join(problems))


HYPERPARAMETERS = Document("set of hyperparameters", "a mapping of hyperparameter: value (ML-Agents' key names)",
                           may_be_empty=True)
DEVICES = "cpu, cuda or cuda:N (one GPU of several)"  # what the training loop runs on
THREADS = "an integer from 1 to 256, or auto (this machine's cores, at most 8)"
WORLD_SEEDS = "an integer from 0 to 4294967295, or scenario (the scenario's seeds.train)"
Precision = Literal["exact", "bf16", "tf32"]
CpuKernels = Literal["native", "portable"]  # what each pins: kernels.py
MAX_AUTO_THREADS = 8  # past 8 the small networks' updates gain little; more belongs to concurrent runs
MINIBATCH_KEYS = ("batch_size", "buffer_size")
ML_AGENTS_SECTIONS = frozenset({"behaviors", "hyperparameters", "network_settings", "reward_signals", "extrinsic",
                                "curiosity"})


class PPOConfig(StrictModel):
    """Every knob of one training run; defaults are those of the paper's WFC config."""

    __hivex_key_noun__ = "hyperparameter"

    @staticmethod
    def __hivex_unknown_key_hint__(key: str, parent: tuple) -> str | None:
        if key in ML_AGENTS_SECTIONS:  # a config pasted from ML-Agents
            return (f"unknown hyperparameter '{key}': ML-Agents nests its keys in sections, here they are one flat "
                    "mapping (hidden_units: 128, not network_settings: {hidden_units: 128}); the extrinsic signal's "
                    "strength is reward_strength, the curiosity signal's keys are curiosity_strength, curiosity_gamma, "
                    "curiosity_encoding_size and curiosity_learning_rate")
        return None

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
    summary_freq: int = Field(40_000, ge=1)
    num_worlds: int = Field(4, ge=1, le=4096)
    buffer_fill: Literal["rollout", "trajectories"] = "rollout"
    policy_lag_steps: int = Field(0, ge=0, le=100_000)
    ended_agents: EndedAgents = "respawn"
    max_grad_norm: float = Field(0.0, ge=0.0)
    checkpoint_every: int = Field(500_000, ge=1)
    keep_checkpoints: int = Field(5, ge=1)
    seed: int = Field(0, ge=0, le=2**32 - 1)
    world_seed: Union[Annotated[int, Field(ge=0, le=2**32 - 1)], Literal["scenario"]] = Field(
        "scenario", json_schema_extra={"x-expected": WORLD_SEEDS})
    device: str = Field("cpu", pattern=r"^(cpu|cuda(:[0-9]+)?)$", json_schema_extra={"x-expected": DEVICES})
    torch_threads: Union[Annotated[int, Field(ge=1, le=256)], Literal["auto"]] = Field(
        "auto", json_schema_extra={"x-expected": THREADS})
    precision: Precision = "exact"
    cpu_kernels: CpuKernels = "native"
    curiosity_strength: float = Field(0.0, ge=0.0, le=1.0)
    curiosity_gamma: float = Field(0.99, ge=0.0, le=1.0)
    curiosity_encoding_size: int = Field(256, ge=1, le=8192)
    curiosity_learning_rate: float = Field(3.0e-4, ge=0.0, le=1.0)
    weight_init: Literal["ml_agents", "cleanrl"] = "ml_agents"
    curiosity_module: Literal["ml_agents", "hivex_v1"] = "ml_agents"
    continuous_actions: Literal["ml_agents", "clip"] = "ml_agents"
    policy_loss: Literal["ml_agents", "joint"] = "ml_agents"
    value_loss: Literal["unclipped", "clipped"] = "unclipped"
    action_masks: bool = True

    def precision_problem(self) -> str | None:
        """Why ``precision`` cannot run on ``device`` (tf32 is a GPU mode), or None."""
        if self.precision == "tf32" and not self.device.startswith("cuda"):
            return (f"precision tf32 is a GPU mode (TensorFloat-32 tensor cores), but device is {self.device}: "
                    "on a CPU use precision bf16 for an approximate run, or exact")
        return None

    def threads(self) -> int:
        """The torch threads this run uses: ``torch_threads``, or for ``auto`` this machine's free cores (at most
        :data:`MAX_AUTO_THREADS`, at least 1; :func:`free_cores`)."""
        if self.torch_threads != "auto":
            return self.torch_threads
        return max(1, min(free_cores(), MAX_AUTO_THREADS))

    def own_worlds(self) -> int | None:
        """The seed of this run's training worlds where it names its own (``world_seed``), None for the scenario's."""
        return None if self.world_seed == "scenario" else self.world_seed

    def rollout_length(self, slots: int) -> int:
        """Steps of every slot per update, at most: with ``buffer_fill: rollout`` always ``buffer_size // slots``
        (at least 1), at most ``time_horizon``; with ``trajectories`` the rollout ends earlier, once its finished
        trajectories exceed ``buffer_size`` (with every slot acting, by ``time_horizon + buffer_size // slots``)."""
        if self.buffer_fill == "trajectories":
            return self.time_horizon + self.buffer_size // slots + 1
        return max(1, min(self.time_horizon, self.buffer_size // slots))


def has_paper_hyperparameters(environment: str) -> bool:
    """Whether ``hyperparams/<environment>.yaml`` ships (the paper's five do; a new environment need not)."""
    return (HYPERPARAMS / f"{environment}.yaml").is_file()


def free_cores() -> int:
    """The cores this process may use (its CPU affinity where the OS says, else the machine's) less the share the
    1-minute load average keeps busy: load / the machine's cores of them, rounded; at least 1. A quiet machine
    frees them all; on 2 cores at load 7 (four busy loops and more), one."""
    machine = os.cpu_count() or 1
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else machine
    try:
        load = os.getloadavg()[0]
    except (AttributeError, OSError):  # no load average on this OS: every core counts as free
        load = 0.0
    busy = round(cores * min(1.0, max(0.0, load) / machine))
    return max(1, cores - busy)


APPENDIX_KEY = "appendix"  # a hyperparameter file's block of the paper appendix's values where they differ


def _hyperparameter_file(environment: str) -> dict[str, Any]:
    """The environment's hyperparameter file as written; none (``{}``, so training takes :class:`PPOConfig`'s
    defaults) for a registered environment without one."""
    if has_paper_hyperparameters(environment):
        return dict(load_file(HYPERPARAMS / f"{environment}.yaml", HYPERPARAMETERS).data or {})
    from ..compiler import registry

    if environment not in registry.environments():
        raise TrainError(f"no paper hyperparameters for environment {environment!r}: it is not a registered "
                         f"environment ({', '.join(registry.environments())})")
    return {}


def paper_defaults(environment: str) -> dict[str, Any]:
    """The hyperparameters of one environment's config that ran, as written in its YAML file."""
    return {k: v for k, v in _hyperparameter_file(environment).items() if k != APPENDIX_KEY}


def appendix(environment: str) -> dict[str, Any]:
    """The paper appendix's values of the keys where its config differs from the one that ran (``{}``: none),
    e.g. ``{"max_steps": 4500000}`` for Wildfire Resource Management."""
    return dict(_hyperparameter_file(environment).get(APPENDIX_KEY) or {})


@dataclass(frozen=True)
class Overrides:
    """Hyperparameters from one source: ``values``, and ``locate(name, key)``, where the user wrote ``name``'s
    key (``key=True``) or its value, to begin an error message with (``hp.yaml:3:8``, ``--set``). A plain
    mapping (from Python) has no place: its problems are named by the key alone."""

    values: Mapping[str, Any]
    locate: Callable[[str, bool], str] | None = None

    @classmethod
    def of(cls, layer: Mapping[str, Any] | Overrides) -> Overrides:
        return layer if isinstance(layer, Overrides) else cls(dict(layer))

    def where(self, name: str, key: bool = False) -> str:
        """``"hp.yaml:3:8: "``, ``"--set: "``, or nothing for a plain mapping."""
        return f"{self.locate(name, key)}: " if self.locate else ""

    def problems(self, base: Mapping[str, Any]) -> list[str]:
        """What is wrong with these values over ``base``, each at the place it was written."""
        try:
            PPOConfig.model_validate(dict(base) | dict(self.values))
        except ValidationError as exc:
            found, named = [], set()
            for err in exc.errors(include_url=False):
                name = err["loc"][0]  # every field is a flat key
                # not an earlier layer's problem, which that layer reports; and one problem a key (a value that
                # fits neither form of `torch_threads` fails both, and its x-expected names both)
                if name in self.values and name not in named:
                    named.add(name)
                    message, at_key = describe(err, (name,), PPOConfig)
                    found.append(self.where(name, at_key) + message)
            return found
        return []


def read_overrides(path: str | Path) -> Overrides:
    """A YAML file of hyperparameters (a flat mapping, ML-Agents' key names), read as strictly as a scenario."""
    try:
        loaded = load_file(path, HYPERPARAMETERS)
    except ScenarioError as exc:
        raise TrainError.listing([str(p) for p in exc.problems]) from None
    if loaded.data is None:  # comments only: nothing overridden
        return Overrides({})
    if not isinstance(loaded.data, dict):
        raise TrainError.listing([f"{loaded.locate(())}: expected {HYPERPARAMETERS.contents}, got {got(loaded.data)}"])
    return Overrides(loaded.data, lambda name, key=False: str(loaded.locate((name,), key=key)))


def parse_assignments(assignments: Sequence[str]) -> Overrides:
    """``["gamma=0.99", "normalize=true"]`` -> ``{"gamma": 0.99, "normalize": True}``, each value read as a YAML
    scalar by the scenario loader (``3e-4`` is a number; YAML 1.1's ``yes`` is refused, not made a boolean)."""
    values: dict[str, Any] = {}
    written: dict[str, str] = {}
    for text in assignments:
        name, sep, value = text.partition("=")
        name = name.strip()
        if not sep or not name:
            raise TrainError(f"--set {text}: expected NAME=VALUE")
        if not value.strip():
            raise TrainError(f"--set {text}: expected a value after '='")
        if name in values:
            raise TrainError(f"--set {name} is given twice ({written[name]}, then {text}): give it once")
        try:
            values[name] = load_text(value, f"--set {name}", HYPERPARAMETERS).data
        except ScenarioError as exc:
            raise TrainError(f"--set {text}: {exc.first.message}") from None
        written[name] = text
    return Overrides(values, lambda name, key=False: "--set")


def make_config(environment: str, *layers: Mapping[str, Any] | Overrides) -> PPOConfig:
    """The paper's values for ``environment`` with each override layer applied in turn. Every problem of every
    layer is reported at once, each where it was written; a rule between keys blames the last layer that set
    one of them."""
    merged = paper_defaults(environment)
    problems: list[str] = []
    overrides = [Overrides.of(layer) for layer in layers]
    for layer in overrides:
        problems += layer.problems(merged)
        merged |= dict(layer.values)
    if problems:
        raise TrainError.listing(problems)
    cfg = PPOConfig(**merged)  # every layer was valid over the ones before it, so the whole is
    if cfg.batch_size > cfg.buffer_size:
        # ML-Agents trains whole minibatches only, so there a batch_size over the experiences collected trains
        # nothing. A rule for new runs only: a checkpoint trained before it still loads and plays.
        blamed = next((layer.where(k) for layer in reversed(overrides) for k in MINIBATCH_KEYS
                       if k in layer.values), "")
        raise TrainError.listing([f"{blamed}batch_size {cfg.batch_size} is larger than buffer_size {cfg.buffer_size}: "
                                  f"a minibatch is drawn from one buffer; set batch_size to at most {cfg.buffer_size} "
                                  f"or buffer_size to at least {cfg.batch_size}"])
    if cfg.precision_problem():
        blamed = next((layer.where(k) for layer in reversed(overrides) for k in ("precision", "device")
                       if k in layer.values), "")
        raise TrainError.listing([blamed + cfg.precision_problem()])
    return cfg
