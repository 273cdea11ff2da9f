"""A sweep trains every point in its own run directory and gathers one table: in turn, or as Ray tasks."""

from __future__ import annotations

import json

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
    dirs = sorted(p.name for p in run_dir.iterdir() if p.is_dir())
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
    results = run_grid(points, configs, tmp_path, eval_episodes=1, ray_address="local",
                       ray_init={"num_cpus": 2}, progress=False)
    _check(results, points, tmp_path)


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
