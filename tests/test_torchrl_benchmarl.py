"""TorchRL's and BenchMARL's multi-agent PPO train a few iterations on every environment (examples/torchrl_mappo.py,
examples/benchmarl_mappo.py), the BenchMARL tasks cover every environment and task, and an agent that ended
early is masked out while its world goes on. CI installs both (`torchrl` and `benchmarl` extras); without them
the tests that need them skip."""

from __future__ import annotations

import importlib.util
import math
import re
import sys
from pathlib import Path

import numpy as np
import pytest

import hivex_dsl
from hivex_dsl.compiler import registry
from hivex_dsl.adapters.torchrl import marl_view

from .crashes import first_agent_crashes_on

ENV_IDS = list(registry.environments())
EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
EPISODE = 20  # decisions per world episode in the training runs


def load(name: str):
    spec = importlib.util.spec_from_file_location(f"example_{name}", EXAMPLES / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # BenchMARL pickles the experiment's callbacks, a class of the example's
    spec.loader.exec_module(module)
    return module


def crashing(restepped, env_id: str, length: int = 6):
    # period 1: the crash is on the second physics step, so on the second step() call
    compiled = hivex_dsl.compile({"hivex": 1, "environment": env_id, "episode_length": length, "decision_period": 1})
    return restepped(compiled, first_agent_crashes_on(2))


def assert_trained(history: list[dict], frames: int, losses: tuple[str, ...]):
    """Every iteration collected ``frames`` env steps and its losses are finite; world episodes (at most EPISODE
    steps each) ended and were reset: new trajectories began, and agents' episodes ended with finite returns."""
    assert [h["frames"] for h in history] == [frames] * len(history)
    for h in history:
        assert all(math.isfinite(h[name]) for name in losses), h
        assert h["world_resets"] >= frames // EPISODE, h  # any EPISODE consecutive steps hold an ending
        assert h["trajectories"] >= frames // EPISODE, h  # each reset began a new trajectory
        assert h["episodes"] >= h["world_resets"] and math.isfinite(h["mean_return"]), h


@pytest.mark.parametrize("env_id", [e for e in ENV_IDS if e != "wind_farm_control"])
def test_the_views_accept_the_action_torchrl_sends_for_an_agent_that_ended(env_id, restepped):
    """TorchRL sends an action for every agent of a group; the flat and joint views used to refuse one for an agent
    that had left ('action for ..., which is not a live agent') where the parallel env ignores it."""
    env = marl_view(hivex_dsl.parallel_env(crashing(restepped, env_id)))
    env.reset(seed=0)
    first = env.possible_agents[0]
    for _ in range(4):
        env.step({agent: env.action_space(agent).sample() for agent in env.possible_agents})
    assert first not in env.agents and env.agents == env.possible_agents[1:]


@pytest.mark.ecosystem("torchrl")
@pytest.mark.parametrize("env_id", ENV_IDS)
def test_an_agent_that_ended_is_masked_out_and_its_world_goes_on_in_torchrl(env_id, restepped):
    pytest.importorskip("torchrl")
    from hivex_dsl.adapters.torchrl import torchrl_env

    env = torchrl_env(crashing(restepped, env_id), seed=0)
    data = env.rollout(12, break_when_any_done=False)  # two 6-step world episodes
    mask, done = data["agents", "mask"], data["next", "agents", "done"][..., 0]
    assert mask[:2].all() and not mask[2:6, 0].any() and mask[2:6, 1:].all()  # agent 0 ended on step 2
    assert done[1, 0] and not done[1, 1:].any() and done[2:6, 0].all()
    assert data["next", "done"][:, 0].tolist() == [False] * 5 + [True] + [False] * 5 + [True]  # at the clock only
    assert mask[6:].all() and not done[6:11].any()  # the world reset: agent 0 is back (and crashes no more)


@pytest.mark.ecosystem("torchrl")
@pytest.mark.parametrize("env_id", ENV_IDS)
def test_torchrl_mappo_trains_a_few_iterations(env_id):
    pytest.importorskip("torchrl")
    history = load("torchrl_mappo").main(["--env", env_id, "--episode-length", str(EPISODE), "--iterations", "2",
                                          "--frames-per-batch", "60", "--minibatch-size", "30", "--epochs", "1",
                                          "--hidden", "16"])
    assert len(history) == 2
    assert_trained(history, 60, ("loss", "mean_return"))


def test_torchrl_ippo_trains_too():
    pytest.importorskip("torchrl")
    history = load("torchrl_mappo").main(["--env", "ocean_plastic_collection", "--ippo", "--episode-length",
                                          str(EPISODE), "--iterations", "1", "--frames-per-batch", "40",
                                          "--minibatch-size", "20", "--epochs", "1", "--hidden", "16"])
    assert_trained(history, 40, ("loss",))


@pytest.mark.ecosystem("benchmarl")
@pytest.mark.parametrize("env_id", ENV_IDS)
def test_benchmarl_mappo_trains_a_few_iterations(env_id, tmp_path):
    pytest.importorskip("benchmarl")
    history = load("benchmarl_mappo").main(["--env", env_id, "--episode-length", str(EPISODE), "--iterations", "2",
                                            "--envs", "2", "--frames-per-batch", "80", "--minibatch-size", "40",
                                            "--epochs", "1", "--hidden", "16", "--folder", str(tmp_path)])
    assert len(history) == 2
    # two copies of 40 steps each: at least two world episodes ended in each
    assert_trained(history, 80, ("loss_objective", "loss_critic", "loss_entropy"))
    assert all(h["world_resets"] >= 4 for h in history)
    assert list(tmp_path.glob("mappo_*/mappo_*/scalars/collection_agents_reward_episode_reward_mean.csv"))


def test_benchmarl_ippo_trains_and_evaluates(tmp_path):
    pytest.importorskip("benchmarl")
    history = load("benchmarl_mappo").main(["--env", "drone_based_reforestation", "--task", "find_high_terrain",
                                            "--ippo", "--evaluate", "--episode-length", str(EPISODE),
                                            "--iterations", "1", "--envs", "2", "--frames-per-batch", "40",
                                            "--minibatch-size", "20", "--epochs", "1", "--hidden", "16",
                                            "--folder", str(tmp_path)])
    assert_trained(history, 40, ("loss_objective", "loss_critic", "loss_entropy"))
    evaluated = list(tmp_path.glob("ippo_find_high_terrain_*/*/scalars/eval_reward_episode_len_mean.csv"))
    assert evaluated and evaluated[0].read_text().strip().endswith(f",{EPISODE}.0")  # one whole episode


def test_benchmarl_has_a_task_for_every_environment_and_task():
    pytest.importorskip("benchmarl")
    from hivex_dsl.adapters.benchmarl import TASKS, task

    assert list(TASKS) == ENV_IDS
    for env_id, enum in TASKS.items():
        assert [member.name.lower() for member in enum] == list(registry.get(env_id).reward_table.task_names)
        assert enum.env_name() == f"hivex_{env_id}"
        for member in enum:
            assert member.get_task().config == {"scenario": None, "level": None, "max_cycles": None}
            assert member.get_task().compiled().task_name == member.name.lower()
    assert task("ocean_plastic_collection").name == "PLASTIC_COLLECTION"  # its main scenario's task
    with pytest.raises(KeyError, match="its tasks: plastic_collection"):
        task("ocean_plastic_collection", "plant_trees")
    with pytest.raises(TypeError):
        task("wind_farm_control", episodes=3)


@pytest.mark.ecosystem("benchmarl")
@pytest.mark.parametrize("env_id", ENV_IDS)
def test_a_benchmarl_task_builds_the_torchrl_env_with_the_actions_it_says(env_id):
    pytest.importorskip("benchmarl")
    from torchrl.data import Categorical

    from hivex_dsl.adapters.benchmarl import task

    hivex = task(env_id, level=None, max_cycles=7)
    env = hivex.get_env_fun(num_envs=1, continuous_actions=hivex.supports_continuous_actions(), seed=3,
                            device="cpu")()
    discrete = isinstance(env.full_action_spec["agents", "action"], Categorical)
    assert hivex.supports_discrete_actions() == discrete != hivex.supports_continuous_actions()
    assert hivex.max_steps(env) == 7
    assert hivex.group_map(env) == {"agents": hivex_dsl.parallel_env(f"{env_id}/main").possible_agents}
    # the global state for MAPPO's critic: the parallel env's state_space, one vector per world
    state_size = hivex_dsl.parallel_env(f"{env_id}/main").state_space.shape[0]
    assert hivex.has_state() and hivex.state_spec(env)["state"].shape == (state_size,)
    assert hivex.action_mask_spec(env) is None
    assert list(hivex.observation_spec(env)["agents"].keys()) == ["observation"]


def test_the_readme_s_torchrl_and_benchmarl_lines_run():
    pytest.importorskip("benchmarl")
    import hivex_dsl.adapters.benchmarl
    import hivex_dsl.adapters.torchrl

    readme = (Path(__file__).resolve().parent.parent / "README.md").read_text()
    rows = dict(re.findall(r"^\| (TorchRL|BenchMARL) \| `([^`]*)`", readme, flags=re.M))
    namespace = {"hivex_dsl": hivex_dsl}
    exec(rows["TorchRL"], namespace)
    assert namespace["env"].group_map == {"agents": ["vessel_0", "vessel_1", "vessel_2"]}
    exec(rows["BenchMARL"], namespace)
    assert namespace["task"].max_steps(namespace["env"]) == 500


@pytest.mark.ecosystem("torchrl")
@pytest.mark.parametrize("flat", [False, True], ids=["raw", "flat"])
@pytest.mark.parametrize("env_id", ENV_IDS)
def test_torchrl_s_gym_wrapper_rolls_out_over_the_same_step_vector_env(env_id, flat):
    # issue 54 item 15: nested step infos and a hybrid Dict action space broke GymWrapper on every environment
    pytest.importorskip("torchrl")
    from torchrl.envs import GymWrapper

    from hivex_dsl.adapters.flat import flat_vector_env

    period = hivex_dsl.compile({"hivex": 1, "environment": env_id}).decision_period  # 4 decisions an episode
    compiled = hivex_dsl.compile({"hivex": 1, "environment": env_id, "episode_length": 4 * period})
    venv = hivex_dsl.vector_env(compiled, num_worlds=2, autoreset_mode="same_step")
    env = GymWrapper(flat_vector_env(venv) if flat else venv)
    env.set_seed(0)
    steps = 10
    rollout = env.rollout(steps, break_when_any_done=False)
    assert tuple(rollout.batch_size) == (venv.num_envs, steps)
    nxt = rollout["next"]
    # every slot's world ran out of its 4 decisions twice in 10 (more endings where an agent's own episode ended)
    assert (nxt["done"].squeeze(-1).sum(dim=1) >= 2).all()
    # the per-step reward terms are read from the infos: the reward is their weighted sum
    weighted = sum(compiled.weights[name] * nxt[f"reward_terms/{name}"].double()
                   for name in compiled.weights if f"reward_terms/{name}" in nxt.keys())
    np.testing.assert_allclose(nxt["reward"].squeeze(-1).double().numpy(), weighted.numpy(), rtol=1e-5, atol=1e-5)
