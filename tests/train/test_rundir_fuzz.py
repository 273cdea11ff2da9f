"""Run management fuzzed as a researcher running grids for days would meet it: a run directory tampered with (a
user's file at a run's name, a run file edited, truncated, deleted or replaced by a link, a folder linked elsewhere),
a run killed at any instant, two runs into one directory at once, and a run directory moved. Whatever happens, a
command either does its work or refuses with one TrainError sentence; a refusal changes nothing; no file the run did
not write is ever removed or changed, inside the directory or through a link out of it; and a run killed at any
instant leaves files its manifest recognises (`--resume` goes on, `--force` replaces). A few cases run by default,
many more with HIVEX_FUZZ_LONG=1."""

from __future__ import annotations

import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from hivex_dsl.compiler import compile
from hivex_dsl.train.config import TrainError, make_config
from hivex_dsl.train.ppo import train
from hivex_dsl.train.rundir import LOCK, META, OWNER

from .conftest import TINY, short_scenario

LONG = os.environ.get("HIVEX_FUZZ_LONG") == "1"
FUZZ_CASES = 150 if LONG else 6
KILLS = 12 if LONG else 2
ONE_UPDATE = TINY | {"buffer_size": 32, "batch_size": 32, "max_steps": 64, "checkpoint_every": 32,
                     "keep_checkpoints": 2, "hidden_units": 8}
# the command line's hyperparameters (the paper's but these): a kill's run is resumed with the same
COMMAND_SET = {"num_worlds": 1, "buffer_fill": "rollout", "buffer_size": 32, "batch_size": 32, "hidden_units": 8,
               "torch_threads": 1, "checkpoint_every": 32, "keep_checkpoints": 2}
RUN_NAMES = ("checkpoint.pt", "config.json", "curve.json", "summary.json", "evaluation.json",
             "checkpoints/step_000000000032.pt", "checkpoints/step_000000000999.pt", "tb/events.out.tfevents.1.x",
             "checkpoint.pt.partial", "summary.json.partial")
TAMPERS = ("user file", "edit", "truncate", "append", "delete", "link file", "link folder", "user note")


@pytest.fixture(scope="module")
def wfc():
    return compile(short_scenario("wind_farm_control", episode_length=16))


@pytest.fixture(scope="module")
def trained(wfc, tmp_path_factory) -> Path:
    """A finished tiny run, copied by each case."""
    folder = tmp_path_factory.mktemp("trained") / "run"
    train(wfc, make_config(wfc.environment, ONE_UPDATE), folder, progress=False)
    return folder


def snapshot(*folders: Path) -> dict[str, bytes | str]:
    """Every file's bytes and every link's target under ``folders`` (not through links), less the lock (an empty
    file that stays, as flock needs) and its owner note."""
    found: dict[str, bytes | str] = {}
    for folder in folders:
        for path in sorted(folder.rglob("*")):
            if path.is_symlink():
                found[str(path)] = f"-> {os.readlink(path)}"
            elif path.is_file() and path.relative_to(folder).as_posix() not in (OWNER, LOCK):
                found[str(path)] = path.read_bytes()
    return found


def tamper(run: Path, outside: Path, how: str, name: str, at: int, users: dict[str, bytes]) -> dict[str, bytes]:
    """Change ``run`` as ``how`` says at ``name``; -> the user's files it made (path: content), which must survive
    (``users``, those made before, are renamed where a folder they are in is moved out and linked)."""
    path = run / name
    mine = f"the user's {name} #{at}".encode()
    if how in ("user file", "user note"):
        target = run / ("notes.md" if how == "user note" else name)
        if target.exists() or target.is_symlink():
            return {}
        target.parent.mkdir(parents=True, exist_ok=True)
        target.write_bytes(mine)
        return {str(target): mine}
    if how == "link folder":
        folder = run / name.partition("/")[0] if "/" in name else run / "checkpoints"
        target = outside / folder.name
        if folder.is_symlink() or target.exists():
            return {}
        outside.mkdir(parents=True, exist_ok=True)
        if folder.exists():
            shutil.move(folder, target)
            for path in [p for p in users if Path(p).is_relative_to(folder)]:
                users[str(target / Path(path).relative_to(folder))] = users.pop(path)
        target.mkdir(parents=True, exist_ok=True)
        (target / "step_000000000777.pt").write_bytes(mine)
        folder.symlink_to(target, target_is_directory=True)
        return {str(target / "step_000000000777.pt"): mine}
    if not path.is_file():
        return {}
    # a user's own file the tamper changes again, reached by its path or through a link (its key may be either)
    real = path.resolve()
    known = [key for key in users if Path(key).resolve() == real]
    if how in ("delete", "link file") and not path.is_symlink():  # the file itself goes, not a link to it
        for key in known:
            users.pop(key)
        known = []
    if how == "edit":
        data = bytearray(path.read_bytes())
        if data:
            data[at % len(data)] ^= 0x01
        path.write_bytes(bytes(data))
    elif how == "truncate":
        path.write_bytes(path.read_bytes()[: at % max(1, path.stat().st_size)])
    elif how == "append":
        with path.open("ab") as handle:
            handle.write(mine)
    elif how == "delete":
        path.unlink()
    elif how == "link file":
        outside.mkdir(parents=True, exist_ok=True)
        (outside / "linked").write_bytes(mine)
        path.unlink()
        path.symlink_to(outside / "linked")
        return {str(outside / "linked"): mine}
    if known and how in ("edit", "truncate", "append"):
        return {key: real.read_bytes() for key in known}  # what must survive is what the user's file holds now
    return {}


@settings(max_examples=FUZZ_CASES, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture,
                                                                         HealthCheck.too_slow])
@given(changes=st.lists(st.tuples(st.sampled_from(TAMPERS), st.sampled_from(RUN_NAMES), st.integers(0, 2**16)),
                        min_size=1, max_size=3),
       mode=st.sampled_from(["resume", "force", "neither"]))
def test_a_tampered_run_directory_is_worked_in_or_refused_and_no_user_file_is_lost(changes, mode, wfc, trained,
                                                                                  tmp_path_factory):
    case = tmp_path_factory.mktemp("case")
    run, outside = case / "run", case / "outside"
    shutil.copytree(trained, run, symlinks=True)
    users: dict[str, bytes] = {}
    for how, name, at in changes:
        users |= tamper(run, outside, how, name, at, users)
    before = snapshot(run, outside) if outside.exists() else snapshot(run)
    cfg = make_config(wfc.environment, ONE_UPDATE | {"max_steps": 96 if mode == "resume" else 64})
    try:
        train(wfc, cfg, run, progress=False, resume=mode == "resume", overwrite=mode == "force")
    except TrainError as exc:
        assert "\n" not in str(exc)
        assert (snapshot(run, outside) if outside.exists() else snapshot(run)) == before  # a refusal changes nothing
    for path, content in users.items():
        assert Path(path).read_bytes() == content, path


def _train_command(run: Path, *more: str) -> list[str]:
    scenario = run.parent / "wfc.yaml"
    if not scenario.exists():
        import json

        scenario.write_text(json.dumps(short_scenario("wind_farm_control", episode_length=16)))
    settings = [part for key, value in COMMAND_SET.items() for part in ("--set", f"{key}={value}")]
    return [sys.executable, "-m", "hivex_dsl.cli", "train", str(scenario), "-o", str(run), "--no-progress",
            *settings, *more]


def _start(command: list[str]) -> subprocess.Popen:
    return subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            env=os.environ | {"PYTHONPATH": os.getcwd()})


def _wait_for(predicate, process: subprocess.Popen, seconds: float = 120) -> None:
    deadline = time.monotonic() + seconds
    while not predicate() and time.monotonic() < deadline and process.poll() is None:
        time.sleep(0.05)
    assert predicate(), process.communicate()


@pytest.mark.parametrize("kill", range(KILLS))
def test_a_run_killed_at_any_instant_leaves_files_its_manifest_recognises(kill, wfc, tmp_path):
    """SIGKILL after a random number of checkpoints and a random delay (seeded by the case): the run's own files
    are never taken for a user's, so --resume goes on from the checkpoint (or says there is none), and --force
    replaces the run, whatever instant the kill cut."""
    import random

    rng = random.Random(kill)
    run = tmp_path / "run"
    process = _start(_train_command(run, "--steps", "100000000"))
    saves = rng.randint(1, 4)
    _wait_for(lambda: len(list(run.glob("checkpoints/step_*.pt"))) >= min(saves, 2) and (run / "checkpoint.pt").exists(),
              process)
    time.sleep(rng.uniform(0.0, 0.3))
    process.send_signal(signal.SIGKILL)
    process.wait(timeout=30)
    outside = snapshot(run)
    try:
        steps = train(wfc, make_config(wfc.environment, COMMAND_SET | {"max_steps": 32}), run, progress=False,
                      resume=True)
        assert steps["agent_steps"] >= 32
    except TrainError as exc:  # only where no checkpoint was whole yet: never a file of its own refused
        assert str(exc).startswith("cannot resume: no checkpoint"), (str(exc), sorted(outside))
    assert train(wfc, make_config(wfc.environment, ONE_UPDATE), run, progress=False, overwrite=True)["agent_steps"] == 64
    assert not list(run.rglob("*.partial"))


def test_two_runs_into_one_directory_at_once_one_trains_and_the_other_is_refused(tmp_path):
    run = tmp_path / "run"
    first, second = (_start(_train_command(run, "--steps", "100000000")) for _ in range(2))
    _wait_for(lambda: first.poll() is not None or second.poll() is not None, first)
    refused, training = (first, second) if first.poll() is not None else (second, first)
    out, err = refused.communicate(timeout=30)
    assert refused.returncode == 2 and f"another hivex is writing to {run}" in err, err
    _wait_for(lambda: (run / "checkpoint.pt").exists(), training)
    training.send_signal(signal.SIGTERM)  # stops after its update, keeps its checkpoint
    training.communicate(timeout=60)
    assert len(list((run / "tb").glob("events.out.tfevents.*"))) == 1  # one run's scalars


def test_a_moved_run_directory_goes_on_where_it_is(wfc, trained, tmp_path):
    """The manifest names the run's files relative to its directory: moved (or copied) whole, the run goes on."""
    moved = tmp_path / "elsewhere" / "run"
    shutil.copytree(trained, moved, symlinks=True)
    summary = train(wfc, make_config(wfc.environment, ONE_UPDATE | {"max_steps": 96}), moved, progress=False,
                    resume=True)
    assert summary["agent_steps"] == 96 and summary["resumed_at"] == [64]
    assert not (tmp_path / "elsewhere" / "run" / META / "manifest.json").read_text().count(str(trained))
