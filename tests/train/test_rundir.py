"""A new run never silently replaces an earlier one in its run directory: --resume goes on, --force replaces."""

from __future__ import annotations

import json

import pytest

from hivex_dsl.cli import main
from hivex_dsl.compiler import compile
from hivex_dsl.train.config import TrainError, make_config
from hivex_dsl.train.grid import run_grid
from hivex_dsl.train.ppo import train
from hivex_dsl.train.rundir import Inventory, RunDir

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
    assert Inventory(tmp_path).ours == []  # none of them is a run's
    train(wfc, make_config(wfc.environment, tiny), tmp_path, progress=False, overwrite=True)
    assert (tmp_path / "checkpoints" / "best.pt").read_text() == "x"
    assert (tmp_path / "tb" / "other.tfevents").read_text() == "x"
    train(wfc, make_config(wfc.environment, tiny, {"seed": 1}), tmp_path, progress=False, overwrite=True)
    assert sorted(p.name for p in (tmp_path / "checkpoints").iterdir()) == ["best.pt", "step_000000000128.pt"]
    assert len(list((tmp_path / "tb").iterdir())) == 2  # the user's file and this run's events


def test_a_file_of_the_user_s_at_a_name_the_run_writes_is_never_overwritten(wfc, tiny, tmp_path):
    (tmp_path / "config.json").write_text('{"editor": "vim"}')
    for overwrite in (False, True):
        with pytest.raises(TrainError, match=r"holds config.json, which hivex did not write, at names a run writes"):
            train(wfc, make_config(wfc.environment, tiny), tmp_path, progress=False, overwrite=overwrite)
    assert (tmp_path / "config.json").read_text() == '{"editor": "vim"}'


def test_resuming_removes_the_half_written_saves_of_an_interrupted_run(wfc, tiny, tmp_path):
    train(wfc, make_config(wfc.environment, tiny, {"max_steps": 64}), tmp_path, progress=False)

    def killed_mid_save(partial):
        partial.write_text("half a save")
        raise KeyboardInterrupt

    (tmp_path / "checkpoints").mkdir(exist_ok=True)
    with RunDir.claim(tmp_path, resume=True) as run, pytest.raises(KeyboardInterrupt):
        run.write(tmp_path / "checkpoints" / "step_000000000128.pt", killed_mid_save)
    assert (tmp_path / "checkpoints" / "step_000000000128.pt.partial").is_file()
    train(wfc, make_config(wfc.environment, tiny), tmp_path, progress=False, resume=True)
    assert not list(tmp_path.rglob("*.partial"))


def test_a_partial_file_no_run_announced_is_the_user_s(wfc, tiny, tmp_path):
    """Before manifests, --force and --resume removed any ``*.partial`` at a run's names (and ``*.json.partial``)."""
    train(wfc, make_config(wfc.environment, tiny, {"max_steps": 64}), tmp_path, progress=False)
    (tmp_path / "checkpoint.pt.partial").write_text("the user's")
    (tmp_path / "draft.json.partial").write_text("the user's draft")
    with pytest.raises(TrainError, match=r"holds checkpoint.pt.partial, which hivex did not write"):
        train(wfc, make_config(wfc.environment, tiny), tmp_path, progress=False, resume=True)
    (tmp_path / "checkpoint.pt.partial").unlink()
    train(wfc, make_config(wfc.environment, tiny), tmp_path, progress=False, overwrite=True)
    assert (tmp_path / "draft.json.partial").read_text() == "the user's draft"


def test_the_command_says_what_to_do_with_a_used_run_directory(tmp_path, capsys):
    scenario = tmp_path / "wfc.yaml"
    scenario.write_text(json.dumps(short_scenario("wind_farm_control", episode_length=16)))
    common = ["train", str(scenario), "-o", str(tmp_path / "run"), "--no-progress", "--steps", "64",
              "--set", "num_worlds=1", "--set", "buffer_fill=rollout",
              "--set", "hidden_units=8", "--set", "buffer_size=64", "--set", "batch_size=64"]
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


USER_FILES = {"curve.json": "[0.1, 0.5, 0.9]", "evaluation.json": '{"split": "validation", "accuracy": 0.91}',
              "summary.json": '{"agent_steps": 5, "mine": true}', "checkpoint.pt": "my weights",
              "checkpoints/step_best.pt": "my best", "tb/events.out.tfevents.mine": "my scalars"}


@pytest.mark.parametrize("name", USER_FILES)
def test_force_refuses_a_user_s_file_at_a_run_s_name_and_keeps_it(name, wfc, tiny, tmp_path):
    """Issue 54, item 1: --force deleted or overwrote each of these (any JSON list passed as a run's curve, any
    ``step_*.pt`` or event file by its name); a run's files are now the ones its manifest lists."""
    (tmp_path / name).parent.mkdir(parents=True, exist_ok=True)
    (tmp_path / name).write_text(USER_FILES[name])
    with pytest.raises(TrainError, match=rf"holds {name}(, which hivex did not write,| at names a run writes, and no "
                                         r"run manifest .*so --force removes nothing)"):
        train(wfc, make_config(wfc.environment, tiny), tmp_path, progress=False, overwrite=True)
    assert (tmp_path / name).read_text() == USER_FILES[name]
    assert not (tmp_path / "config.json").exists()


def test_force_refuses_a_file_of_the_run_s_changed_since_and_keeps_it(wfc, tiny, tmp_path):
    train(wfc, make_config(wfc.environment, tiny), tmp_path, progress=False)
    edited = json.loads((tmp_path / "summary.json").read_text()) | {"note": "my edit"}
    (tmp_path / "summary.json").write_text(json.dumps(edited))
    for mode in ({"overwrite": True}, {"resume": True}):
        with pytest.raises(TrainError, match=r"holds summary.json, changed since the run wrote it"):
            train(wfc, make_config(wfc.environment, tiny), tmp_path, progress=False, **mode)
    assert json.loads((tmp_path / "summary.json").read_text()) == edited


def test_nothing_is_followed_through_a_linked_run_folder(wfc, tiny, tmp_path):
    """A ``checkpoints/`` that is a link to the user's own folder: --force deleted its ``step_*.pt``."""
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    (elsewhere / "step_000000000064.pt").write_text("the user's")
    run = tmp_path / "run"
    run.mkdir()
    (run / "checkpoints").symlink_to(elsewhere, target_is_directory=True)
    with pytest.raises(TrainError, match=r"holds checkpoints \(a link\), which hivex did not write"):
        train(wfc, make_config(wfc.environment, tiny), run, progress=False, overwrite=True)
    assert (elsewhere / "step_000000000064.pt").read_text() == "the user's"


def test_a_second_writer_is_refused_at_once_and_a_dead_one_s_lock_is_not_held(wfc, tiny, tmp_path):
    """Issue 54, item 3: two `hivex train -o same` at once both ran. The lock is an flock, which ends with its
    process however it ends: a SIGKILLed holder leaves nothing that refuses the next run."""
    import os
    import signal
    import subprocess
    import sys
    import time

    holder = subprocess.Popen([sys.executable, "-c", "import sys, time\nfrom hivex_dsl.train.rundir import RunDir\n"
                               f"held = RunDir.claim({str(tmp_path)!r})\nprint('held', flush=True)\ntime.sleep(600)"],
                              stdout=subprocess.PIPE, text=True, env=os.environ | {"PYTHONPATH": os.getcwd()})
    assert holder.stdout.readline() == "held\n"
    started = time.monotonic()
    with pytest.raises(TrainError, match=rf"^another hivex is writing to {tmp_path} \(process {holder.pid} on .*, "
                                         r"since .*\): wait for it to end, or give another run directory$"):
        train(wfc, make_config(wfc.environment, tiny), tmp_path, progress=False, overwrite=True)
    assert time.monotonic() - started < 5  # at once, not after a wait
    holder.send_signal(signal.SIGKILL)
    holder.wait(timeout=30)
    assert train(wfc, make_config(wfc.environment, tiny), tmp_path, progress=False)["agent_steps"] == 192


def test_the_same_process_cannot_claim_a_run_directory_twice(wfc, tiny, tmp_path):
    with RunDir.claim(tmp_path):
        with pytest.raises(TrainError, match=r"another hivex is writing to"):
            train(wfc, make_config(wfc.environment, tiny), tmp_path, progress=False)
    train(wfc, make_config(wfc.environment, tiny), tmp_path, progress=False)  # released with its block


def test_a_manifest_edited_to_list_another_file_is_refused(wfc, tiny, tmp_path):
    """The manifest decides what --force removes: one that lists a file outside the run's names (with its digest
    written in) is refused, and the file stays."""
    from hivex_dsl.train.rundir import MANIFEST, file_digest

    run = tmp_path / "run"
    train(wfc, make_config(wfc.environment, tiny), run, progress=False)
    (tmp_path / "precious.txt").write_text("mine")
    manifest = json.loads((run / MANIFEST).read_text())
    manifest["files"]["../precious.txt"] = {"sha256": [file_digest(tmp_path / "precious.txt")]}
    (run / MANIFEST).write_text(json.dumps(manifest))
    with pytest.raises(TrainError, match=r"manifest.json lists '../precious.txt', not names a run writes"):
        train(wfc, make_config(wfc.environment, tiny), run, progress=False, overwrite=True)
    assert (tmp_path / "precious.txt").read_text() == "mine"
