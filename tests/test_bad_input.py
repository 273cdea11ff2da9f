"""Bad input outside the scenario text itself: oversized and endless input, output paths, closed pipes,
edited lock files and environments used out of order. Each ends in the toolkit's own located error."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import threading
import tracemalloc
from pathlib import Path

import numpy as np
import pytest

import hivex_dsl
from hivex_dsl import ResetNeeded, ScenarioError
from hivex_dsl.cli import EXIT_PIPE, main
from hivex_dsl.base.errors import is_integer
from hivex_dsl.lang.loader import MAX_FILE_BYTES, load_file

ROOT = Path(__file__).resolve().parents[1]
MAIN = ROOT / "scenarios" / "wind_farm_control" / "main.yaml"
SUITE = ROOT / "scenarios" / "wind_farm_control" / "paper_suite.yaml"
HIVEX = Path(sys.executable).with_name("hivex")


def refusal_of(path) -> tuple[str, int]:
    """(message, peak bytes allocated by Python) of refusing ``path``."""
    tracemalloc.start()
    try:
        with pytest.raises(ScenarioError) as caught:
            load_file(path)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    [problem] = caught.value.problems
    assert (problem.location.line, problem.location.col) == (1, 1)
    return problem.message, peak


# --- memory and time are bounded before reading whole ------------------------------------------------


def test_a_huge_sparse_file_is_refused_by_its_size_without_reading_it(tmp_path):
    path = tmp_path / "huge.yaml"
    with open(path, "wb") as f:
        f.truncate(3 * 1024 ** 3)  # 3 GiB of holes: costs no disk
    message, peak = refusal_of(path)
    assert message == f"file is {3 * 1024 ** 3:,} bytes; a scenario may be at most {MAX_FILE_BYTES:,} bytes"
    assert peak < 1_000_000  # nothing of it was read


def test_a_file_one_byte_over_the_limit_is_refused_and_one_at_the_limit_is_read(tmp_path):
    over = tmp_path / "over.yaml"
    over.write_bytes(b"#" * (MAX_FILE_BYTES + 1))
    assert refusal_of(over)[0].startswith(f"file is {MAX_FILE_BYTES + 1:,} bytes")
    at = tmp_path / "at.yaml"
    at.write_bytes(b"a: 1\n" + b"#" * (MAX_FILE_BYTES - 5))
    assert load_file(at).data == {"a": 1}


@pytest.mark.skipif(not Path("/dev/zero").exists(), reason="needs /dev/zero")
def test_an_endless_device_is_read_no_further_than_the_limit():
    message, peak = refusal_of("/dev/zero")
    assert message == f"input is longer than {MAX_FILE_BYTES:,} bytes, the most a scenario may be"
    assert peak < 4 * MAX_FILE_BYTES


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="needs named pipes")
def test_an_endless_stream_through_a_pipe_is_cut_at_the_limit(tmp_path):
    fifo = tmp_path / "endless.yaml"
    os.mkfifo(fifo)
    written = []

    def write_forever():
        chunk = b"a: 1\n" * 1000
        try:
            with open(fifo, "wb") as stream:
                while True:
                    stream.write(chunk)
                    written.append(len(chunk))
        except (BrokenPipeError, OSError):  # the reader stopped: what an endless writer sees
            pass

    writer = threading.Thread(target=write_forever, daemon=True)
    writer.start()
    message, _ = refusal_of(fifo)
    writer.join(timeout=10)
    assert message == f"input is longer than {MAX_FILE_BYTES:,} bytes, the most a scenario may be"
    assert not writer.is_alive()


def test_validate_reads_a_scenario_from_standard_input():
    result = subprocess.run([str(HIVEX), "validate", "/dev/stdin"], input=MAIN.read_bytes(), capture_output=True,
                            timeout=120)
    assert result.returncode == 0, result.stderr
    assert result.stdout.decode().startswith("ok  /dev/stdin  (1 scenario)")


# --- output paths and pipes of the CLI ---------------------------------------------------------------


@pytest.mark.parametrize("make, target, expected", [
    (None, "missing/main.lock.json", "-o {out}: the directory {parent} does not exist"),
    ("dir", "out", "-o {out} is a directory; give the lock file's name (a directory is for a sweep)"),
])
def test_a_single_lock_needs_a_file_in_an_existing_directory(tmp_path, capsys, make, target, expected):
    out = tmp_path / target
    if make == "dir":
        out.mkdir()
    assert main(["compile", str(MAIN), "-o", str(out)]) == 2
    captured = capsys.readouterr()
    assert captured.out == ""  # checked before anything is printed
    assert captured.err == "hivex: " + expected.format(out=out, parent=out.parent) + "\n"


def test_a_sweep_needs_a_directory_free_of_other_locks(tmp_path, capsys):
    file = tmp_path / "locks.json"
    file.write_text("{}")
    assert main(["compile", str(SUITE), "-o", str(file)]) == 2
    assert capsys.readouterr().err == (f"hivex: -o {file} is a file; a sweep of 18 scenarios writes one lock per point "
                                       "into a directory\n")
    stale = tmp_path / "locks" / "0099.lock.json"
    stale.parent.mkdir()
    stale.write_text("{}")
    assert main(["compile", str(SUITE), "-o", str(stale.parent)]) == 2
    assert "holds lock files this sweep would not overwrite (0099.lock.json, ...)" in capsys.readouterr().err
    assert sorted(p.name for p in stale.parent.iterdir()) == ["0099.lock.json"]  # nothing written


def test_an_output_the_system_refuses_is_reported_without_a_traceback(tmp_path, capsys):
    locked = tmp_path / "ro"
    locked.mkdir()
    locked.chmod(0o500)
    try:
        if os.access(locked, os.W_OK):
            pytest.skip("running as a user who may write anywhere")
        assert main(["compile", str(MAIN), "-o", str(locked / "x.json")]) == 1
    finally:
        locked.chmod(0o700)
    assert capsys.readouterr().err == f"hivex: Permission denied: {locked / 'x.json'}\n"


@pytest.mark.skipif(not Path("/proc/self").is_dir(), reason="needs Linux's /proc, where no file may be created")
def test_an_output_the_system_refuses_is_reported_even_as_root(capsys):
    assert main(["compile", str(MAIN), "-o", "/proc/hivex.lock.json"]) == 1
    captured = capsys.readouterr()
    assert captured.err == "hivex: No such file or directory: /proc/hivex.lock.json\n"


class _ClosedPipe:
    def write(self, text):
        raise BrokenPipeError(32, "Broken pipe")

    def flush(self):
        raise BrokenPipeError(32, "Broken pipe")


def test_a_closed_pipe_ends_the_command_quietly(monkeypatch, capsys):
    monkeypatch.setattr(sys, "stdout", _ClosedPipe())
    assert main(["compile", str(SUITE)]) == EXIT_PIPE
    assert capsys.readouterr().err == ""


def test_a_reader_that_goes_away_gets_no_traceback():
    # `true` exits at once, long before Python has started, so the first write meets a closed pipe
    result = subprocess.run(f"'{HIVEX}' compile '{SUITE}' | true; exit ${{PIPESTATUS[0]}}", shell=True,
                            executable="/bin/bash", capture_output=True, timeout=120)
    assert (result.returncode, result.stderr) == (EXIT_PIPE, b"")
    result = subprocess.run(f"'{HIVEX}' schema | head -1", shell=True, executable="/bin/bash",
                            capture_output=True, timeout=120)
    assert (result.stdout, result.stderr) == (b"{\n", b"")


# --- lock files --------------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def sweep_lock():
    point = hivex_dsl.compile_all(SUITE)[3]
    return point, point.to_lock()


def _problems_of_lock(tmp_path, lock) -> tuple[str, list]:
    text = json.dumps(lock, indent=2)
    path = tmp_path / "edited.lock.json"
    path.write_text(text)
    with pytest.raises(ScenarioError) as caught:
        hivex_dsl.compile_all(path)
    return text, list(caught.value.problems)


def _line_of(text: str, key: str) -> int:
    return next(i for i, line in enumerate(text.split("\n"), 1) if line.startswith(f'  "{key}": '))


@pytest.mark.parametrize("key, edit", [
    ("task_index", lambda lock: lock.update(task_index=0)),
    ("ends_on", lambda lock: lock.update(ends_on=["collision"])),
    ("spaces", lambda lock: lock["spaces"].update(action="Discrete(4)")),
    ("term_contracts", lambda lock: lock["term_contracts"]["avoid_damage"].update(range=[0.0, 2.0])),
])
def test_every_derived_field_of_a_lock_is_verified(tmp_path, sweep_lock, key, edit):
    lock = json.loads(json.dumps(sweep_lock[1]))
    edit(lock)
    text, [problem] = _problems_of_lock(tmp_path, lock)
    assert problem.location.line == _line_of(text, key)
    assert problem.message.startswith(f"{key}: the stored value does not match what the scenario compiles to (")


def test_a_lock_keeps_its_sweep_point_and_an_edited_one_is_refused(tmp_path, sweep_lock):
    point, lock = sweep_lock
    assert lock["sweep_point"] == {"pattern": 1, "task": 1}
    path = tmp_path / "point.lock.json"
    path.write_text(json.dumps(lock))
    [again] = hivex_dsl.compile_all(path)
    assert dict(again.sweep_point) == {"pattern": 1, "task": 1} and again.name == point.name
    assert again.to_lock() == lock  # re-locking a sweep point loses nothing

    lock = json.loads(json.dumps(lock))
    lock["sweep_point"]["task"] = 0
    lock["scenario"]["name"] = lock["scenario"]["name"].replace("task=1", "task=0")
    text, [problem] = _problems_of_lock(tmp_path, lock)
    assert problem.message.startswith("sweep_point.task: 0 is not the locked scenario's value")
    assert problem.location.line == text.split("\n").index('    "task": 0') + 1


def test_an_emptied_sweep_point_is_refused(tmp_path, sweep_lock):
    lock = json.loads(json.dumps(sweep_lock[1]))
    lock["sweep_point"] = {}
    text, [problem] = _problems_of_lock(tmp_path, lock)
    assert problem.message.startswith("sweep_point: {} but the scenario's name 'wfc-paper[pattern=1,task=1]' "
                                      "ends with a sweep point")
    assert problem.location.line == _line_of(text, "sweep_point")


def test_a_sweep_inserted_into_a_lock_is_refused(tmp_path, sweep_lock):
    lock = json.loads(json.dumps(sweep_lock[1]))
    lock["scenario"]["sweep"] = {"agents": [1, 2]}
    text, [problem] = _problems_of_lock(tmp_path, lock)
    assert problem.message.startswith("a lock holds one resolved scenario; 'sweep' is not allowed in it")
    assert problem.location.line == text.split("\n").index('    "sweep": {') + 1


def test_a_lock_missing_a_field_is_refused(tmp_path, sweep_lock):
    lock = {k: v for k, v in sweep_lock[1].items() if k != "spaces"}
    _, [problem] = _problems_of_lock(tmp_path, lock)
    assert problem.message.startswith("missing required key 'spaces' in a lock file")


# --- environments used out of order ------------------------------------------------------------------


def test_stepping_before_reset_says_so():
    env = hivex_dsl.parallel_env(MAIN)
    with pytest.raises(ResetNeeded, match=r"call reset\(\) before step\(\): the environment has not been reset yet"):
        env.step({a: 0 for a in env.possible_agents})
    venv = hivex_dsl.vector_env(MAIN, num_worlds=1)
    with pytest.raises(ResetNeeded, match="has not been reset yet"):
        venv.step(np.zeros(venv.num_envs, np.int64))
    assert issubclass(ResetNeeded, hivex_dsl.HivexError) and issubclass(ResetNeeded, RuntimeError)


@pytest.mark.parametrize("seed", [-1, "7", True, 2.0])
def test_a_seed_that_is_not_a_non_negative_integer_is_named(seed):
    # numpy said 'expected non-negative integer' (or a TypeError about SeedSequence) from deep inside reset
    with pytest.raises(ValueError) as refused:
        hivex_dsl.parallel_env(MAIN).reset(seed=seed)
    assert str(refused.value) == f"seed must be a non-negative integer or None, got {seed!r}"
    assert hivex_dsl.parallel_env(MAIN).reset(seed=np.int64(7))[0]  # numpy's integers are integers


@pytest.mark.parametrize("worlds", [0, -2, 2.0])
def test_a_vector_env_of_no_worlds_names_the_argument(worlds):
    with pytest.raises(ValueError, match=rf"^num_worlds \(make_vec's num_envs: copies of the world\) must be an "
                                         rf"integer >= 1, got {worlds!r}$"):
        hivex_dsl.vector_env(MAIN, num_worlds=worlds)


@pytest.mark.parametrize("value, integer", [(3, True), (np.int64(3), True), (np.uint8(0), True), (-1, True),
                                            (True, False), (np.bool_(True), False), (3.0, False), ("3", False),
                                            (None, False)])
def test_every_integer_argument_check_counts_numpy_integers_and_not_bools(value, integer):
    # one predicate behind seeds, num_worlds, levels, layout patterns, canvas sizes and GIF loops
    assert is_integer(value) is integer


# --- the README's promises ---------------------------------------------------------------------------


def test_the_readme_error_examples_are_what_validate_prints(tmp_path, capsys):
    readme = (ROOT / "README.md").read_text()
    shown = [line.strip() for line in readme.splitlines() if line.strip().startswith("scenario.yaml:")]
    assert len(shown) == 2
    path = tmp_path / "scenario.yaml"
    path.write_text("hivex: 1\nname: x\nenvironment: wind_farm_control\ntask: 0\npattern: 0\nagents: 40\n"
                    "episode_length: 100\nparams:\n  rotaton_speed_deg: 2\n")
    assert main(["validate", str(path)]) == 2
    printed = [line.replace(str(path), "scenario.yaml") for line in capsys.readouterr().err.splitlines()]
    assert printed[0] == shown[0]
    assert shown[1].endswith(" ...") and printed[1].startswith(shown[1][:-4])


@pytest.mark.parametrize("written, reading", [("0123", "octal number 83"), ("1:30", "base-60 number (90)"),
                                               ("yes", "boolean true"), ("off", "boolean false"),
                                               ("1_000_", "1000")])
def test_the_readme_yaml_1_1_readings_are_refused_as_it_says(written, reading):
    assert f"`{written}`" in (ROOT / "README.md").read_text()
    with pytest.raises(ScenarioError) as caught:
        hivex_dsl.compile_all(hivex_dsl.lang.loader.load_text(f"hivex: 1\nenvironment: wind_farm_control\n"
                                                         f"episode_length: {written}\n", "s.yaml").data)
    assert f"{written} is read by YAML 1.1 as" in str(caught.value) or "leading zero" in str(caught.value)
    assert reading in str(caught.value)


@pytest.mark.parametrize("source", [None, "", 12, b"main.yaml"])
def test_a_source_that_is_neither_a_path_nor_a_dict_is_named(source):
    with pytest.raises(ScenarioError) as caught:
        hivex_dsl.compile_all(source)
    assert str(caught.value) == f"<input>:1:1: expected a scenario file path or dict, got {source!r}"


def test_a_lock_may_be_renamed_since_the_name_is_a_label(tmp_path):
    lock = hivex_dsl.compile(MAIN).to_lock()
    lock["scenario"]["name"] = "renamed"
    path = tmp_path / "renamed.lock.json"
    path.write_text(json.dumps(lock))
    [again] = hivex_dsl.compile_all(path)
    assert again.name == "renamed" and again.fingerprint == lock["fingerprint"]


def test_a_message_never_hides_a_character():
    with pytest.raises(ScenarioError) as caught:
        hivex_dsl.compile({"hivex": 1, "environment": "wind_farm_control", "a\u200bgents": 4})
    message = caught.value.problems[0].message
    assert message.startswith("unknown key 'a\\u200bgents'; did you mean 'agents'?") and message.isprintable()


def test_finding_the_cause_of_a_problem_is_bounded_over_a_whole_sweep(monkeypatch):
    from hivex_dsl.compiler import scenario as compiler

    calls = []
    validated = compiler._validated
    monkeypatch.setattr(compiler, "_validated", lambda *a: calls.append(1) or validated(*a))
    monkeypatch.setattr(compiler, "MAX_BLAME_TRIALS", 10)
    spacings = list(range(450, 550))
    with pytest.raises(ScenarioError) as caught:
        hivex_dsl.compile_all({"hivex": 1, "environment": "wind_farm_control", "params": {"drag": 0.2},
                               "sweep": {"params.turbine_spacing_m": spacings}})
    assert len(caught.value.problems) == len(spacings)
    assert len(calls) <= len(spacings) + 10
