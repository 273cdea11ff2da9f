"""Every environment trains a few hundred agent-steps, leaves a checkpoint that evaluates, and a seed decides it all."""

from __future__ import annotations

import json
import os
import signal

import numpy as np
import pytest
import torch

from hivex_dsl.cli import main
from hivex_dsl.compiler import compile
from hivex_dsl.evaluation.original import compare
from hivex_dsl.train.checkpoint import load_checkpoint, seal
from hivex_dsl.train.config import make_config
from hivex_dsl.train.evaluate import _original_episode_length, evaluate, format_report
from hivex_dsl.train.ppo import train

from .conftest import ENVIRONMENTS, short_scenario

CAMERA_ENCODER = {"drone_based_reforestation": "resnet", "ocean_plastic_collection": "resnet",
                  "aerial_wildfire_suppression": "simple"}


@pytest.mark.parametrize("environment", ENVIRONMENTS)
def test_each_environment_trains_and_evaluates(environment, tiny, tmp_path):
    compiled = compile(short_scenario(environment))
    summary = train(compiled, make_config(environment, tiny), tmp_path, progress=False)
    assert summary["agent_steps"] >= tiny["max_steps"]
    assert (tmp_path / "checkpoint.pt").is_file() and len(list((tmp_path / "checkpoints").glob("*.pt"))) == 1
    assert list((tmp_path / "tb").glob("events.out.tfevents.*"))
    loaded = load_checkpoint(tmp_path / "checkpoint.pt")
    assert loaded["fingerprint"] == compiled.fingerprint
    assert loaded["config"].vis_encode_type == make_config(environment).vis_encode_type
    report = evaluate(tmp_path / "checkpoint.pt", episodes=2)
    assert report["agent_episodes"] == 2 * compiled.agents
    assert report["seed"] == compiled.seeds.test
    assert set(report["reward_terms"]) <= set(compiled.weights)
    assert report["return"]["std"] >= 0


def test_the_camera_encoders_follow_the_paper():
    for environment, kind in CAMERA_ENCODER.items():
        assert make_config(environment).vis_encode_type == kind


def test_a_seed_decides_the_run(tiny, tmp_path):
    compiled = compile(short_scenario("aerial_wildfire_suppression"))  # hybrid actions and a camera

    def weights(seed, name):
        train(compiled, make_config(compiled.environment, tiny, {"seed": seed}), tmp_path / name, progress=False)
        state = torch.load(tmp_path / name / "checkpoint.pt", weights_only=True)["model"]
        return torch.cat([v.flatten().float() for v in state.values()])

    first, again, other = weights(1, "a"), weights(1, "b"), weights(2, "c")
    assert torch.equal(first, again)
    assert not torch.equal(first, other)


def test_world_seed_trains_on_the_worlds_of_that_seed_and_tests_on_the_scenario_s(tiny, tmp_path):
    from hivex_dsl.train.ppo import make_env

    scenario = short_scenario("wildfire_resource_management")  # its fire and weather are drawn per world
    compiled = compile(scenario)
    own, other = compiled.seeds.train, compiled.seeds.train + 1
    # world_seed X plays the worlds a scenario whose seeds.train is X plays
    _, moved, _ = make_env(compiled, 2, "train", seed=other)
    _, written, _ = make_env(compile(scenario | {"seeds": {"train": other, "test": compiled.seeds.test}}), 2, "train")
    _, default, _ = make_env(compiled, 2, "train")
    assert np.array_equal(moved, written)
    assert not np.array_equal(moved, default)

    def weights(name, world_seed):
        cfg = make_config(compiled.environment, tiny, {"seed": 1, "world_seed": world_seed})
        train(compiled, cfg, tmp_path / name, progress=False)
        state = torch.load(tmp_path / name / "checkpoint.pt", weights_only=True)["model"]
        return torch.cat([v.flatten().float() for v in state.values()])

    unset, named, elsewhere = weights("a", "scenario"), weights("b", own), weights("c", other)
    assert torch.equal(unset, named)  # unset, the scenario's own training seed
    assert not torch.equal(unset, elsewhere)  # the same weights' seed, other worlds: another run
    config = json.loads((tmp_path / "c" / "config.json").read_text())["hyperparameters"]
    assert config["world_seed"] == other and config["seed"] == 1
    assert evaluate(tmp_path / "c" / "checkpoint.pt", episodes=1)["seed"] == compiled.seeds.test


def test_the_commands_train_and_evaluate(tmp_path, capsys):
    scenario = tmp_path / "wfc.yaml"
    scenario.write_text(json.dumps(short_scenario("wind_farm_control", episode_length=16)))
    run = tmp_path / "run"
    args = ["train", str(scenario), "-o", str(run), "--steps", "256", "--seed", "3", "--no-progress",
            "--set", "num_worlds=1", "--set", "buffer_fill=rollout", "--set", "hidden_units=8",
            "--set", "buffer_size=64", "--set", "batch_size=64", "--json"]
    assert main(args) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["agent_steps"] == 256 and summary["seed"] == 3
    assert main(["evaluate", str(run / "checkpoint.pt"), "--episodes", "1", "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    # a 16-step episode (turning fast, see short_scenario) is not the paper's setting, so its cell (WFC pattern 0,
    # task 0: 4611.6) is not set beside it
    assert report["published"] is None and report["original_episode_length"] is None
    assert report["episode_length"] == {"mean": 15.0, "std": 0.0}  # 16 decisions, logged less one as ML-Agents does
    assert report["caveat"] == ("the paper's result for this task and level (return 4612) is not this scenario's: it "
                                "differs from the paper's setting in episode_length, params")
    assert main(["evaluate", str(run / "checkpoint.pt"), "--episodes", "1"]) == 0
    assert f"(no published result: {report['caveat']})" in capsys.readouterr().out


def test_the_report_sets_episode_length_beside_the_original_s_test_average():
    """Only a scenario that is the paper's cell borrows the original's test Episode Length (its plot pages' average
    sheet; the paper published none), and the table shows it without a spread, with a line saying what it is."""
    paper = compile("scenarios/ocean_plastic_collection/main.yaml")
    average = compare.original_test_average("ocean_plastic_collection", 0, None, "Environment/Episode Length")
    assert _original_episode_length(paper) == average and 133 < average < 184  # the test points' lengths
    assert _original_episode_length(compile(short_scenario("ocean_plastic_collection"))) is None
    report = {"scenario": "opc-main", "split": "test", "seed": 6000, "episodes": 1, "agent_episodes": 3,
              "actions": "sampled", "trained_agent_steps": 10, "return": {"mean": 5.0, "std": 1.0},
              "episode_length": {"mean": 40.0, "std": 2.0}, "original_episode_length": average, "statistics": {},
              "weighted_reward_terms": {}, "weights": {}, "published": None, "caveat": None}
    lines = format_report(report).splitlines()
    assert lines[3].split() == ["Episode", "Length", "40.000", "2.000", f"{average:.3f}", "-"]
    assert "the original's test average from its plot pages, which the paper did not publish" in lines[4]


def test_bad_training_input_is_a_clear_error(tmp_path, capsys):
    assert main(["train", "scenarios/wind_farm_control/main.yaml", "--set", "gama=0.9"]) == 2
    assert "gama" in capsys.readouterr().err
    (tmp_path / "x.pt").write_bytes(b"not a checkpoint")
    assert main(["evaluate", str(tmp_path / "x.pt")]) == 2
    err = capsys.readouterr().err
    assert "not a hivex checkpoint" in err and "weights_only=False" not in err  # never advise running its code
    torch.save({"format": "hivex-ppo/9"}, tmp_path / "later.pt")
    assert main(["evaluate", str(tmp_path / "later.pt")]) == 2
    assert "it says format 'hivex-ppo/9'" in capsys.readouterr().err
    small = {"max_steps": 64, "num_worlds": 1, "buffer_fill": "rollout", "buffer_size": 64, "batch_size": 64}
    train(compile(short_scenario("wind_farm_control")), make_config("wind_farm_control", small), tmp_path / "w",
          progress=False)
    assert main(["evaluate", str(tmp_path / "w")]) == 2
    assert f"give the checkpoint file in it ({tmp_path / 'w' / 'checkpoint.pt'})" in capsys.readouterr().err
    assert main(["evaluate", str(tmp_path / "w" / "checkpoint.pt"),
                 "scenarios/aerial_wildfire_suppression/main.yaml"]) == 2
    assert capsys.readouterr().err == (
        "hivex: the checkpoint trained on wind_farm_control (scenario 'wfc-main') and cannot play "
        "aerial_wildfire_suppression (scenario 'aws-main'): a policy plays the environment it trained on\n")
    edited = torch.load(tmp_path / "w" / "checkpoint.pt", weights_only=True)
    edited["config"]["hidden_units"] = 16  # it trained with the paper's 64
    torch.save(edited | {"checksums": seal(edited)}, tmp_path / "edited.pt")  # resealed, as a tool that edits would
    assert main(["evaluate", str(tmp_path / "edited.pt")]) == 2
    assert "weights do not fit the network its own hyperparameters build: Error(s)" in capsys.readouterr().err


def test_a_device_this_machine_lacks_is_a_clear_error(monkeypatch, tmp_path, capsys):
    monkeypatch.setattr(torch.cuda, "is_available", lambda: False)
    base = ["train", "scenarios/wind_farm_control/main.yaml", "-o", str(tmp_path / "run"), "--no-progress"]
    assert main(base + ["--device", "cuda"]) == 2
    assert "no CUDA GPU" in capsys.readouterr().err
    assert main(base + ["--device", "abacus"]) == 2
    assert capsys.readouterr().err == ("hivex: bad hyperparameters\n--device: device: 'abacus' is not allowed: "
                                       "expected cpu, cuda or cuda:N (one GPU of several)\n")
    assert main(base + ["--set", "device=mps"]) == 2  # torch knows mps, but this loop is not written for it
    assert "--set: device: 'mps' is not allowed: expected cpu, cuda or cuda:N" in capsys.readouterr().err


@pytest.mark.skipif(not torch.cuda.is_available(), reason="needs a CUDA GPU (run it where one is lent)")
def test_training_on_cuda_updates_the_policy_and_evaluates_on_the_cpu(tiny, tmp_path):
    """The camera, curiosity and hybrid-action paths on the GPU: the weights change between the first and the
    last checkpoint (updates reached the GPU's parameters), and the checkpoint evaluates on the CPU."""
    for environment in ("aerial_wildfire_suppression", "ocean_plastic_collection"):
        compiled = compile(short_scenario(environment))
        cfg = make_config(environment, tiny, {"device": "cuda", "checkpoint_every": 64, "keep_checkpoints": 5})
        summary = train(compiled, cfg, tmp_path / environment, progress=False)
        assert summary["agent_steps"] >= tiny["max_steps"]
        first, *_, last = sorted((tmp_path / environment / "checkpoints").glob("step_*.pt"))
        before, after = (load_checkpoint(path)["model"] for path in (first, last))
        assert any(not torch.equal(before[k], after[k]) for k in before)
        report = evaluate(tmp_path / environment / "checkpoint.pt", episodes=1)
        assert report["agent_episodes"] == compiled.agents


def test_torch_without_the_rest_of_the_train_extra_is_named(monkeypatch, capsys):
    import importlib.util

    real = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec", lambda name, *a: None if name == "tensorboard" else real(name, *a))
    assert main(["train", "scenarios/wind_farm_control/main.yaml"]) == 2
    assert capsys.readouterr().err == "hivex: training needs tensorboard beside torch: pip install 'hivex-dsl[train]'\n"


def test_a_run_too_short_for_an_episode_says_so(tmp_path, capsys):
    scenario = tmp_path / "wfc.yaml"
    scenario.write_text(json.dumps(short_scenario("wind_farm_control", episode_length=100)))
    assert main(["train", str(scenario), "-o", str(tmp_path / "run"), "--no-progress", "--steps", "64",
                 "--set", "num_worlds=1", "--set", "buffer_fill=rollout", "--set", "hidden_units=8",
                 "--set", "buffer_size=64", "--set", "batch_size=64", "--json"]) == 0
    out, err = capsys.readouterr()
    assert json.loads(out)["final_return"] is None
    # 64 agent-steps of 8 turbines in 1 world: 8 of the episode's 100 steps
    assert err == ("hivex: no episode ended within 64 agent-steps, so the run has no return yet: an episode of "
                   "wfc-main lasts 100 steps of each of its 8 slots (800 agent-steps); train longer with --steps\n")


def test_without_torch_the_commands_say_what_to_install(monkeypatch, capsys):
    import sys

    monkeypatch.setitem(sys.modules, "torch", None)  # import torch now raises ImportError
    assert main(["train", "scenarios/wind_farm_control/main.yaml"]) == 2
    assert "pip install" in capsys.readouterr().err


@pytest.mark.parametrize("signum", [signal.SIGINT, signal.SIGTERM])
def test_an_interrupted_run_finishes_its_update_and_keeps_everything(signum, tiny, tmp_path):
    """Ctrl-C (or a scheduler's SIGTERM) during the first update: the run stops after it, saves its checkpoint,
    curve and summary, says it stopped early, and gives the signal handlers back."""
    before = signal.getsignal(signal.SIGINT), signal.getsignal(signal.SIGTERM)
    summary = train(compile(short_scenario("wind_farm_control")), make_config("wind_farm_control", tiny),
                    tmp_path / "run", progress=False, on_update=lambda _: os.kill(os.getpid(), signum))
    assert summary["stopped_early"] is True
    assert summary["agent_steps"] == tiny["buffer_size"]  # one rollout of the 192 asked for
    assert (tmp_path / "run" / "checkpoint.pt").is_file() and (tmp_path / "run" / "curve.json").is_file()
    assert (signal.getsignal(signal.SIGINT), signal.getsignal(signal.SIGTERM)) == before


def test_steps_is_a_budget_the_last_rollout_stops_at_and_the_bar_moves_every_step(tiny, tmp_path, monkeypatch):
    # issue 54 item 17: the last update collected a whole buffer past --steps (20,448 for 10,240), and the bar moved
    # once an update. WFC's 8 turbines in 1 world are 8 slots; a buffer of 64 is 8 steps of each per update.
    from hivex_dsl.train import ppo
    from hivex_dsl.train.logs import Progress

    moves = []

    class Recorded(Progress):
        def __init__(self, total, *args, **kwargs):
            moves.append(("total", total))
            super().__init__(total, *args, **kwargs)

        def advance(self, steps, episode_return):
            moves.append(steps)
            super().advance(steps, episode_return)

    monkeypatch.setattr(ppo, "Progress", Recorded)
    summary = train(compile(short_scenario("wind_farm_control")), make_config("wind_farm_control", tiny | {
        "max_steps": 100}), tmp_path, progress=False)
    # 64 in the first update; 36 left are 5 steps of the 8 slots (40): 104, less than one step of every slot over
    assert summary["agent_steps"] == 104 and ppo.planned_agent_steps(100, 0, 8) == 104
    assert moves[0] == ("total", 104)
    assert [m for m in moves[1:] if m] == [8] * 13  # every step of every slot moves the bar


def test_progress_off_a_terminal_prints_a_line_every_so_often(capsys):
    from hivex_dsl.train.logs import Progress

    now = [0.0]
    progress = Progress(1000, enabled=True, label="wfc", every=30.0, clock=lambda: now[0])
    progress.advance(100, None)
    now[0] = 29.0
    progress.advance(100, None)
    assert capsys.readouterr().err == ""  # stderr here is no terminal: no bar, and no line before 30 s
    now[0] = 40.0
    progress.advance(200, 12.5)
    line = capsys.readouterr().err
    assert line == "wfc: 400 / 1,000 agent-steps (40%), 10 agent-steps/s, mean episode return 12.50\n"
    progress.close()
    assert capsys.readouterr().err.startswith("wfc: 400 / 1,000")
    silent = Progress(1000, enabled=False, label="wfc", every=0.0)
    silent.advance(500, 1.0)
    silent.close()
    assert capsys.readouterr().err == ""


def test_train_ends_with_a_summary_and_the_next_command_and_evaluate_shows_weighted_terms(tmp_path, capsys):
    # issue 54 item 18: train dumped summary.json raw; evaluate printed unweighted term rows unlabelled
    scenario = tmp_path / "wfc.yaml"
    scenario.write_text(json.dumps(short_scenario("wind_farm_control", episode_length=8)
                                   | {"weights": {"generate_energy": 0.5}}))
    run = tmp_path / "run"
    assert main(["train", str(scenario), "-o", str(run), "--no-progress", "--steps", "64", "--set", "num_worlds=1",
                 "--set", "hidden_units=8", "--set", "buffer_fill=rollout", "--set", "buffer_size=64", "--set",
                 "batch_size=64"]) == 0
    out = capsys.readouterr().out
    assert not out.lstrip().startswith("{") and "trained 64 agent-steps" in out
    assert f"next: hivex evaluate {run / 'checkpoint.pt'}" in out
    assert main(["evaluate", str(run / "checkpoint.pt"), "--episodes", "1", "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert main(["evaluate", str(run / "checkpoint.pt"), "--episodes", "1"]) == 0
    table = capsys.readouterr().out
    unweighted = report["reward_terms"]["generate_energy"]["mean"]
    row = next(line for line in table.splitlines() if "generate_energy" in line)
    assert row.startswith("term generate_energy x0.5 (weighted)")
    assert float(row.split()[4]) == pytest.approx(0.5 * unweighted, abs=1e-3)
    assert report["weighted_reward_terms"]["generate_energy"]["mean"] == pytest.approx(report["return"]["mean"])
