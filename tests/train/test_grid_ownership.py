"""A grid's folder is the grid's: its table is matched to its points by their folders (wherever the grid is moved),
a table that is not hivex's is refused, a point is not restarted over a run whose checkpoint is gone, and the
points trained in processes of their own end with the command however it ends."""

from __future__ import annotations

import json
import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from hivex_dsl.compiler import compile_all
from hivex_dsl.train.config import TrainError, make_config
from hivex_dsl.train.grid import run_grid
from hivex_dsl.train.rundir import MANIFEST, RunDir

from .conftest import short_scenario


def _sweep(patterns=(0, 1), episode_length: int = 16) -> dict:
    sweep = short_scenario("wind_farm_control", episode_length) | {"sweep": {"pattern": list(patterns)}}
    del sweep["pattern"]
    return sweep


@pytest.fixture
def points():
    return compile_all(_sweep())


def _configs(points, tiny, **changes):
    return [make_config(p.environment, tiny | {"torch_threads": 1} | changes) for p in points]


def _files(folder: Path) -> dict[str, bytes]:
    return {str(p.relative_to(folder)): p.read_bytes() for p in sorted(folder.rglob("*"))
            if p.is_file() and ".hivex" not in p.parts}


def test_resuming_a_point_whose_checkpoint_is_gone_is_refused_and_deletes_nothing(points, tiny, tmp_path):
    """Issue 54, item 2: the grid retrained such a point from 0 and deleted its checkpoints and event files, where
    a single run refuses ("cannot resume: no checkpoint")."""
    run_grid(points, _configs(points, tiny), tmp_path, progress=False)
    first, second = sorted(tmp_path.glob("00*"))
    (second / "checkpoint.pt").unlink()
    before = {folder: _files(folder) for folder in (first, second)}
    with pytest.raises(TrainError, match=rf"^cannot resume point 1: {second} holds a run that saved a checkpoint, and "
                                         r"its checkpoint.pt is gone: restore it, or train the point afresh with "
                                         r"--force --points 1$"):
        run_grid(points, _configs(points, tiny, max_steps=384), tmp_path, progress=False, resume=True)
    assert {folder: _files(folder) for folder in (first, second)} == before  # point 0 did not train on either


def test_resuming_starts_afresh_a_point_stopped_before_its_first_checkpoint(points, tiny, tmp_path):
    run_grid(points[:1], _configs(points[:1], tiny), tmp_path, progress=False)
    killed = tmp_path / "001-wfc-main_pattern=1"
    with RunDir.claim(killed) as run:  # as a point killed after writing its config, before any checkpoint
        run.write_json("config.json", {"hyperparameters": {}, "scenario": {}})
    results = run_grid(points, _configs(points, tiny), tmp_path, progress=False, resume=True)
    assert [row["agent_steps"] for row in results] == [tiny["max_steps"]] * 2


def test_the_table_keeps_one_row_per_point_after_the_grid_is_moved(points, tiny, tmp_path):
    """Issue 54, item 8: rows were keyed by their folder's absolute path, so after moving the grid and training a
    point again the table held two rows of it."""
    run_grid(points, _configs(points, tiny), tmp_path / "grid", progress=False)
    shutil.move(tmp_path / "grid", tmp_path / "moved")
    run_grid(points[1:], _configs(points[1:], tiny, seed=1), tmp_path / "moved", progress=False, overwrite=True,
             indices=[1])
    table = json.loads((tmp_path / "moved" / "results.json").read_text())
    assert [(row["run_dir"], row["seed"]) for row in table] == [("000-wfc-main_pattern=0", 0),
                                                                ("001-wfc-main_pattern=1", 1)]
    assert [row["fingerprint"] for row in table] == [p.fingerprint for p in points]


def test_a_table_an_earlier_hivex_wrote_with_whole_paths_is_taken_over(points, tiny, tmp_path):
    run_grid(points, _configs(points, tiny), tmp_path / "grid", progress=False)
    table = tmp_path / "grid" / "results.json"
    rows = json.loads(table.read_text())
    for row in rows:  # as before: the whole path, of where the grid was then
        row["run_dir"] = f"/elsewhere/grid/{row['run_dir']}"
        row.pop("fingerprint")
    table.write_text(json.dumps(rows))
    (tmp_path / "grid" / MANIFEST).unlink()  # nor did it keep a manifest
    run_grid(points[1:], _configs(points[1:], tiny), tmp_path / "grid", progress=False, overwrite=True, indices=[1])
    assert [row["run_dir"] for row in json.loads(table.read_text())] == ["000-wfc-main_pattern=0",
                                                                         "001-wfc-main_pattern=1"]


@pytest.mark.parametrize("text", ['{"my": 1}', "[1, 2]", '[{"scenario": "wfc-ma'])
def test_a_results_json_of_the_user_s_in_the_grid_folder_is_refused_before_any_point_trains(text, points, tiny,
                                                                                            tmp_path, capsys):
    """Issue 54, item 12: each was a traceback after every point had trained (and the table is not hivex's to
    overwrite)."""
    from hivex_dsl.cli import main

    (tmp_path / "results.json").write_text(text)
    with pytest.raises(TrainError, match=rf"^{tmp_path} holds results.json(, which hivex did not write| at names a "
                                         "run writes, and no run manifest)"):
        run_grid(points, _configs(points, tiny), tmp_path, progress=False)
    assert (tmp_path / "results.json").read_text() == text
    assert sorted(p.name for p in tmp_path.iterdir()) == ["results.json"]
    sweep = tmp_path.parent / f"{tmp_path.name}-sweep.yaml"
    sweep.write_text(json.dumps(_sweep()))
    assert main(["train", str(sweep), "-o", str(tmp_path), "--steps", "64", "--no-progress", "--resume"]) == 2
    assert capsys.readouterr().err.startswith(f"hivex: {tmp_path} holds results.json")


def _children(pid: int) -> set[int]:
    """The processes whose parent is ``pid`` (Linux's /proc)."""
    found = set()
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            fields = stat.read_text().rsplit(")", 1)[1].split()
        except OSError:
            continue
        if int(fields[1]) == pid:
            found.add(int(stat.parent.name))
    return found


def _alive(pid: int) -> bool:
    """Running, not a zombie waiting for its (new) parent to reap it."""
    try:
        return Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0] != "Z"
    except OSError:
        return False


@pytest.mark.skipif(not Path("/proc/self/stat").exists(), reason="lists processes through Linux's /proc")
def test_points_at_once_end_with_their_command_even_when_it_is_killed(tmp_path):
    """Issue 54, item 11: SIGKILL reaches no handler of the parent's, and the points it ran with --jobs trained on to
    their end, orphaned. Now each is sent SIGTERM as its parent dies: it stops after its update, keeps its
    checkpoint, and ends."""
    path = tmp_path / "sweep.yaml"
    path.write_text(json.dumps(_sweep(episode_length=16)))
    runs = tmp_path / "runs"
    command = [sys.executable, "-m", "hivex_dsl.cli", "train", str(path), "-o", str(runs), "--steps", "100000000",
               "--jobs", "2", "--no-progress", "--set", "num_worlds=1", "--set", "buffer_size=32",
               "--set", "batch_size=32", "--set", "hidden_units=8", "--set", "torch_threads=1",
               "--set", "checkpoint_every=64"]
    log = tmp_path / "stderr.txt"  # the points' too: they write to their parent's stderr
    grid = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=log.open("w"),
                            env=os.environ | {"PYTHONPATH": os.getcwd()})
    deadline = time.monotonic() + 120
    begun = lambda: len(list(runs.glob("*/checkpoint.pt"))) == 2  # noqa: E731 - both points are training
    while not begun() and time.monotonic() < deadline and grid.poll() is None:
        time.sleep(0.2)
    assert begun()
    workers = {pid for pid in _children(grid.pid) if runs.as_posix() in Path(f"/proc/{pid}/cmdline").read_text()
               or "multiprocessing" in Path(f"/proc/{pid}/cmdline").read_text()}
    assert len(workers) >= 2
    grid.send_signal(signal.SIGKILL)
    grid.wait(timeout=30)
    deadline = time.monotonic() + 20
    while any(_alive(pid) for pid in workers) and time.monotonic() < deadline:
        time.sleep(0.2)
    assert not [pid for pid in workers if _alive(pid)]
    for folder in sorted(runs.glob("00*")):  # each stopped after its update, its checkpoint whole
        assert (folder / "summary.json").is_file(), (sorted(p.name for p in folder.iterdir()), log.read_text())
        assert json.loads((folder / "summary.json").read_text())["stopped_early"] is True


@pytest.mark.skipif(not Path("/proc/self/stat").exists(), reason="lists processes through Linux's /proc")
def test_where_the_kernel_does_not_signal_a_parent_s_death_a_watcher_does(tmp_path):
    """The portable fallback of :func:`hivex_dsl.train.grid.end_with_parent` (macOS has no PR_SET_PDEATHSIG)."""
    inner = ("import os, threading, time\nfrom hivex_dsl.train.grid import _signal_when_orphaned\n"
             "threading.Thread(target=_signal_when_orphaned, args=(os.getppid(), 0.1), daemon=True).start()\n"
             "print('watching', flush=True)\ntime.sleep(120)")
    outer = subprocess.Popen([sys.executable, "-c", f"import subprocess, sys, time\nchild = subprocess.Popen([sys.executable, "
                              f"'-c', {inner!r}], stdout=sys.stdout)\nprint(child.pid, flush=True)\ntime.sleep(120)"],
                             stdout=subprocess.PIPE, text=True, env=os.environ | {"PYTHONPATH": os.getcwd()})
    child = int(outer.stdout.readline())
    assert outer.stdout.readline() == "watching\n"
    outer.send_signal(signal.SIGKILL)
    outer.wait(timeout=30)
    deadline = time.monotonic() + 10
    while _alive(child) and time.monotonic() < deadline:
        time.sleep(0.1)
    assert not _alive(child)
