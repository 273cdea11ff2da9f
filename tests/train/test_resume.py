"""`hivex train --resume`: a stopped run goes on from its checkpoint with its optimizers and curve."""

from __future__ import annotations

import json
import os
import signal
import time

import pytest
import torch

from hivex_dsl.cli import main
from hivex_dsl.compiler import compile
from hivex_dsl.train.config import TrainError, make_config
from hivex_dsl.train.grid import run_grid
from hivex_dsl.train.ppo import train

from .conftest import TINY, short_scenario

# WRM's 9 agents in one world: 90 agent-steps per update in one minibatch, so 2 epochs -> 2 optimizer steps
ONE_MINIBATCH = {"buffer_size": 90, "batch_size": 90, "num_epoch": 2, "max_steps": 270}
STEPS_PER_UPDATE, UPDATES = 2, 3


def adam_steps(run_dir, module: str = "optimizer") -> int:
    state = torch.load(run_dir / "checkpoint.pt", weights_only=True)["training"][module]["state"]
    return {int(s["step"]) for s in state.values()}.pop()


def stop_after_first_update(*_):
    os.kill(os.getpid(), signal.SIGINT)


@pytest.fixture
def wrm():
    """Wildfire resource management: curiosity ships in its paper hyperparameters."""
    return compile(short_scenario("wildfire_resource_management", episode_length=8))


@pytest.fixture
def tiny(tiny):
    return tiny | ONE_MINIBATCH


def test_a_resumed_run_goes_on_with_its_optimizers_and_curve(wrm, tiny, tmp_path):
    cfg = make_config(wrm.environment, tiny)
    assert cfg.curiosity_strength > 0
    run = tmp_path / "run"
    first = train(wrm, cfg, run, progress=False, on_update=stop_after_first_update)
    assert first["stopped_early"] and first["agent_steps"] == tiny["buffer_size"]
    assert adam_steps(run) == STEPS_PER_UPDATE
    curve_before = json.loads((run / "curve.json").read_text())

    second = train(wrm, cfg, run, progress=False, resume=True)
    assert second["agent_steps"] == tiny["max_steps"] and not second["stopped_early"]
    assert first["resumed_at"] == [] and second["resumed_at"] == [first["agent_steps"]]
    assert second["wall_s"] >= first["wall_s"]
    # without the saved optimizer state Adam would count only the resumed run's steps
    assert adam_steps(run) == STEPS_PER_UPDATE * UPDATES
    assert adam_steps(run, "curiosity_optimizer") == STEPS_PER_UPDATE * UPDATES
    curve = json.loads((run / "curve.json").read_text())
    assert curve[:len(curve_before)] == curve_before and len(curve) > len(curve_before)
    assert [p["agent_steps"] for p in curve] == sorted(p["agent_steps"] for p in curve)
    assert not list(run.rglob("*.partial"))


def test_a_resumed_run_may_train_longer_but_not_differently(wrm, tiny, tmp_path):
    run = tmp_path / "run"
    train(wrm, make_config(wrm.environment, tiny), run, progress=False)
    longer = train(wrm, make_config(wrm.environment, tiny, {"max_steps": 360}), run, progress=False, resume=True)
    assert longer["agent_steps"] == 360 and longer["resumed_at"] == [270]
    assert adam_steps(run) == STEPS_PER_UPDATE * 4

    with pytest.raises(TrainError, match=r"gamma: 0\.99 -> 0\.5"):
        train(wrm, make_config(wrm.environment, tiny, {"gamma": 0.5}), run, progress=False, resume=True)
    other = compile(short_scenario("wildfire_resource_management", episode_length=9))
    with pytest.raises(TrainError, match="fingerprint"):
        train(other, make_config(wrm.environment, tiny), run, progress=False, resume=True)
    with pytest.raises(TrainError, match="no checkpoint"):
        train(wrm, make_config(wrm.environment, tiny), tmp_path / "empty", progress=False, resume=True)
    step_file = next((run / "checkpoints").glob("step_*.pt"))
    (tmp_path / "weights").mkdir()
    step_file.replace(tmp_path / "weights" / "checkpoint.pt")
    with pytest.raises(TrainError, match="weights only"):
        train(wrm, make_config(wrm.environment, tiny), tmp_path / "weights", progress=False, resume=True)


def test_the_train_command_resumes(tmp_path, capsys):
    scenario = tmp_path / "wfc.yaml"
    scenario.write_text(json.dumps(short_scenario("wind_farm_control", episode_length=16)))
    common = [str(scenario), "-o", str(tmp_path / "run"), "--no-progress", "--set", "num_worlds=1",
              "--set", "hidden_units=8", "--set", "buffer_size=64", "--set", "batch_size=64"]
    assert main(["train", *common, "--steps", "128", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["agent_steps"] == 128
    assert main(["train", *common, "--steps", "256", "--resume", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["agent_steps"] == 256
    assert main(["train", *common, "--steps", "256", "--resume", "--set", "gamma=0.5"]) == 2
    assert "gamma" in capsys.readouterr().err


def test_a_resumed_grid_finishes_what_is_left(tmp_path):
    tiny = dict(TINY)
    points = [compile(short_scenario("wind_farm_control")), compile(short_scenario("wind_farm_control", 30))]
    configs = [make_config("wind_farm_control", tiny) for _ in points]
    run_grid(points[:1], configs[:1], tmp_path, progress=False)  # the second point never started
    done = next(tmp_path.glob("000-*")) / "checkpoint.pt"
    before = torch.load(done, weights_only=True)["model"]
    results = run_grid(points, configs, tmp_path, progress=False, resume=True)
    assert [r["agent_steps"] for r in results] == [tiny["max_steps"]] * 2
    assert [r["resumed_at"] for r in results] == [[], []]  # nothing was left to go on with, or it started afresh
    after = torch.load(done, weights_only=True)["model"]
    assert all(torch.equal(before[k], after[k]) for k in before)  # a finished point is not trained again


def test_the_curve_is_on_disk_at_every_checkpoint(wrm, tiny, tmp_path):
    """A long run can be followed (and survives a kill) from curve.json, rewritten with each checkpoint."""
    run, seen = tmp_path / "run", []

    def look(update):
        path = run / "curve.json"
        seen.append((update["agent_steps"], json.loads(path.read_text()) if path.is_file() else None))

    train(wrm, make_config(wrm.environment, tiny, {"checkpoint_every": 180}), run, progress=False, on_update=look)
    assert [steps for steps, _ in seen] == [90, 180, 270]
    assert seen[0][1] is None and seen[1][1] is None  # the first checkpoint is taken after the second update
    assert [p["agent_steps"] for p in seen[2][1]] == [90, 180]
    assert len(json.loads((run / "curve.json").read_text())) == 3


def _strip_key(checkpoint, key):
    """Rewrite ``checkpoint`` as a version of hivex from before hyperparameter ``key`` existed wrote it (checksummed,
    in a run directory without a manifest, as versions before manifests wrote them)."""
    from hivex_dsl.train.checkpoint import seal
    from hivex_dsl.train.rundir import MANIFEST

    data = torch.load(checkpoint, weights_only=True)
    del data["config"][key]
    torch.save(data | {"checksums": seal(data)}, checkpoint)
    (checkpoint.parent / MANIFEST).unlink(missing_ok=True)


def test_a_run_from_before_curiosity_module_goes_on_with_the_module_it_trained(wrm, tiny, tmp_path):
    from hivex_dsl.train.checkpoint import load_checkpoint

    run = tmp_path / "run"
    first = make_config(wrm.environment, tiny, {"curiosity_module": "hivex_v1"})
    train(wrm, first, run, progress=False, on_update=stop_after_first_update)
    _strip_key(run / "checkpoint.pt", "curiosity_module")
    assert load_checkpoint(run / "checkpoint.pt")["config"].curiosity_module == "hivex_v1"
    with pytest.raises(TrainError, match=r"curiosity_module: 'hivex_v1' -> 'ml_agents'"):
        train(wrm, make_config(wrm.environment, tiny), run, progress=False, resume=True)
    assert train(wrm, first, run, progress=False, resume=True)["agent_steps"] == tiny["max_steps"]


def test_a_checkpoint_without_curiosity_or_continuous_actions_from_before_their_keys_reads_the_defaults(tiny, tmp_path):
    from hivex_dsl.train.checkpoint import load_checkpoint

    wfc = compile(short_scenario("wind_farm_control"))
    run = tmp_path / "run"
    train(wfc, make_config(wfc.environment, tiny), run, progress=False)
    _strip_key(run / "checkpoint.pt", "curiosity_module")
    _strip_key(run / "checkpoint.pt", "continuous_actions")
    _strip_key(run / "checkpoint.pt", "policy_loss")
    config = load_checkpoint(run / "checkpoint.pt")["config"]
    assert (config.curiosity_module, config.continuous_actions, config.policy_loss) == ("ml_agents",) * 3
    train(wfc, make_config(wfc.environment, tiny, {"max_steps": 2 * tiny["max_steps"]}), run, progress=False,
          resume=True)


def test_keys_added_since_read_as_what_they_meant_then_where_they_change_the_policy():
    from gymnasium import spaces

    from hivex_dsl.train.checkpoint import older_defaults

    hybrid = spaces.Dict({"continuous": spaces.Box(-1.0, 1.0, (1,)), "discrete": spaces.MultiDiscrete([2])})
    # every policy from before weight_init started from cleanrl; every run before summary_freq logged each update;
    # every critic from before value_loss learned clipped
    before = {"seed": 3, "weight_init": "cleanrl", "summary_freq": 1, "value_loss": "clipped"}
    assert older_defaults({"seed": 3}, hybrid) == before | {"continuous_actions": "clip", "policy_loss": "joint"}
    assert older_defaults({"seed": 3}, spaces.MultiDiscrete([2, 3])) == before | {"policy_loss": "joint"}
    assert older_defaults({"seed": 3}, spaces.Discrete(3)) == before  # one dimension: the losses agree
    assert older_defaults({"weight_init": "ml_agents"}, hybrid)["weight_init"] == "ml_agents"
    assert older_defaults({"policy_loss": "ml_agents"}, hybrid)["policy_loss"] == "ml_agents"  # written, kept
    assert older_defaults({"curiosity_strength": 0.1}, spaces.Discrete(3))["curiosity_module"] == "hivex_v1"
    assert older_defaults({"summary_freq": 6000}, spaces.Discrete(3))["summary_freq"] == 6000  # written, kept


@pytest.fixture
def interrupted(monkeypatch):
    """Every run that `hivex train` starts gets Ctrl-C after its first update."""
    from hivex_dsl.train import ppo

    real = ppo.train
    monkeypatch.setattr(ppo, "train", lambda *a, **kw: real(*a, **kw, on_update=stop_after_first_update))


def test_an_interrupted_command_exits_130_and_says_how_to_go_on(interrupted, tmp_path, capsys):
    scenario = tmp_path / "wrm.yaml"
    scenario.write_text(json.dumps(short_scenario("wildfire_resource_management", episode_length=8)))
    sets = [arg for key, value in (TINY | ONE_MINIBATCH).items() for arg in ("--set", f"{key}={value}")]
    assert main(["train", str(scenario), "-o", str(tmp_path / "run"), "--no-progress", "--json", *sets]) == 130
    out, err = capsys.readouterr()
    assert json.loads(out)["stopped_early"] is True
    assert err == (f"hivex: interrupted: the run stopped after its update and kept its checkpoint; add --resume to "
                   f"the same command to go on in {tmp_path / 'run'}\n")


def test_ctrl_c_stops_a_grid_with_its_point(interrupted, wrm, tiny, tmp_path):
    points = [wrm, compile(short_scenario("wildfire_resource_management", episode_length=9))]
    results = run_grid(points, [make_config(p.environment, tiny) for p in points], tmp_path, progress=False)
    assert [r["stopped_early"] for r in results] == [True]  # the second point never started
    assert len(list(tmp_path.glob("0*"))) == 1
    assert json.loads((tmp_path / "results.json").read_text()) == results


def test_the_run_s_json_files_are_written_atomically(wrm, tiny, tmp_path, monkeypatch):
    """A run killed while it writes curve.json leaves the earlier curve.json whole (it was written in place)."""
    from pathlib import Path

    cfg = make_config(wrm.environment, tiny)
    train(wrm, cfg, tmp_path, progress=False, on_update=stop_after_first_update)
    before = (tmp_path / "curve.json").read_text()
    write_text = Path.write_text

    def killed_halfway(path, text, *args, **kwargs):
        if ".json" in path.name:
            write_text(path, text[: len(text) // 2], *args, **kwargs)
            raise KeyboardInterrupt
        return write_text(path, text, *args, **kwargs)

    monkeypatch.setattr(Path, "write_text", killed_halfway)
    with pytest.raises(KeyboardInterrupt):
        train(wrm, cfg, tmp_path, progress=False, resume=True)
    monkeypatch.undo()
    assert (tmp_path / "curve.json").read_text() == before and json.loads((tmp_path / "config.json").read_text())
    train(wrm, cfg, tmp_path, progress=False, resume=True)  # the next claim clears the half-written .partial
    assert not list(tmp_path.glob("*.partial"))


def test_a_second_ctrl_c_ends_the_command_at_once_without_a_traceback(monkeypatch, tmp_path, capsys):
    from hivex_dsl.train import ppo

    def twice(*_):
        os.kill(os.getpid(), signal.SIGINT)  # the first asks the run to stop after this update
        # A process's signal may reach one of torch's threads; the main thread runs the handler at its next
        # bytecode, and two signals pending by then count as one. Wait for the first to be taken, as a person's
        # second Ctrl-C comes after it.
        deadline = time.monotonic() + 10
        while getattr(signal.getsignal(signal.SIGINT), "__func__", None) is ppo.StopRequests._request:
            assert time.monotonic() < deadline, "the first Ctrl-C was never handled"
            time.sleep(0.001)
        os.kill(os.getpid(), signal.SIGINT)  # the second kills it

    real = ppo.train
    monkeypatch.setattr(ppo, "train", lambda *a, **kw: real(*a, **kw, on_update=twice))
    scenario = tmp_path / "wrm.yaml"
    scenario.write_text(json.dumps(short_scenario("wildfire_resource_management", episode_length=8)))
    sets = [arg for key, value in (TINY | ONE_MINIBATCH).items() for arg in ("--set", f"{key}={value}")]
    # a `hivex` process starts with Python's own SIGINT handler; a test before this one may have left another
    found = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        assert main(["train", str(scenario), "-o", str(tmp_path / "run"), "--no-progress", "--json", *sets]) == 130
    finally:
        signal.signal(signal.SIGINT, found)
    assert capsys.readouterr().err == "hivex: interrupted\n", f"SIGINT's handler before the test: {found!r}"


def test_a_run_names_every_machine_it_trained_on(wrm, tiny, tmp_path, monkeypatch):
    """A run reproduces only on alike processors, so its summary (and the checkpoint it goes on from) lists each
    machine it trained on once, in the order first used: stopped on one, resumed on another, then on the first."""
    from hivex_dsl.train import ppo

    cfg, run = make_config(wrm.environment, tiny | {"max_steps": 450}), tmp_path / "run"
    monkeypatch.setattr(ppo, "machine", lambda device: f"machine A ({device})")
    assert train(wrm, cfg, run, progress=False, on_update=stop_after_first_update)["machines"] == ["machine A (cpu)"]
    monkeypatch.setattr(ppo, "machine", lambda device: "machine B")
    second = train(wrm, cfg, run, progress=False, resume=True, on_update=stop_after_first_update)
    assert second["machines"] == ["machine A (cpu)", "machine B"]
    monkeypatch.setattr(ppo, "machine", lambda device: f"machine A ({device})")
    third = train(wrm, cfg, run, progress=False, resume=True)
    assert not third["stopped_early"] and third["machines"] == ["machine A (cpu)", "machine B"]
    assert json.loads((run / "summary.json").read_text())["machines"] == third["machines"]
