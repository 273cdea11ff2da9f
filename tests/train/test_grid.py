"""A sweep trains every point in its own run directory and gathers one table: in turn, or as Ray tasks."""

from __future__ import annotations

import json
import signal

import pytest

from hivex_dsl.compiler import compile_all
from hivex_dsl.train.config import make_config
from hivex_dsl.train.grid import format_table, run_grid

from .conftest import short_scenario


def _two_points():
    sweep = short_scenario("wind_farm_control", episode_length=16) | {"sweep": {"pattern": [0, 1]}}
    del sweep["pattern"]
    return compile_all(sweep)


def _check(results, points, run_dir):
    assert [r["scenario"] for r in results] == [p.name for p in points]
    assert json.loads((run_dir / "results.json").read_text()) == results
    dirs = sorted(p.name for p in run_dir.iterdir() if p.is_dir() and p.name != ".hivex")
    assert dirs == ["000-wfc-main_pattern=0", "001-wfc-main_pattern=1"]
    for r in results:
        assert r["test_return"]["std"] >= 0
        assert (run_dir / r["run_dir"].rsplit("/", 1)[-1] / "checkpoint.pt").is_file()
    # a few steps' episodes are not the paper's 5,000: no published cell beside them (test_grid_record.py sets
    # the cells beside a grid as if its points reproduced them)
    assert [r["published_return"] for r in results] == [None, None]
    assert format_table(results).count("\n") == 2


def test_a_sweep_trains_every_point_in_turn(tiny, tmp_path):
    points = _two_points()
    configs = [make_config(p.environment, tiny) for p in points]
    _check(run_grid(points, configs, tmp_path, eval_episodes=1, progress=False), points, tmp_path)


def test_a_sweep_runs_on_a_local_ray_instance(tiny, tmp_path):
    pytest.importorskip("ray")
    points = _two_points()
    configs = [make_config(p.environment, tiny) for p in points]
    before = signal.getsignal(signal.SIGINT), signal.getsignal(signal.SIGTERM)
    results = run_grid(points, configs, tmp_path, eval_episodes=1, ray_address="local",
                       ray_init={"num_cpus": 2}, progress=False)
    _check(results, points, tmp_path)
    # ray.init ignores Ctrl-C in the driver and takes SIGTERM; the caller's process gets its own handlers back
    assert (signal.getsignal(signal.SIGINT), signal.getsignal(signal.SIGTERM)) == before


def test_the_command_trains_a_sweep_file(tmp_path, capsys):
    from hivex_dsl.cli import main

    sweep = short_scenario("wind_farm_control", episode_length=8) | {"sweep": {"pattern": [0, 1]}}
    del sweep["pattern"]
    path = tmp_path / "sweep.yaml"
    path.write_text(json.dumps(sweep))
    args = ["train", str(path), "-o", str(tmp_path / "runs"), "--steps", "64", "--no-progress",
            "--set", "num_worlds=1", "--set", "buffer_size=32", "--set", "batch_size=32",
            "--set", "hidden_units=8"]
    assert main(args) == 0
    out = capsys.readouterr().out
    assert "wfc-main[pattern=0]" in out and "wfc-main[pattern=1]" in out
    assert len(json.loads((tmp_path / "runs" / "results.json").read_text())) == 2


def test_the_command_trains_the_points_asked_in_their_own_folders(tmp_path, capsys):
    """--points: a grid trained a few points at a time; each point in the folder its sweep index names, and one
    results table of all the points trained so far."""
    from hivex_dsl.cli import main

    sweep = short_scenario("wind_farm_control", episode_length=8) | {"sweep": {"pattern": [0, 1, 2]}}
    del sweep["pattern"]
    path, runs = tmp_path / "sweep.yaml", tmp_path / "runs"
    path.write_text(json.dumps(sweep))
    args = ["train", str(path), "-o", str(runs), "--steps", "32", "--no-progress", "--set", "num_worlds=1",
            "--set", "buffer_size=32", "--set", "batch_size=32", "--set", "hidden_units=8"]
    assert main([*args, "--points", "2"]) == 0
    assert sorted(p.name for p in runs.iterdir() if p.is_dir() and p.name != ".hivex") == ["002-wfc-main_pattern=2"]
    assert main([*args, "--points", "0-1"]) == 0
    assert sorted(p.name for p in runs.iterdir() if p.is_dir() and p.name != ".hivex") == [
        "000-wfc-main_pattern=0", "001-wfc-main_pattern=1", "002-wfc-main_pattern=2"]
    table = json.loads((runs / "results.json").read_text())
    assert [row["scenario"] for row in table] == [f"wfc-main[pattern={k}]" for k in (0, 1, 2)]
    capsys.readouterr()
    for bad, said in [("3", "'3' is not within the 3 points of"),
                      ("1-0", "'1-0' is a range from high to low: write it 0-1"),
                      ("0,x", "expected indices and ranges joined by commas (e.g. 0,14-29), got 'x'"),
                      # issue 54, items 9 and 12: str.isdigit took these as 1 and 3, and '²' to a traceback
                      ("\u0661", "got '\u0661' (indices are written in the digits 0-9)"),
                      ("\uff13", "got '\uff13' (indices are written in the digits 0-9)"),
                      ("\u00b2", "got '\u00b2' (indices are written in the digits 0-9)"),
                      ("0-\u00b2", "got '0-\u00b2' (indices are written in the digits 0-9)")]:
        assert main([*args, "--points", bad, "--resume"]) == 2
        assert said in capsys.readouterr().err
    single = tmp_path / "one.yaml"
    single.write_text(json.dumps(short_scenario("wind_farm_control", episode_length=8)))
    assert main(["train", str(single), "--points", "0"]) == 2
    assert f"--points chooses points of a sweep, and {single} is one scenario" in capsys.readouterr().err


def _weights(run_dir):
    import torch

    found = {}
    for folder in sorted(p for p in run_dir.iterdir() if p.is_dir() and p.name != ".hivex"):
        model = torch.load(folder / "checkpoint.pt", weights_only=False)["model"]
        found[folder.name] = torch.cat([v.flatten().float() for v in model.values()])
    return found


def test_two_points_at_once_train_exactly_as_in_turn(tiny, tmp_path):
    """--jobs 2: each point in a process of its own gives the same summaries and weights as the points in turn
    (one torch thread each, so the arithmetic is the same)."""
    import torch

    points = _two_points()
    configs = [make_config(p.environment, tiny | {"torch_threads": 1}) for p in points]
    in_turn = run_grid(points, configs, tmp_path / "turn", eval_episodes=1, progress=False)
    at_once = run_grid(points, configs, tmp_path / "once", eval_episodes=1, progress=False, jobs=2)
    _check(at_once, points, tmp_path / "once")
    drop = ("wall_s", "run_dir")
    assert [{k: v for k, v in r.items() if k not in drop} for r in at_once] == \
        [{k: v for k, v in r.items() if k not in drop} for r in in_turn]
    turn, once = _weights(tmp_path / "turn"), _weights(tmp_path / "once")
    assert turn.keys() == once.keys() and all(torch.equal(turn[k], once[k]) for k in turn)


def test_points_at_once_share_the_cores():
    from hivex_dsl.train.grid import shared_cores

    auto = make_config("wind_farm_control")
    assert auto.torch_threads == "auto"
    assert shared_cores(auto, 2).torch_threads == max(1, auto.threads() // 2)
    assert shared_cores(auto, 10_000).torch_threads == 1
    assert shared_cores(make_config("wind_farm_control", {"torch_threads": 3}), 2).torch_threads == 3


def test_a_failing_point_at_once_stops_the_grid_with_its_error(tiny, tmp_path):
    """Point 1's checkpoint swapped for point 0's in a folder without a manifest (an earlier hivex's, so nothing
    refuses it before the points start): resuming it is refused inside its process, and the grid raises that
    refusal instead of a bare traceback from a child."""
    from hivex_dsl.train.config import TrainError

    points = _two_points()
    configs = [make_config(p.environment, tiny | {"torch_threads": 1}) for p in points]
    run_grid(points, configs, tmp_path, progress=False)
    first, second = sorted(p for p in tmp_path.iterdir() if p.is_dir() and p.name != ".hivex")
    (second / "checkpoint.pt").write_bytes((first / "checkpoint.pt").read_bytes())
    (second / ".hivex" / "manifest.json").unlink()
    longer = [c.model_copy(update={"max_steps": 2 * c.max_steps}) for c in configs]
    with pytest.raises(TrainError, match=r"cannot resume from .*001-wfc-main_pattern=1.* it trained scenario "
                                         r"'wfc-main\[pattern=0\]'"):
        run_grid(points, longer, tmp_path, progress=False, resume=True, jobs=2)


def test_sigterm_stops_the_points_under_way_and_starts_no_other(tmp_path):
    """A grid of three points, two at a time, stopped by SIGTERM once both have begun: both finish their update
    and keep a checkpoint, the third never starts, and the command says the grid stopped early."""
    import signal
    import subprocess
    import sys
    import time

    sweep = short_scenario("wind_farm_control", episode_length=16) | {"sweep": {"pattern": [0, 1, 2]}}
    del sweep["pattern"]
    path = tmp_path / "sweep.yaml"
    path.write_text(json.dumps(sweep))
    runs = tmp_path / "runs"
    command = [sys.executable, "-m", "hivex_dsl.cli", "train", str(path), "-o", str(runs), "--steps", "100000000",
               "--jobs", "2", "--no-progress", "--set", "num_worlds=1", "--set", "buffer_size=32",
               "--set", "batch_size=32", "--set", "hidden_units=8", "--set", "torch_threads=1"]
    grid = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 120
    begun = lambda: len(list(runs.glob("*/config.json"))) == 2  # noqa: E731 - written as training begins
    while not begun() and time.monotonic() < deadline and grid.poll() is None:
        time.sleep(0.2)
    assert begun(), grid.communicate()
    time.sleep(1.0)
    grid.send_signal(signal.SIGTERM)
    out, err = grid.communicate(timeout=120)
    results = json.loads((runs / "results.json").read_text())
    assert [r["stopped_early"] for r in results] == [True, True], (out, err)
    assert sorted(p.name for p in runs.iterdir() if p.is_dir() and p.name != ".hivex") == ["000-wfc-main_pattern=0",
                                                                    "001-wfc-main_pattern=1"]
    assert all((runs / name / "checkpoint.pt").is_file() for name in ("000-wfc-main_pattern=0",
                                                                       "001-wfc-main_pattern=1"))
    assert grid.returncode != 0


def test_jobs_and_ray_together_are_refused(tmp_path, capsys):
    from hivex_dsl.cli import main

    sweep = short_scenario("wind_farm_control", episode_length=8) | {"sweep": {"pattern": [0, 1]}}
    del sweep["pattern"]
    path = tmp_path / "sweep.yaml"
    path.write_text(json.dumps(sweep))
    assert main(["train", str(path), "-o", str(tmp_path / "runs"), "--jobs", "2", "--ray"]) == 2
    assert "--jobs 2 runs the points in local processes and --ray runs them as Ray tasks" in capsys.readouterr().err
    assert not (tmp_path / "runs").exists()
