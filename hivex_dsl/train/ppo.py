"""Parameter-shared PPO over the batched vector env, CleanRL-style: one file, read top to bottom.

Every (world, agent) slot of ``HivexVectorEnv`` is one actor of one shared policy, as in the paper.
The env autoresets in Gymnasium's NEXT_STEP mode: after a step that ends a slot's episode, the slot's
next step ignores its action and returns its fresh observation with reward 0. That reset transition is
no experience of the policy, so it is masked out of the loss, and GAE never flows across an episode's end.
A slot that reports ``infos["active"] == False`` (an agent that died while its world goes on, when the env
keeps it out until its world resets) is masked the same way.

Hyperparameters and their ML-Agents meaning: ``config.py``.
"""

from __future__ import annotations

import time
from pathlib import Path
from typing import Any, Callable

import numpy as np
import torch
from torch import nn

from ..adapters.gymnasium import EndedAgents, HivexVectorEnv
from ..compiler import CompiledScenario
from .checkpoint import resume_state, save_checkpoint, save_numbered_checkpoint
from .config import PPOConfig, TrainError
from .curiosity import Curiosity
from .devices import autocast, machine, matmul_precision, torch_device
from .kernels import cpu_kernels
from .lag import PolicyLag
from .logs import EpisodeLog, Progress, ScalarLog
from .networks import VALUE_HEADS, ActorCritic, fixed_weights, to_tensors
from .buffer import FinishedTrajectories, Rollout, in_chunks, minibatches, update_data
from .rundir import RunDir
from .stopping import StopRequests


def gae(rewards: torch.Tensor, values: torch.Tensor, next_value: torch.Tensor, terminated: torch.Tensor,
        done: torch.Tensor, gamma: float | torch.Tensor, lam: float) -> tuple[torch.Tensor, torch.Tensor]:
    """Generalized advantage estimates and returns of a (T, S) rollout, or of (T, S, K) rewards and values of
    K reward signals with a (K,) tensor ``gamma`` (the masks are (T, S) either way).

    ``values[t]`` is V(obs_t); ``next_value`` (S,) is V of the observation after the last step.
    A step that ``terminated`` bootstraps from 0; one that was truncated from V of the observation it
    returned (in NEXT_STEP mode the episode's last observation). ``done`` = terminated | truncated stops
    the recursion, so the masked reset transition after an ending never leaks into the step before it.
    """
    steps = rewards.shape[0]
    trailing = (1,) * (rewards.dim() - terminated.dim())  # per-signal axes: the masks broadcast over them
    terminated, done = terminated.reshape(terminated.shape + trailing), done.reshape(done.shape + trailing)
    advantages = torch.zeros_like(rewards)
    running = torch.zeros_like(next_value)
    for t in reversed(range(steps)):
        following = next_value if t == steps - 1 else values[t + 1]
        delta = rewards[t] + gamma * following * (1.0 - terminated[t]) - values[t]
        running = delta + gamma * lam * (1.0 - done[t]) * running
        advantages[t] = running
    return advantages, advantages + values


def make_env(compiled: CompiledScenario, num_worlds: int, split: str, ended_agents: EndedAgents = "respawn",
             seed: int | None = None) -> tuple[HivexVectorEnv, Any, dict[str, Any]]:
    """The vector env on ``split``, its first observations and the reset's infos, reset on ``seed`` or, where it is
    None, the split's seed (explicitly, so every run of one seed plays the same worlds); ``ended_agents``: see
    :class:`HivexVectorEnv`."""
    try:
        env = HivexVectorEnv(compiled, num_worlds=num_worlds, split=split, ended_agents=ended_agents)
    except ValueError as exc:
        raise TrainError(f"cannot run {compiled.name!r} on its {split} seeds: {exc}") from None
    observations, infos = env.reset(seed=int(getattr(compiled.seeds, split) if seed is None else seed))
    return env, observations, infos


def make_optimizer(agent: nn.Module, learning_rate: float) -> torch.optim.Optimizer:
    """Adam with its fused kernel (one pass over all parameters: the small networks' update is dominated by
    per-tensor overhead otherwise), or the per-tensor loop where this torch build has no fused Adam."""
    try:
        return torch.optim.Adam(agent.parameters(), lr=learning_rate, fused=True)
    except (RuntimeError, TypeError):
        return torch.optim.Adam(agent.parameters(), lr=learning_rate)


def acting_mask(previous_done: np.ndarray, active: np.ndarray) -> np.ndarray:
    """Slots whose action this step is a real experience: not the NEXT_STEP reset after an ending, and live."""
    return ~previous_done & active


def schedule(cfg: PPOConfig, progress: float) -> tuple[float, float, float]:
    """(learning rate, beta, epsilon) at ``progress`` in [0, 1]: ML-Agents' linear decay, or constant."""
    if cfg.learning_rate_schedule == "constant":
        return cfg.learning_rate, cfg.beta, cfg.epsilon
    left = max(0.0, 1.0 - progress)
    lerp = lambda start, end: end + (start - end) * left  # noqa: E731 - ML-Agents decays towards these floors
    return cfg.learning_rate * left, lerp(cfg.beta, 1e-5), lerp(cfg.epsilon, 0.1)


def start_rollouts(observations: Any, agent: ActorCritic, steps: int, infos: dict[str, Any] | None = None
                   ) -> tuple[dict[str, Any], Rollout]:
    """The collection state after a reset to ``observations`` and its ``infos`` (obs, previous done, active, the
    action mask where ``agent`` takes the env's; see :func:`collect`) and the (``steps``, slots) storage its
    rollouts fill, sized for ``agent``'s actions, value heads and masks."""
    obs = to_tensors(observations)
    slots = next(iter(obs.values())).shape[0]
    state = {"obs": obs, "done": np.zeros(slots, bool), "active": np.ones(slots, bool),
             "mask": action_mask(infos or {}, agent)}
    width = 0 if state["mask"] is None else state["mask"].shape[1]
    return state, rollout_storage(obs, agent, steps, width)


def action_mask(infos: dict[str, Any], agent: ActorCritic) -> torch.Tensor | None:
    """The open choices (slots, N) bool of the vector env's ``infos["action_mask"]`` where ``agent`` takes masks;
    None otherwise (every choice open)."""
    mask = infos.get("action_mask")
    return torch.as_tensor(mask, dtype=torch.bool) if mask is not None and agent.takes_masks else None


def rollout_storage(obs: dict[str, torch.Tensor], agent: ActorCritic, steps: int, mask_width: int = 0) -> Rollout:
    """The (``steps``, slots) storage of rollouts from observations like ``obs`` (slots, ...) for ``agent``, with
    action masks of ``mask_width`` choices (none at 0)."""
    slots = next(iter(obs.values())).shape[0]
    return Rollout(steps, slots, obs, agent.layout.continuous, len(agent.layout.nvec), agent.signals,
                   agent.logp_columns, mask_width)


def planned_agent_steps(max_steps: int, done: int, slots: int) -> int:
    """The agent-steps a run that has ``done`` ends at: ``max_steps`` rounded up to a whole decision of every slot
    (worlds x agents step together), so it overshoots by less than ``slots``; ``done`` if that is already past."""
    return done if done >= max_steps else done + -(-(max_steps - done) // slots) * slots


def update_due(cfg: PPOConfig, slots: int) -> Callable[[np.ndarray, np.ndarray], bool] | None:
    """When a rollout of ``slots`` ends before its length (``collect``'s ``until``): with ``buffer_fill:
    trajectories`` once its finished trajectories exceed ``buffer_size`` (ML-Agents'), else never (None)."""
    if cfg.buffer_fill != "trajectories":
        return None
    return FinishedTrajectories(slots, cfg.time_horizon, cfg.buffer_size).step


def forward_precision(cfg: PPOConfig):
    """The context of a forward pass under ``cfg.precision``: bfloat16 autocast for ``bf16``, else none."""
    return autocast(cfg.precision, torch_device(cfg.device))


def collect(env: HivexVectorEnv, agent: ActorCritic, buf: Rollout, state: dict[str, Any], cfg: PPOConfig,
            episodes: EpisodeLog, on_step: Callable[[], None] | None = None,
            until: Callable[[np.ndarray, np.ndarray], bool] | None = None, steps: int | None = None,
            lag: PolicyLag | None = None) -> torch.Tensor:
    """Fill ``buf`` with one rollout from ``state`` (obs, previous done, active, mask) of ``steps`` (default: the
    storage's capacity); -> V(next obs) (S,). ``on_step`` (optional) is called after each step of every slot (the
    progress bar moves within a rollout). ``until`` (optional; :func:`update_due`) is asked after each step with the
    slots whose step was an experience and those whose episode ended (both (S,) bool); when it says True the rollout
    ends there, ``buf`` limited to the steps taken. ``lag`` (optional): its kept weights act the first steps
    (:mod:`.lag`).

    The policy acts step by step; the critic values every frame once the rollout is done (as ML-Agents' trajectory
    processing does), in batches of thousands rather than one slot batch a step: the weights are the same
    throughout, so are the values (``tests/train/test_exact_speedups.py``), at a fraction of the CPU time."""
    buf.limit(buf.capacity if steps is None else steps)
    with fixed_weights():
        _act_and_step(env, agent, buf, state, cfg, episodes, on_step, until, lag)
    buf.end(state["obs"])
    return rollout_values(agent, buf, cfg)


def _act_and_step(env: HivexVectorEnv, agent: ActorCritic, buf: Rollout, state: dict[str, Any], cfg: PPOConfig,
                  episodes: EpisodeLog, on_step: Callable[[], None] | None,
                  until: Callable[[np.ndarray, np.ndarray], bool] | None, lag: PolicyLag | None = None) -> None:
    """:func:`collect`'s steps: the policy acts on ``state``, the environment steps, ``buf`` records both."""
    for t in range(buf.rewards.shape[0]):
        obs = state["obs"]
        for k, v in obs.items():
            buf.obs[k][t] = v
        valid = acting_mask(state["done"], state["active"])
        buf.valid[t] = torch.as_tensor(valid, dtype=torch.float32)
        # None: every choice open (no masks, an agent that takes none, or a storage made without them)
        mask = state.get("mask") if buf.mask is not None else None
        if mask is not None:
            buf.mask[t] = mask
        with torch.no_grad(), forward_precision(cfg):
            cont, disc, logp = (agent if lag is None else lag.actor(agent, t)).act(obs, mask=mask)
        buf.cont[t], buf.disc[t], buf.logp[t] = cont, disc, logp
        next_obs, reward, terminated, truncated, infos = env.step(agent.layout.to_env(cont, disc))
        done = terminated | truncated
        buf.rewards[t] = torch.as_tensor(reward, dtype=torch.float32) * cfg.reward_strength
        buf.terminated[t] = torch.as_tensor(terminated, dtype=torch.float32)
        buf.done[t] = torch.as_tensor(done, dtype=torch.float32)
        episodes.record(infos)
        state["obs"], state["done"], state["mask"] = to_tensors(next_obs), done, action_mask(infos, agent)
        state["active"] = np.asarray(infos.get("active", np.ones_like(done)), dtype=bool)
        if on_step is not None:
            on_step()
        if until is not None and until(valid, done):
            buf.limit(t + 1)
            break


def rollout_values(agent: ActorCritic, buf: Rollout, cfg: PPOConfig) -> torch.Tensor:
    """V of every frame of ``buf``: the observations' into ``buf.values`` (T, S[, K]); -> the last frame's (S[, K])."""
    with torch.no_grad(), forward_precision(cfg):
        values = in_chunks(agent.get_value, buf.flat_frames()).float()
    values = values.reshape((-1,) + buf.values.shape[1:])
    buf.values.copy_(values[:-1])
    return values[-1]


def update(agent: ActorCritic, optimizer: torch.optim.Optimizer, buf: Rollout, advantages: torch.Tensor,
           returns: torch.Tensor, cfg: PPOConfig, beta: float, epsilon: float,
           rng: np.random.Generator, curiosity: tuple[Curiosity, torch.optim.Optimizer] | None = None
           ) -> dict[str, float]:
    """``num_epoch`` passes of minibatch PPO over the valid experiences only; -> mean losses.

    ``advantages`` (T, S) are the signals' summed; ``returns`` (T, S) or (T, S, K) one column per value head.
    With ``curiosity`` (the module and its optimizer) each minibatch also trains it (ML-Agents does so)."""
    data, valid = update_data(buf, advantages, returns, with_next_obs=curiosity is not None)
    if valid.size == 0:
        return {}
    params = list(agent.parameters())
    losses: dict[str, list[torch.Tensor]] = {"policy": [], "value": [], "entropy": []}
    log_ratios = []  # detached, for approx_kl and clipfrac once per update (not a dozen small ops per minibatch)
    for _ in range(cfg.num_epoch):
        for mb in minibatches(data, valid, cfg.batch_size, rng, buf.gathered):
            with forward_precision(cfg):
                loss, (policy_loss, value_loss, entropy, log_ratio) = ppo_loss(
                    agent, mb, beta, epsilon, clip_value=cfg.value_loss == "clipped")
            optimizer.zero_grad()
            loss.backward()
            if cfg.max_grad_norm > 0:
                nn.utils.clip_grad_norm_(params, cfg.max_grad_norm, foreach=True)
            optimizer.step()
            if curiosity is not None:
                forward, inverse = train_curiosity(*curiosity, mb, cfg)
                losses.setdefault("curiosity_forward", []).append(forward)
                losses.setdefault("curiosity_inverse", []).append(inverse)
            # kept as tensors: one .item() per minibatch each would sync a GPU
            for name, term in (("policy", policy_loss), ("value", value_loss), ("entropy", entropy)):
                losses[name].append(term.detach())
            log_ratios.append(log_ratio.detach())
    return {k: float(torch.stack(v).mean()) for k, v in losses.items()} | ratio_stats(torch.cat(log_ratios), epsilon)


def ppo_loss(agent: ActorCritic, mb: dict[str, Any], beta: float, epsilon: float, clip_value: bool = True
             ) -> tuple[torch.Tensor, tuple[torch.Tensor, ...]]:
    """ML-Agents' PPO loss of a minibatch: the clipped surrogate, 0.5 x the value loss (with ``clip_value`` its
    estimates clipped within ``epsilon`` of the old ones, ML-Agents' trust region), minus beta x the entropy;
    -> (loss, (policy loss, value loss, mean entropy, log-ratios (B,) or (B, D))).

    With one log-probability per action dimension (B, D), each dimension's ratio is clipped on its own against
    the shared advantage and the surrogate is their mean (ML-Agents' trust_region_policy_loss)."""
    logp, entropy, value = agent.evaluate(mb["obs"], mb["cont"], mb["disc"], mb.get("mask"))
    log_ratio = logp - mb["old_logp"]
    ratio = log_ratio.exp()
    adv = mb["adv"] if log_ratio.dim() == 1 else mb["adv"][:, None]
    policy_loss = torch.max(-adv * ratio, -adv * ratio.clamp(1 - epsilon, 1 + epsilon)).mean()
    value_loss = (value - mb["returns"]).square()
    if clip_value:
        clipped = mb["old_values"] + (value - mb["old_values"]).clamp(-epsilon, epsilon)
        value_loss = torch.max(value_loss, (clipped - mb["returns"]).square())
    value_loss = value_loss.mean()
    entropy = entropy.mean()
    return policy_loss + 0.5 * value_loss - beta * entropy, (policy_loss, value_loss, entropy, log_ratio)


def ratio_stats(log_ratio: torch.Tensor, epsilon: float) -> dict[str, float]:
    """Over every (epoch, sample) log probability ratio log(pi/pi_old) (N,): the approximate KL divergence
    from the rollout's policy, E[(r - 1) - log r] (CleanRL's k3 estimator), and the share of ratios clipped."""
    ratio = log_ratio.exp()
    return {"approx_kl": float(((ratio - 1) - log_ratio).mean()),
            "clipfrac": float(((ratio - 1).abs() > epsilon).float().mean())}


def train_curiosity(module: Curiosity, optimizer: torch.optim.Optimizer, mb: dict[str, Any], cfg: PPOConfig
                    ) -> tuple[torch.Tensor, torch.Tensor]:
    """One gradient step of the curiosity module on a minibatch; -> its (forward, inverse) losses."""
    with forward_precision(cfg):
        total, forward, inverse = module.loss(mb["obs"], mb["next_obs"], mb["cont"], mb["disc"])
    optimizer.zero_grad()
    total.backward()
    optimizer.step()
    module.updated.fill_(True)
    return forward, inverse


def advantages_and_returns(buf: Rollout, next_value: torch.Tensor, cfg: PPOConfig, curiosity: Curiosity | None,
                           episodes: EpisodeLog | None = None) -> tuple[torch.Tensor, torch.Tensor, dict[str, float]]:
    """GAE of every reward signal -> (summed advantages (T, S), returns (T, S[, K]), charts).

    With curiosity, its rewards for the rollout come from the module as it is now (ML-Agents rewards a
    trajectory when it is processed), over valid transitions only, and are discounted with its own gamma;
    ``episodes`` gets them, to report each agent-episode's sum (the original's Curiosity Reward panel)."""
    if curiosity is None:
        advantages, returns = gae(buf.rewards, buf.values, next_value, buf.terminated, buf.done, cfg.gamma, cfg.lambd)
        return advantages, returns, {}
    intrinsic = curiosity.rollout_rewards(buf.flat_frames(), buf.flat("cont"), buf.flat("disc"))
    intrinsic = intrinsic.reshape(buf.rewards.shape) * buf.valid
    if episodes is not None:
        episodes.record_signal("curiosity", intrinsic.numpy(), (buf.done * buf.valid).numpy() > 0)
    rewards = torch.stack([buf.rewards, intrinsic], dim=-1)
    gammas = torch.tensor([cfg.gamma, cfg.curiosity_gamma])
    advantages, returns = gae(rewards, buf.values, next_value, buf.terminated, buf.done, gammas, cfg.lambd)
    mean = float(intrinsic.sum() / buf.valid.sum().clamp(min=1))
    return advantages.sum(-1), returns, {"curiosity_reward": mean}


def train(compiled: CompiledScenario, cfg: PPOConfig, run_dir: Path, progress: bool = True,
          on_update: Callable[[dict[str, Any]], None] | None = None, resume: bool = False,
          overwrite: bool = False, stop_event: Any = None, run: RunDir | None = None) -> dict[str, Any]:
    """Train one policy for ``cfg.max_steps`` agent-steps; write checkpoints, scalars and curve.json
    under ``run_dir``; -> the run's summary (also written as summary.json). A ``run_dir`` that holds an
    earlier run is refused unless ``resume`` goes on from it or ``overwrite`` replaces it (:mod:`.rundir`).

    ``resume`` goes on from ``run_dir/checkpoint.pt`` (see :func:`resume_state`): the weights, both optimizers,
    the curiosity module, the agent-steps, wall time and learning curve so far. As in ML-Agents' ``--resume``
    the environments start afresh on the training worlds' seed, so a resumed run is not bit-identical to one never
    stopped. Ctrl-C, SIGTERM or setting ``stop_event`` stops the run after its update (:class:`StopRequests`).
    ``run``: the run directory already claimed (by a grid's point, which writes its evaluation there after)."""
    if cfg.precision_problem():
        raise TrainError(cfg.precision_problem())
    with cpu_kernels(cfg.cpu_kernels):  # pinned before the run directory is touched: a refusal writes nothing
        if run is not None:
            return _train(compiled, cfg, run, progress, on_update, resume, stop_event)
        with RunDir.claim(Path(run_dir), resume, overwrite) as claimed:
            return _train(compiled, cfg, claimed, progress, on_update, resume, stop_event)


def _train(compiled: CompiledScenario, cfg: PPOConfig, run: RunDir, progress: bool,
           on_update: Callable[[dict[str, Any]], None] | None, resume: bool, stop_event: Any) -> dict[str, Any]:
    """:func:`train` in the run directory ``run``, claimed."""
    run_dir = run.root
    cfg = cfg.model_copy(update={"torch_threads": cfg.threads()})  # `auto` written down as the count it ran on
    resumed = resume_state(run_dir / "checkpoint.pt", compiled, cfg) if resume else None
    done_before = resumed["agent_steps"] if resumed else 0
    torch.set_num_threads(cfg.torch_threads)
    torch.manual_seed(cfg.seed + done_before)
    rng = np.random.default_rng([cfg.seed, done_before])
    env, obs, infos = make_env(compiled, cfg.num_worlds, "train", cfg.ended_agents, cfg.own_worlds())
    agent = ActorCritic(env.single_observation_space, env.single_action_space, cfg).to(torch_device(cfg.device))
    optimizer = make_optimizer(agent, cfg.learning_rate)
    curiosity, curiosity_optimizer = None, None
    if cfg.curiosity_strength > 0:
        curiosity = Curiosity(env.single_observation_space, agent.layout, cfg).to(torch_device(cfg.device))
        curiosity_optimizer = make_optimizer(curiosity, cfg.curiosity_learning_rate)
    modules = {"optimizer": optimizer, "curiosity": curiosity, "curiosity_optimizer": curiosity_optimizer}
    if resumed:
        agent.load_state_dict(resumed["model"])
        for name, module in modules.items():
            if module is not None:
                module.load_state_dict(resumed["training"][name])
    slots, steps = env.num_envs, cfg.rollout_length(env.num_envs)
    state, buf = start_rollouts(obs, agent, steps, infos)
    lag = PolicyLag(agent, cfg.policy_lag_steps) if cfg.policy_lag_steps else None
    run.write_json("config.json", {"hyperparameters": cfg.model_dump(mode="json"), "scenario": compiled.resolved()})
    episodes, scalars = EpisodeLog(), ScalarLog(run)
    bar = Progress(planned_agent_steps(cfg.max_steps, done_before, slots), enabled=progress, label=compiled.name,
                   start=done_before)
    agent_steps, curve = done_before, list(resumed["training"]["curve"]) if resumed else []
    resumed_at = list(resumed["training"].get("resumed_at", [])) if resumed else []
    if resumed and done_before < cfg.max_steps:
        resumed_at.append(done_before)
    # the machines it trained on, each once in the order first used: a run reproduces only on alike processors
    before = resumed["training"].get("machines", []) if resumed else []
    machines = list(dict.fromkeys([*before, machine(cfg.device)]))
    wall_before = (resumed["wall_s"] or 0.0) if resumed else 0.0
    next_checkpoint = (agent_steps // cfg.checkpoint_every + 1) * cfg.checkpoint_every
    next_summary = (agent_steps // cfg.summary_freq + 1) * cfg.summary_freq  # ML-Agents' summary_freq
    started = time.perf_counter()

    def latest(steps: int, wall: float) -> None:
        """The run directory's resumable checkpoint.pt, and the curve so far (to follow a long run)."""
        training = {name: module.state_dict() for name, module in modules.items() if module is not None}
        save_checkpoint(run_dir / "checkpoint.pt", agent, cfg, compiled, steps, wall,
                        training | {"curve": curve, "resumed_at": resumed_at, "machines": machines}, write=run.write)
        run.write_json("curve.json", curve, indent=1)
        scalars.flush()

    with StopRequests(stop_event) as stop, matmul_precision(cfg.precision):  # Ctrl-C or SIGTERM: finish this update, then save
        while agent_steps < cfg.max_steps and not stop.requested:
            lr, beta, epsilon = schedule(cfg, agent_steps / cfg.max_steps)
            for group in optimizer.param_groups:
                group["lr"] = lr
            length = min(steps, -(-(cfg.max_steps - agent_steps) // slots))  # the last rollout stops at the budget
            next_value = collect(env, agent, buf, state, cfg, episodes, on_step=lambda: bar.advance(slots, None),
                                 until=update_due(cfg, slots), steps=length, lag=lag)
            length = buf.rewards.shape[0]
            episodes.record_estimates(VALUE_HEADS[:agent.signals], buf.values.numpy(), buf.valid.numpy() > 0,
                                      buf.done.numpy() > 0, cfg.time_horizon)
            agent.observe(buf.flat_obs())
            advantages, returns, signal_charts = advantages_and_returns(buf, next_value, cfg, curiosity, episodes)
            if lag is not None:
                lag.keep(agent)
            losses = update(agent, optimizer, buf, advantages, returns, cfg, beta, epsilon, rng,
                            None if curiosity is None else (curiosity, curiosity_optimizer))
            episodes.record_losses(losses)
            agent_steps += length * slots
            wall = wall_before + time.perf_counter() - started
            summarise = agent_steps >= next_summary or agent_steps >= cfg.max_steps or stop.requested
            summary = episodes.drain() if summarise else {}
            next_summary = (agent_steps // cfg.summary_freq + 1) * cfg.summary_freq if summarise else next_summary
            if summary:
                curve.append({"agent_steps": agent_steps, "wall_s": round(wall, 3), "return": summary["return"],
                              "episodes": summary["episodes"], "length": summary["length"],
                              "statistics": summary["statistics"],
                              **{f"{k}_reward": v for k, v in summary["signals"].items()},
                              **{f"{k}_value_estimate": v for k, v in summary["estimates"].items()},
                              **({"losses": summary["losses"]} if summary["losses"] else {})})
            scalars.write(agent_steps, summary, losses, {"learning_rate": lr, "beta": beta, "epsilon": epsilon,
                                                         "agent_steps_per_s": (agent_steps - done_before)
                                                         / max(wall - wall_before, 1e-9),
                                                         **signal_charts})
            bar.advance(0, summary.get("return"))
            if on_update is not None:
                on_update({"agent_steps": agent_steps, "wall_s": wall, **summary})
            if agent_steps >= next_checkpoint:
                save_numbered_checkpoint(run, agent, cfg, compiled, agent_steps, wall)
                latest(agent_steps, wall)
                next_checkpoint += cfg.checkpoint_every
    bar.close()
    scalars.close()
    wall = wall_before + time.perf_counter() - started
    latest(agent_steps, wall)
    result = {"scenario": compiled.name, "environment": compiled.environment, "task_index": compiled.task_index,
              "level": compiled.level, "agent_steps": agent_steps, "wall_s": round(wall, 3), "seed": cfg.seed,
              "final_return": curve[-1]["return"] if curve else None, "checkpoint": "checkpoint.pt",
              "stopped_early": stop.requested, "resumed_at": resumed_at, "machines": machines}
    run.write_json("summary.json", result)
    return result

