"""A new run never silently replaces an earlier one in its run directory: --resume goes on, --force replaces."""

from __future__ import annotations

import json

import pytest

from hivex_dsl.cli import main
from hivex_dsl.compiler import compile
from hivex_dsl.train.config import TrainError, make_config
from hivex_dsl.train.grid import run_grid
from hivex_dsl.train.ppo import train
from hivex_dsl.train.rundir import earlier_run

from .conftest import short_scenario


@pytest.fixture
def wfc():
    return compile(short_scenario("wind_farm_control"))


def test_a_second_run_into_the_same_directory_is_refused_and_changes_nothing(wfc, tiny, tmp_path):
    train(wfc, make_config(wfc.environment, tiny), tmp_path, progress=False)
    before = {p.relative_to(tmp_path): p.read_bytes() for p in tmp_path.rglob("*") if p.is_file()}
    with pytest.raises(TrainError, match=r"holds an earlier run \(checkpoint.pt, checkpoints/ \(1 file\), config.json, "
                                         r"curve.json, summary.json, tb/ \(1 file\)\): add --resume .* --force"):
        train(wfc, make_config(wfc.environment, tiny, {"seed": 1}), tmp_path, progress=False)
    assert {p.relative_to(tmp_path): p.read_bytes() for p in tmp_path.rglob("*") if p.is_file()} == before


def test_overwrite_replaces_the_earlier_run_s_files_and_only_those(wfc, tiny, tmp_path):
    train(wfc, make_config(wfc.environment, tiny, {"checkpoint_every": 64, "keep_checkpoints": 5}), tmp_path,
          progress=False)
    assert len(list((tmp_path / "checkpoints").glob("*.pt"))) == 3  # 64, 128, 192
    (tmp_path / "notes.md").write_text("the user's own file\n")
    old_events = {p.name for p in (tmp_path / "tb").iterdir()}
    summary = train(wfc, make_config(wfc.environment, tiny, {"seed": 1}), tmp_path, progress=False, overwrite=True)
    assert summary["seed"] == 1
    # the earlier run's three checkpoints are gone, not mixed with this run's one (checkpoint_every 128)
    assert [p.name for p in (tmp_path / "checkpoints").glob("*.pt")] == ["step_000000000128.pt"]
    assert not old_events & {p.name for p in (tmp_path / "tb").iterdir()}  # one run's scalars in tb/
    assert (tmp_path / "notes.md").read_text() == "the user's own file\n"


def test_overwrite_keeps_the_user_s_own_files_in_the_run_s_folders(wfc, tiny, tmp_path):
    """The issue's reproducer: --force removed all of checkpoints/ and tb/, a user's best.pt and events too."""
    (tmp_path / "checkpoints").mkdir()
    (tmp_path / "tb").mkdir()
    (tmp_path / "checkpoints" / "best.pt").write_text("x")
    (tmp_path / "tb" / "other.tfevents").write_text("x")
    (tmp_path / "checkpoints" / "step_000000000064.pt.partial").write_text("half a save")
    assert earlier_run(tmp_path) == ["checkpoints/step_000000000064.pt.partial"]
    train(wfc, make_config(wfc.environment, tiny), tmp_path, progress=False, overwrite=True)
    assert (tmp_path / "checkpoints" / "best.pt").read_text() == "x"
    assert (tmp_path / "tb" / "other.tfevents").read_text() == "x"
    assert not list(tmp_path.glob("checkpoints/*.partial"))
    train(wfc, make_config(wfc.environment, tiny, {"seed": 1}), tmp_path, progress=False, overwrite=True)
    assert sorted(p.name for p in (tmp_path / "checkpoints").iterdir()) == ["best.pt", "step_000000000128.pt"]
    assert len(list((tmp_path / "tb").iterdir())) == 2  # the user's file and this run's events


def test_a_file_of_the_user_s_at_a_name_the_run_writes_is_never_overwritten(wfc, tiny, tmp_path):
    (tmp_path / "config.json").write_text('{"editor": "vim"}')
    for overwrite in (False, True):
        with pytest.raises(TrainError, match=r"holds config.json, which a run did not write and would overwrite"):
            train(wfc, make_config(wfc.environment, tiny), tmp_path, progress=False, overwrite=overwrite)
    assert (tmp_path / "config.json").read_text() == '{"editor": "vim"}'


def test_resuming_removes_the_half_written_saves_of_an_interrupted_run(wfc, tiny, tmp_path):
    train(wfc, make_config(wfc.environment, tiny, {"max_steps": 64}), tmp_path, progress=False)
    (tmp_path / "checkpoints").mkdir(exist_ok=True)
    (tmp_path / "checkpoints" / "step_000000000128.pt.partial").write_text("killed mid-save")
    train(wfc, make_config(wfc.environment, tiny), tmp_path, progress=False, resume=True)
    assert not list(tmp_path.rglob("*.partial"))


def test_the_command_says_what_to_do_with_a_used_run_directory(tmp_path, capsys):
    scenario = tmp_path / "wfc.yaml"
    scenario.write_text(json.dumps(short_scenario("wind_farm_control", episode_length=16)))
    common = ["train", str(scenario), "-o", str(tmp_path / "run"), "--no-progress", "--steps", "64",
              "--set", "num_worlds=1", "--set", "hidden_units=8", "--set", "buffer_size=64", "--set", "batch_size=64"]
    assert main(common) == 0
    capsys.readouterr()
    assert main(common) == 2
    assert capsys.readouterr().err.startswith(f"hivex: {tmp_path / 'run'} holds an earlier run (checkpoint.pt")
    assert main(common + ["--resume", "--force"]) == 2
    assert "give one" in capsys.readouterr().err
    assert main(common + ["--force", "--seed", "5", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["seed"] == 5
    (tmp_path / "file").write_text("")
    assert main([*common[:3], str(tmp_path / "file"), *common[4:]]) == 2
    assert capsys.readouterr().err == f"hivex: {tmp_path / 'file'} is a file, not a run directory: give a " \
                                      "directory's path (it is made if new)\n"


def test_a_grid_over_earlier_runs_is_refused_before_any_point_trains(tiny, tmp_path):
    points = [compile(short_scenario("wind_farm_control")), compile(short_scenario("wind_farm_control", 30))]
    configs = [make_config("wind_farm_control", tiny) for _ in points]
    run_grid(points[1:], configs[1:], tmp_path, progress=False)  # 000-: the second point's folder
    taken = next(tmp_path.glob("000-*")) / "checkpoint.pt"
    before = taken.read_bytes()
    with pytest.raises(TrainError, match="000-wfc-main holds an earlier run"):
        run_grid(points, configs, tmp_path, progress=False)
    assert not list(tmp_path.glob("001-*")) and taken.read_bytes() == before
    results = run_grid(points, configs, tmp_path, progress=False, overwrite=True)
    assert [r["agent_steps"] for r in results] == [tiny["max_steps"]] * 2
