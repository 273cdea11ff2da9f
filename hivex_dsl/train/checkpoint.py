"""Checkpoints: the network's weights with everything needed to rebuild it and replay its scenario.

A checkpoint is read back through one validation step (:func:`load_checkpoint`): its layout (every field
present with its type, :class:`Layout`), its checksums, its weights finite, its scenario and hyperparameters
valid. Whatever is wrong with a file is one :class:`TrainError` sentence naming it, never a traceback."""

from __future__ import annotations

import hashlib
from pathlib import Path
from typing import Any, Callable, Iterator, Mapping

import torch
from pydantic import BaseModel, ConfigDict, Field, ValidationError

from ..base.errors import ScenarioError, got
from ..compiler import CompiledScenario, as_written, compile, written
from ..lang.spec.validate import describe
from .config import PPOConfig, TrainError
from .devices import torch_device
from .networks import ActionLayout, ActorCritic
from .rundir import RunDir, write_atomically

# Format 2 checksums every field; format 1 (checksums of the weights and training state only) still loads to play
# and evaluate, its scenario checked against its fingerprint, but a run does not go on from it: its agent-steps and
# hyperparameters are not covered (an agent_steps edited to 10**9 resumed and trained nothing).
FORMAT = "hivex-ppo/2"
OLDER_FORMATS = ("hivex-ppo/1",)
# the fields outside the weights and the training state, checksummed together as "fields"
FIELDS = ("format", "config", "scenario", "fingerprint", "agent_steps", "wall_s")
# the sections a SHA-256 checksum guards, and what a mismatch means
CHECKSUMMED = {"model": "its weights do not match their checksum",
               "training": "its training state (optimizers, curiosity module, curve) does not match its checksum",
               "fields": f"its fields ({', '.join(FIELDS)}) do not match their checksum"}


class LayoutPart(BaseModel):
    """A part of a checkpoint's layout: strictly typed, and blind to keys it does not read."""

    model_config = ConfigDict(strict=True, arbitrary_types_allowed=True, allow_inf_nan=False, extra="ignore")


class OptimizerState(LayoutPart):
    """``torch.optim.Optimizer.state_dict()``."""

    state: dict[int, dict[str, torch.Tensor]]
    param_groups: list[dict[str, Any]]


class TrainingState(LayoutPart):
    """What a run goes on from (``--resume``): the optimizers, the curiosity module and the curve so far."""

    optimizer: OptimizerState
    curiosity: dict[str, torch.Tensor] | None = None
    curiosity_optimizer: OptimizerState | None = None
    curve: list[dict[str, float | dict[str, float]]]  # a point's numbers, and its statistics by name
    resumed_at: list[int] = []
    machines: list[str] = []  # the machines it trained on, in words (devices.machine), each once as first used


class Layout(LayoutPart):
    """A checkpoint file's fields and their types (``wall_s`` came later, and a numbered checkpoint holds weights
    only, no ``training``; the ``checksums`` :func:`_check_checksums` requires)."""

    format: str
    model: dict[str, torch.Tensor]
    config: dict[str, Any]
    scenario: dict[str, Any]
    fingerprint: str
    agent_steps: int = Field(ge=0)
    wall_s: float | None = Field(None, ge=0)
    training: TrainingState | None = None
    checksums: dict[str, str] | None = None


def save_checkpoint(path: Path, agent: ActorCritic, cfg: PPOConfig, compiled: CompiledScenario,
                    agent_steps: int, wall_s: float | None = None, training: dict[str, Any] | None = None,
                    write: Callable[[Path, Callable[[Path], None]], None] = write_atomically) -> Path:
    """Write one checkpoint (weights, hyperparameters, the resolved scenario and its fingerprint, and the
    training's agent-steps and wall seconds when it was taken). ``training`` (optimizer states, the curiosity
    module, the learning curve so far) makes it resumable: the run directory's ``checkpoint.pt`` carries it.
    The weights and the training state each carry a SHA-256 checksum (:func:`checksum`), checked on load.

    The file is written beside and then renamed over ``path``, so a run killed mid-write leaves the previous
    checkpoint whole (``write``: :func:`.rundir.write_atomically`, or a claimed run directory's, which records it)."""
    path.parent.mkdir(parents=True, exist_ok=True)
    data = {"format": FORMAT, "model": agent.state_dict(), "config": cfg.model_dump(mode="json"),
            "scenario": compiled.resolved(), "fingerprint": compiled.fingerprint,
            "agent_steps": int(agent_steps), "wall_s": None if wall_s is None else round(float(wall_s), 3)}
    if training is not None:
        data["training"] = training
    data["checksums"] = seal(data)
    write(path, lambda partial: torch.save(data, partial))
    return path


def save_numbered_checkpoint(run: RunDir, agent: ActorCritic, cfg: PPOConfig, compiled: CompiledScenario,
                             steps: int, wall: float) -> None:
    """Save ``checkpoints/step_N.pt`` in the claimed run directory ``run`` and keep only the newest
    ``cfg.keep_checkpoints`` of the run's own."""
    folder = run.root / "checkpoints"
    save_checkpoint(folder / f"step_{steps:012d}.pt", agent, cfg, compiled, steps, wall, write=run.write)
    for old in sorted(folder.glob("step_*.pt"))[:-cfg.keep_checkpoints]:
        run.remove(old)


def sections(data: dict[str, Any]) -> dict[str, Any]:
    """The checkpoint's :data:`CHECKSUMMED` sections: its weights, its training state (where it has one) and
    every other field of :data:`FIELDS` together."""
    found = {section: data[section] for section in ("model", "training") if section in data}
    return found | {"fields": {key: data.get(key) for key in FIELDS}}


def seal(data: dict[str, Any]) -> dict[str, str]:
    """The checksums of every section of ``data`` (:func:`sections`), as a checkpoint of this content carries."""
    return {section: checksum(value) for section, value in sections(data).items()}


def checksum(section: Any) -> str:
    """The SHA-256 hex digest of a checkpoint's section: every tensor's dtype, shape and bytes and every plain
    value, each with its place, in sorted key order (so it does not depend on how the mapping was built)."""
    digest = hashlib.sha256()
    for place, leaf in _leaves(section, ()):
        digest.update(repr(place).encode())
        digest.update(_leaf_bytes(leaf))
    return digest.hexdigest()


def _leaves(tree: Any, place: tuple) -> Iterator[tuple[tuple, Any]]:
    """(place, value) of every tensor and plain value in nested mappings and sequences, keys sorted."""
    if isinstance(tree, Mapping):
        for key in sorted(tree, key=repr):
            yield from _leaves(tree[key], place + (key,))
    elif isinstance(tree, (list, tuple)):
        for index, item in enumerate(tree):
            yield from _leaves(item, place + (index,))
    else:
        yield place, tree


def _leaf_bytes(leaf: Any) -> bytes:
    """A tensor's dtype, shape and raw bytes; a plain value's repr."""
    if not isinstance(leaf, torch.Tensor):
        return repr(leaf).encode()
    flat = leaf.detach().cpu().contiguous().reshape(-1)
    return f"{flat.dtype}{tuple(leaf.shape)}".encode() + flat.view(torch.uint8).numpy().tobytes()


def load_checkpoint(path: str | Path) -> dict[str, Any]:
    """The checkpoint's content, with ``config`` as a PPOConfig, ``compiled`` the scenario it trained on and
    ``path`` where it was read; a file that is not a whole, valid checkpoint is a :class:`TrainError`."""
    data = _read(Path(path))
    _check_layout(path, data)
    _check_checksums(path, data)
    _check_finite(path, data["model"], "weight tensor")
    _check_finite(path, data.get("training") or {}, "training state's tensor")
    data["compiled"] = _compiled(path, data["scenario"])
    if data["compiled"].fingerprint != data["fingerprint"]:
        raise TrainError(f"{path} is corrupt: its scenario's fingerprint is {data['compiled'].fingerprint}, not the "
                         f"{_one_line(data['fingerprint'])} it trained on (its scenario was edited after training)")
    data["config"] = _hyperparameters(path, data["config"], data["compiled"])
    data["path"] = Path(path)
    return data


def _read(path: Path) -> dict[str, Any]:
    """What ``torch.load`` reads (tensors and plain data only), which says it is of this :data:`FORMAT`."""
    try:
        data = torch.load(path, map_location="cpu", weights_only=True)
    except FileNotFoundError:
        raise TrainError(f"no checkpoint at {path}") from None
    except IsADirectoryError:
        raise TrainError(f"{path} is a directory: give the checkpoint file in it ({path / 'checkpoint.pt'})") from None
    except Exception:  # torch raises many kinds for a file that is not a checkpoint
        # not torch's own advice (load with weights_only=False), which would run whatever code the file holds
        raise TrainError(f"{path} is not a hivex checkpoint: torch.load(weights_only=True) cannot read it, and a "
                         "hivex checkpoint holds tensors and plain data only") from None
    written = data.get("format") if isinstance(data, dict) else None
    if written not in (FORMAT, *OLDER_FORMATS):
        also = (f" (it says format {written!r}: written by another version of hivex?)"
                if isinstance(written, str) else "")
        raise TrainError(f"{path} is not a hivex checkpoint of format {FORMAT!r}{also}")
    return data


def _check_layout(path: str | Path, data: dict[str, Any]) -> None:
    """Every field :class:`Layout` names is there with its type, or a TrainError says which is not."""
    try:
        Layout.model_validate(data)
    except ValidationError as exc:
        problems = "; ".join(dict.fromkeys(_layout_problem(err) for err in exc.errors(include_url=False)))
        raise TrainError(_one_line(f"{path} is not a valid hivex checkpoint: {problems}")) from None


# what a value of each pydantic error kind should have been
EXPECTED_KIND = {"dict_type": "a mapping", "model_type": "a mapping", "int_type": "an integer",
                 "float_type": "a number", "string_type": "a string", "list_type": "a list",
                 "is_instance_of": "a tensor", "finite_number": "a finite number"}


def _layout_problem(err: dict[str, Any]) -> str:
    """One pydantic error of :class:`Layout` as a clause: "its 'config' is a list, expected a mapping"."""
    loc, kind, value = err["loc"], err["type"], err.get("input")
    if kind == "missing":
        return f"it has no {_place(loc)}"
    expected = EXPECTED_KIND.get(kind) or err["msg"].removeprefix("Input should be ")
    if loc and loc[-1] == "[key]":
        return f"its {_place(loc[:-2])} has the key {_got(loc[-2])}, expected {expected}"
    return f"its {_place(loc)} is {_got(value)}, expected {expected}"


def _place(loc: tuple) -> str:
    """``('training', 'curve', 3, 'return')`` -> ``'training.curve.3.return'``."""
    return repr(".".join(str(part) for part in loc))


def _got(value: Any) -> str:
    """What a value is, in a message: ``'x' (a string)``, ``a list``, ``a tensor``."""
    return "a tensor" if isinstance(value, torch.Tensor) else got(value)


def _one_line(message: str) -> str:
    """``message`` with every character visible and on one line (keys read from a file may hold anything)."""
    return "".join(c if c.isprintable() else c.encode("unicode_escape").decode() for c in message)


def _check_checksums(path: str | Path, data: dict[str, Any]) -> None:
    """Each :data:`CHECKSUMMED` section is what was saved: all three in :data:`FORMAT`, the weights and the
    training state in the :data:`OLDER_FORMATS`. A file without checksums is refused: nothing says its content
    is what training saved."""
    saved = data.get("checksums")
    if saved is None:
        raise TrainError(f"{path} carries no checksums, so nothing says its weights, scenario and agent-steps are "
                         "what training saved (removed from the file, or written before checkpoints carried them): "
                         "train again")
    found = sections(data)
    required = set(found) if data["format"] == FORMAT else set(found) - {"fields"}
    for section in required | (set(saved) & set(CHECKSUMMED)):
        if section not in found:
            raise TrainError(f"{path} is corrupt: it has no {section!r}, which its checksums cover")
        if saved.get(section) != checksum(found[section]):
            raise TrainError(f"{path} is corrupt: {CHECKSUMMED[section]}")


def _check_finite(path: str | Path, tensors: Any, what: str) -> None:
    """No tensor in ``tensors`` (nested mappings and lists) is NaN or infinite: a policy of such weights acts on
    NaN probabilities, and an optimizer of such moments makes them so in its first step."""
    for place, tensor in _leaves(tensors, ()):
        if isinstance(tensor, torch.Tensor) and tensor.is_floating_point() and not bool(torch.isfinite(tensor).all()):
            found = "NaN" if bool(torch.isnan(tensor).any()) else "an infinite value"
            name = ".".join(str(part) for part in place)
            raise TrainError(_one_line(f"{path} is corrupt: its {what} {name!r} holds {found}"))


def _compiled(path: str | Path, scenario: dict[str, Any]) -> CompiledScenario:
    """The scenario the checkpoint trained on, compiled, params added since read as they meant then, under the
    fingerprint it was written with."""
    try:
        return written(compile(as_written(scenario)), scenario)
    except ScenarioError as exc:
        problems = "; ".join(problem.message for problem in exc.problems)
        raise TrainError(_one_line(f"{path} holds a scenario that does not compile: {problems}")) from None


def _hyperparameters(path: str | Path, config: dict[str, Any], compiled: CompiledScenario) -> PPOConfig:
    """The checkpoint's hyperparameters, keys added since it was written read as they meant then."""
    try:
        return PPOConfig.model_validate(older_defaults(config, *acting_interface(compiled)))
    except ValidationError as exc:
        problems = "; ".join(describe(err, err["loc"][:1], PPOConfig)[0] for err in exc.errors(include_url=False))
        raise TrainError(_one_line(f"{path} holds bad hyperparameters: {problems}")) from None


# keys added since, with what their absence meant for every policy alike
ALWAYS_THEN: dict[str, Any] = {"weight_init": "cleanrl", "summary_freq": 1, "value_loss": "clipped"}


def older_defaults(config: dict[str, Any], action_space: Any, masks_actions: bool = False) -> dict[str, Any]:
    """The hyperparameters ``config`` of a checkpoint (or record) of a policy over ``action_space`` (in an
    environment that ``masks_actions`` or not), with what a key added since meant when they were written, where it
    changes anything for this policy: every policy from before ``weight_init`` started from ``cleanrl`` weights, a
    curiosity module from before ``curiosity_module`` is ``hivex_v1``, continuous actions from before
    ``continuous_actions`` were clipped, more than one action dimension from before ``policy_loss`` shared one
    ``joint`` ratio, every run from before ``summary_freq`` wrote a curve point every update (``summary_freq: 1``),
    a policy from before ``action_masks`` ignored its environment's masks, and every critic from before
    ``value_loss`` learned under the ``clipped`` trust region (:data:`ALWAYS_THEN`). (``max_grad_norm`` was
    always written.)"""
    layout = ActionLayout.of(action_space)
    then: dict[str, Any] = dict(ALWAYS_THEN)
    if masks_actions:
        then["action_masks"] = False
    strength = config.get("curiosity_strength", 0)
    if isinstance(strength, (int, float)) and strength > 0:  # not a number: PPOConfig says so
        then["curiosity_module"] = "hivex_v1"
    if layout.continuous:
        then["continuous_actions"] = "clip"
    if layout.continuous + len(layout.nvec) > 1:
        then["policy_loss"] = "joint"
    return then | config


def acting_interface(compiled: CompiledScenario) -> tuple[Any, bool]:
    """The single-agent action space of ``compiled`` and whether its environment masks actions (one world built,
    not reset)."""
    from ..adapters.gymnasium import HivexVectorEnv

    env = HivexVectorEnv(compiled, num_worlds=1)
    return env.single_action_space, env.core.masks_actions


def policy_for(checkpoint: dict[str, Any], compiled: CompiledScenario, device: str = "cpu") -> ActorCritic:
    """The checkpoint's network, to play ``compiled``: another scenario of the environment it trained on (another
    task, level or seeds), never another environment."""
    agent, _ = _network_of(checkpoint, compiled)
    return agent.to(torch_device(device)).eval()


def _network_of(checkpoint: dict[str, Any], compiled: CompiledScenario) -> tuple[ActorCritic, Any]:
    """The checkpoint's network for ``compiled``, its weights loaded, and the observation space it was built for."""
    from ..adapters.gymnasium import HivexVectorEnv

    trained = checkpoint["compiled"]
    if trained.environment != compiled.environment:
        raise TrainError(f"the checkpoint trained on {trained.environment} (scenario {trained.name!r}) and cannot play "
                         f"{compiled.environment} (scenario {compiled.name!r}): a policy plays the environment it "
                         "trained on")
    env = HivexVectorEnv(compiled, num_worlds=1)
    agent = ActorCritic(env.single_observation_space, env.single_action_space, checkpoint["config"])
    try:
        agent.load_state_dict(checkpoint["model"])
    except RuntimeError as exc:  # the same environment, so the file's weights were changed after training
        whose = f"{checkpoint['path']}'s" if "path" in checkpoint else "the checkpoint's"
        raise TrainError(_one_line(f"{whose} weights do not fit the network its own hyperparameters build: "
                                   f"{_first_lines(exc)}")) from None
    return agent, env.single_observation_space


def _first_lines(exc: Exception) -> str:
    """The first two lines of torch's message, as one ("Error(s) in loading ...: size mismatch for ...")."""
    lines = [line.strip() for line in str(exc).splitlines() if line.strip()]
    return " ".join(lines[:2])


# what may change when a run goes on: how long it trains and where and how it runs, not what it learns
RESUMABLE_CHANGES = frozenset({"max_steps", "device", "torch_threads", "checkpoint_every", "keep_checkpoints",
                               "summary_freq"})


def resume_state(path: Path, compiled: CompiledScenario, cfg: PPOConfig) -> dict[str, Any]:
    """The checkpoint a run goes on from, checked to be resumable with ``compiled`` and ``cfg``: the same
    scenario (fingerprint) and the same hyperparameters but for :data:`RESUMABLE_CHANGES`, and weights and
    training state that the run's modules take."""
    if not path.is_file():
        raise TrainError(f"cannot resume: no checkpoint at {path} (train without --resume first)")
    data = load_checkpoint(path)
    if data["format"] != FORMAT:
        raise TrainError(f"cannot resume from {path}: it is of format {data['format']!r}, whose checksums do not cover "
                         "its agent-steps and hyperparameters; it plays and evaluates, but a run goes on only from a "
                         f"checkpoint of format {FORMAT!r}: train again")
    if data.get("training") is None:
        raise TrainError(f"cannot resume from {path}: it holds weights only, not the optimizer state")
    if data["fingerprint"] != compiled.fingerprint:
        raise TrainError(f"cannot resume from {path}: it trained scenario {data['compiled'].name!r}, which differs "
                         f"from {compiled.name!r} (fingerprint {data['fingerprint']} != {compiled.fingerprint})")
    before, now = data["config"].model_dump(), cfg.model_dump()
    changed = sorted(k for k in now if before[k] != now[k] and k not in RESUMABLE_CHANGES)
    if changed:
        listing = ", ".join(f"{k}: {before[k]!r} -> {now[k]!r}" for k in changed)
        raise TrainError(f"cannot resume from {path}: hyperparameters differ from the run's ({listing}); "
                         f"only {', '.join(sorted(RESUMABLE_CHANGES))} may change")
    _check_resumable(path, data, compiled)
    return data


def _check_resumable(path: Path, data: dict[str, Any], compiled: CompiledScenario) -> None:
    """The modules a run builds take the checkpoint's weights, optimizer states and curiosity module (a file
    edited after training may hold states of other shapes)."""
    from .curiosity import Curiosity

    agent, observations = _network_of(data, compiled)
    modules: dict[str, Any] = {"optimizer": torch.optim.Adam(agent.parameters())}
    if data["config"].curiosity_strength > 0:
        curiosity = Curiosity(observations, agent.layout, data["config"])
        modules |= {"curiosity": curiosity, "curiosity_optimizer": torch.optim.Adam(curiosity.parameters())}
    for name, module in modules.items():
        state = data["training"].get(name)
        if state is None:
            raise TrainError(f"cannot resume from {path}: it holds no {name} state, which its hyperparameters train")
        try:
            module.load_state_dict(state)
            if isinstance(module, torch.optim.Optimizer):
                _check_moments(module)
        except (RuntimeError, ValueError, KeyError, TypeError, IndexError) as exc:  # torch's kinds for a bad state
            raise TrainError(_one_line(f"cannot resume from {path}: its {name} state does not fit the run's: "
                                       f"{_first_lines(exc) or type(exc).__name__}")) from None


def _check_moments(optimizer: torch.optim.Optimizer) -> None:
    """Every per-parameter state tensor (Adam's moments) has its parameter's shape (loading does not check)."""
    for group in optimizer.param_groups:
        for parameter in group["params"]:
            for key, value in optimizer.state.get(parameter, {}).items():
                if isinstance(value, torch.Tensor) and value.dim() and value.shape != parameter.shape:
                    raise ValueError(f"{key} of a parameter of shape {tuple(parameter.shape)} has shape "
                                     f"{tuple(value.shape)}")
