"""`hivex replay`: the recorded terms add up to what the environment paid, the trace is the documented data, every
environment's main scenario replays with the scripted policy and a checkpoint, a sweep point replays, a comparison
plays both on one seed, and bad input is one clear sentence."""

from __future__ import annotations

import json
import re

import numpy as np
import pytest

from hivex_dsl.cli import main
from hivex_dsl.compiler import compile
from hivex_dsl.evaluation.policies import make_policy
from hivex_dsl.replay.page import default_frame_step
from hivex_dsl.replay.record import record
from hivex_dsl.replay.trace import FIELDS, episode_data, significant
from hivex_dsl.runtime.batched import BatchedEnv
from hivex_dsl.sim.spaces import check_actions

from ..untrained import untrained_checkpoint
from .conftest import ENVIRONMENTS, SCENARIOS, short_scenario


def env_rewards(compiled, decisions: int, seed=None) -> np.ndarray:
    """(decisions, agents) rewards the environment itself returns to the scripted policy on the test split."""
    core = BatchedEnv(compiled, batch=1, split="test")
    policy = make_policy("scripted", compiled, core.sim.action_space, core.shape, seed=0 if seed is None else seed)
    observations, rewards = core.reset(seed), []
    for _ in range(decisions):
        actions = check_actions(core.sim.action_space, policy(observations), compiled.agent_names)
        result = core.step(actions)
        observations = result.observations
        rewards.append(result.rewards[0].copy())
    return np.array(rewards)


@pytest.mark.parametrize("environment", ENVIRONMENTS)
def test_the_weighted_terms_of_every_decision_add_up_to_what_the_environment_paid(environment):
    compiled = compile(f"{environment}/main")
    episode = record(compiled, "scripted", {"kind": "scripted"}, frame_step=50, steps=40)
    paid = env_rewards(compiled, episode.decisions)
    np.testing.assert_allclose(sum(episode.weighted.values()), paid, rtol=1e-12, atol=1e-12)
    np.testing.assert_array_equal(episode.reward, paid)
    for name, values in episode.terms.items():  # weighted = weight x raw where the weight does not move
        np.testing.assert_allclose(episode.weighted[name], compiled.weights[name] * values, rtol=1e-12, atol=1e-15)
    data = episode_data(episode)  # the trace's rounded values add up too, to its precision
    summed = sum(np.array(data["weighted"][name]) for name in data["terms"])
    np.testing.assert_allclose(summed, paid, rtol=1e-5, atol=1e-5 * max(1.0, np.abs(paid).max()))


def test_significant_rounds_to_six_digits_and_keeps_zeros_and_signs():
    assert significant(np.array([123456789.0, -0.000123456789, 0.0, 1.0])) == [123457000.0, -0.000123457, 0.0, 1.0]
    assert significant(np.array([[True, False]])) == [[True, False]]


def test_the_trace_holds_every_documented_field_per_agent_and_decision(tmp_path, capsys):
    # 30 decisions of OPC's default period 5
    scenario = short_scenario(tmp_path, "ocean_plastic_collection", episode_length=150)
    page, trace = tmp_path / "opc.html", tmp_path / "opc.json"
    assert main(["replay", str(scenario), "-o", str(page), "--trace", str(trace), "--frame-step", "7"]) == 0
    data = json.loads(trace.read_text())
    assert data["format"] == "hivex-replay-trace/1"
    (episode,) = data["episodes"]
    assert set(episode) == set(FIELDS)  # docs/replay.md's table is FIELDS
    compiled = compile(str(scenario))
    shape = [compiled.episode_decisions, compiled.agents]
    assert episode["decisions"] == 30 and episode["agents"] == list(compiled.agent_names)
    for name in episode["terms"]:
        assert list(np.shape(episode["raw"][name])) == shape == list(np.shape(episode["weighted"][name]))
        assert len(episode["weights"][name]) == 30
    assert list(np.shape(episode["actions"])) == shape + [2]  # throttle and steer
    assert list(np.shape(episode["observations"])) == shape + [len(episode["observation_labels"])]
    assert episode["observation_labels"][0] == "local position x"
    assert episode["observation_labels"][-1].endswith("(previous)")  # two stacks, newest first
    assert set(episode["statistics_so_far"]) == set(episode["statistics"])
    assert episode["frame_decisions"] == [0, 7, 14, 21, 28, 30]
    assert any(ev["kind"] == "truncated" and ev["decision"] == 30 for ev in episode["events"])
    assert f"wrote {page}" in capsys.readouterr().out


@pytest.mark.parametrize("environment", ENVIRONMENTS)
def test_every_environment_main_scenario_replays_as_one_page_that_needs_no_network(environment, tmp_path):
    page = tmp_path / "episode.html"
    assert main(["replay", f"{environment}/main", "-o", str(page), "--steps", "12", "--frame-step", "6"]) == 0
    text = page.read_text()
    assert "uPlot" in text and 'id="replay-data"' in text
    assert not re.search(r"""(src|href)=["']?(https?:)?//""", text)  # nothing is fetched
    frames = json.loads(re.search(r'id="replay-frames" type="application/json">(.*?)</script>', text).group(1))
    assert len(frames[0]) == 3 and all(f.startswith(("data:image/png;base64,", "data:image/webp;base64,"))
                                       for f in frames[0])


def test_a_default_main_task_episode_fits_the_five_megabyte_bound(tmp_path, capsys):
    """Wind Farm Control's main task, the longest episode of the five (5000 decisions of 8 turbines), played whole
    at the defaults: about 100 frames (one every 50 decisions) and every decision's data."""
    page = tmp_path / "wfc.html"
    assert main(["replay", "wind_farm_control/main", "-o", str(page)]) == 0
    assert page.stat().st_size < 5_000_000
    assert "5000 decisions, 101 frames, one every 50 decisions" in capsys.readouterr().out


def test_the_default_frame_step_is_renders_until_an_episode_would_show_more_than_a_hundred_frames():
    assert default_frame_step(500) == 10 and default_frame_step(1000) == 10
    assert default_frame_step(5000) == 50 and default_frame_step(2000) == 20


def test_a_page_over_its_bound_is_refused_early_with_a_frame_step_that_fits(tmp_path, capsys):
    page = tmp_path / "big.html"
    assert main(["replay", "wind_farm_control/main", "-o", str(page), "--frame-step", "1", "--max-mb", "0.2"]) == 2
    err = capsys.readouterr().err
    assert "over its bound of 0.2 MB: give a larger --frame-step (at least" in err
    assert "Traceback" not in err and not page.exists()
    step = int(re.search(r"at least (\d+)", err).group(1))
    assert main(["replay", "wind_farm_control/main", "-o", str(page), "--frame-step", str(step), "--max-mb", "0.2",
                 "--steps", "200"]) == 0
    assert page.stat().st_size <= 200_000


def test_a_sweep_point_replays(tmp_path):
    trace = tmp_path / "point.json"
    assert main(["replay", str(SCENARIOS / "wind_farm_control" / "scaling.yaml"), "--point", "agents=2", "-o",
                 str(tmp_path / "point.html"), "--trace", str(trace), "--steps", "10"]) == 0
    (episode,) = json.loads(trace.read_text())["episodes"]
    assert episode["agents"] == ["turbine_0", "turbine_1"] and episode["scenario"]["sweep_point"] == {"agents": 2}


def test_compare_plays_two_reward_tables_on_one_seed(tmp_path):
    first = short_scenario(tmp_path, "wind_farm_control", episode_length=20)
    other = tmp_path / "heavier.json"
    data = json.loads(first.read_text())
    other.write_text(json.dumps(data | {"name": "wfc-heavier", "weights": {"generate_energy": 3.0}}))
    trace = tmp_path / "both.json"
    assert main(["replay", str(first), "--compare", str(other), "-o", str(tmp_path / "both.html"),
                 "--trace", str(trace), "--seed", "7"]) == 0
    a, b = json.loads(trace.read_text())["episodes"]
    assert a["seed"] == b["seed"] == 7 and a["actions"] == b["actions"]  # one policy, one seed: the same play
    np.testing.assert_allclose(np.array(b["weighted"]["generate_energy"]),
                               3.0 * np.array(a["weighted"]["generate_energy"]), rtol=1e-5)


def test_a_run_directory_replays_its_checkpoint_on_the_scenario_it_trained_on(trained, tmp_path):
    scenario, run = trained
    trace = tmp_path / "run.json"
    assert main(["replay", str(run), "-o", str(tmp_path / "run.html"), "--trace", str(trace)]) == 0
    (episode,) = json.loads(trace.read_text())["episodes"]
    policy = episode["policy"]
    assert policy["kind"] == "checkpoint" and policy["checkpoint"] == str(run / "checkpoint.pt")
    assert policy["agent_steps"] >= 64 and policy["weights_sha256"]
    assert policy["trained_fingerprint"] == episode["scenario"]["fingerprint"] == compile(str(scenario)).fingerprint
    assert episode["decisions"] == 16
    # the scenario file with --checkpoint plays the same episode
    again = tmp_path / "again.json"
    assert main(["replay", str(scenario), "--checkpoint", str(run / "checkpoint.pt"), "-o", str(tmp_path / "a.html"),
                 "--trace", str(again)]) == 0
    assert json.loads(again.read_text())["episodes"][0]["actions"] == episode["actions"]


def test_a_checkpoint_of_another_scenario_is_refused_by_fingerprint(trained, tmp_path, capsys):
    _, run = trained
    longer = short_scenario(tmp_path, "wind_farm_control", episode_length=17)
    assert main(["replay", str(longer), "--checkpoint", str(run / "checkpoint.pt"), "-o",
                 str(tmp_path / "x.html")]) == 2
    err = capsys.readouterr().err
    assert "trained on the scenario" in err and "fingerprint" in err and "Traceback" not in err
    # --compare may put it beside another reward table of its environment
    assert main(["replay", str(run), "--compare", str(longer), "-o", str(tmp_path / "y.html")]) == 0


@pytest.mark.parametrize("what, message", [
    ("text", "the top level must be a mapping"),
    ("empty dir", "without a checkpoint.pt"),
    ("sweep", "sweeps over 6 points"),
    ("bad suffix", "expected a file name ending in .html"),
    ("sweep run", "is the run directory of a sweep: replay one point's run"),
    ("not a checkpoint", "is not a hivex checkpoint"),
])
def test_bad_input_is_one_sentence_and_exit_2(what, message, tmp_path, capsys):
    output = str(tmp_path / "out.html")
    if what == "text":
        (tmp_path / "notes.txt").write_text("just some words\n")
        argv = ["replay", str(tmp_path / "notes.txt"), "-o", output]
    elif what == "empty dir":
        (tmp_path / "run").mkdir()
        argv = ["replay", str(tmp_path / "run"), "-o", output]
    elif what == "sweep":
        argv = ["replay", str(SCENARIOS / "wind_farm_control" / "scaling.yaml"), "-o", output]
    elif what == "sweep run":  # `hivex train SWEEP` keeps each point's run in a folder of its index
        (tmp_path / "grid" / "0003").mkdir(parents=True)
        (tmp_path / "grid" / "0003" / "checkpoint.pt").write_bytes(b"")
        argv = ["replay", str(tmp_path / "grid"), "-o", output]
    elif what == "not a checkpoint":
        pytest.importorskip("torch")
        (tmp_path / "model.pt").write_text("not a checkpoint")
        argv = ["replay", str(tmp_path / "model.pt"), "-o", output]
    else:
        argv = ["replay", "wind_farm_control/main", "-o", str(tmp_path / "out.gif")]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert message in err and "Traceback" not in err
    assert not (tmp_path / "out.html").exists()


@pytest.mark.parametrize("environment", ENVIRONMENTS)
def test_every_environment_main_scenario_replays_with_a_checkpoint(environment, tmp_path):
    """A checkpoint of the environment's main scenario (shortened), as `hivex train` writes one, from an untrained
    network of the paper's hyperparameters: what the replay reads of it is the same as after training."""
    scenario = short_scenario(tmp_path, environment, episode_length=10)
    compiled = compile(str(scenario))
    checkpoint = untrained_checkpoint(tmp_path / "run" / "checkpoint.pt", compiled, agent_steps=123)
    trace = tmp_path / "trace.json"
    assert main(["replay", str(checkpoint), "-o", str(tmp_path / "cp.html"), "--trace", str(trace)]) == 0
    (episode,) = json.loads(trace.read_text())["episodes"]
    assert episode["policy"]["agent_steps"] == 123 and episode["decisions"] >= 1
    assert episode["policy"]["trained_fingerprint"] == compiled.fingerprint


def test_a_moving_weight_over_decisions_of_several_physics_steps_still_adds_up(tmp_path):
    """A schedule moves Generate Energy's weight at every physics step, and a decision holds two of them: the
    recorded weighted values are summed per physics step with that step's weight, as the composer pays them."""
    scenario = short_scenario(tmp_path, "wind_farm_control", episode_length=40, decision_period=2,
                              weights={"generate_energy": {"from": 1.0, "to": 3.0, "over_steps": 30}})
    compiled = compile(str(scenario))
    episode = record(compiled, "scripted", {"kind": "scripted"}, frame_step=10)
    paid = env_rewards(compiled, episode.decisions)
    assert episode.decisions == 20
    np.testing.assert_allclose(sum(episode.weighted.values()), paid, rtol=1e-12, atol=1e-12)
    weights = episode.weights["generate_energy"]
    # decision k's last physics step pays at the weight of the 2k - 1 steps before it: 3 from k = 16 (31 >= 30)
    np.testing.assert_allclose(weights, [min(3.0, 1.0 + 2.0 * (2 * k - 1) / 30) for k in range(1, 21)], rtol=1e-12)
    moves = [(ev["decision"], ev["name"]) for ev in episode.events if ev["kind"] == "schedule"]
    assert moves == [(1, "generate_energy weight leaves 1"), (16, "generate_energy weight reaches 3")]
