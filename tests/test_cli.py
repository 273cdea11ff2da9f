"""The `hivex` command as a researcher uses it: exit codes, located errors, no tracebacks."""

from __future__ import annotations

import json
import re
import subprocess
import sys
from pathlib import Path

import pytest
from PIL import Image

from hivex_dsl.cli import main

ROOT = Path(__file__).resolve().parents[1]
MAIN = ROOT / "scenarios/wind_farm_control/main.yaml"
SUITE = ROOT / "scenarios/wind_farm_control/paper_suite.yaml"


@pytest.fixture
def short(tmp_path):
    path = tmp_path / "short.yaml"
    path.write_text("hivex: 1\nname: short\nenvironment: wind_farm_control\nagents: 3\nepisode_length: 40\n")
    return path


def test_validate_every_bundled_scenario(capsys):
    files = sorted(str(p) for p in (ROOT / "scenarios").glob("*/*.yaml"))
    assert main(["validate", *files]) == 0
    out = capsys.readouterr().out
    assert f"ok  {SUITE}  (18 scenarios)" in out
    assert out.count("ok  ") == len(files)


def test_validate_reports_located_errors_with_exit_2(tmp_path, capsys):
    bad = tmp_path / "bad.yaml"
    bad.write_text("hivex: 1\nenvironment: wind_farm_control\nagents: 40\n")
    assert main(["validate", str(bad), str(MAIN)]) == 2
    captured = capsys.readouterr()
    assert captured.err.strip() == f"{bad}:3:9: agents: 40 is out of range: expected an integer from 1 to 16"
    assert f"ok  {MAIN}" in captured.out


def test_compile_summary_names_spaces_weights_and_seeds(capsys):
    assert main(["compile", str(MAIN)]) == 0
    out = capsys.readouterr().out
    for expected in ("wind_farm_control (Wind Farm Control)", "0 generate_energy", "Box(-1.0, 1.0, (6,), float32)",
                     "Discrete(3)", "train 5000 | test 6000", "rotation_speed_deg = 0.1", "(inactive)"):
        assert expected in out


def test_compile_sweep_lists_all_18_points(capsys):
    assert main(["compile", str(SUITE)]) == 0
    out = capsys.readouterr().out
    assert "18 scenarios over pattern x task" in out
    assert out.count("generate_energy  ") >= 9


def test_lock_file_round_trip_keeps_the_fingerprint(tmp_path, capsys):
    lock = tmp_path / "main.lock.json"
    assert main(["compile", str(MAIN), "-o", str(lock)]) == 0
    first = json.loads(lock.read_text())
    assert first["scenario"]["weights"] == {"generate_energy": 1.0, "avoid_damage": 0.0}
    assert first["spaces"] == {"observation": "Box(-1.0, 1.0, (6,), float32)", "action": "Discrete(3)"}
    again = tmp_path / "again.lock.json"
    assert main(["compile", str(lock), "-o", str(again)]) == 0
    assert json.loads(again.read_text()) == first


def test_sweep_locks_go_to_a_directory(tmp_path):
    assert main(["compile", str(SUITE), "-o", str(tmp_path / "locks")]) == 0
    assert len(list((tmp_path / "locks").glob("*.lock.json"))) == 18


def test_run_prints_per_agent_returns_and_terms(short, capsys):
    assert main(["run", str(short), "--policy", "random", "--episodes", "2", "--seed", "4"]) == 0
    captured = capsys.readouterr()
    lines = captured.out.splitlines()
    assert lines[0].startswith("short: 2 episode(s), policy random")
    assert "generate_energy (x1)" in lines[1]
    assert [l.split()[0] for l in lines if l.startswith(("turbine_", "mean"))] == [
        "turbine_0", "turbine_1", "turbine_2", "mean"]
    assert "episode 2/2: 40 steps" in captured.err


SEED = "argument --seed: expected an integer from 0 to 4294967295, got"


@pytest.mark.parametrize("args, message", [
    (["run", str(MAIN), "--seed", "-1"], f"{SEED} -1"),
    (["run", str(MAIN), "--seed", "4294967296"], f"{SEED} 4294967296"),
    (["run", str(MAIN), "--episodes", "1.5"], "argument --episodes: expected a positive integer, got '1.5'"),
    (["train", str(MAIN), "--seed", "x"], f"{SEED} 'x'"),
    (["evaluate", "run/checkpoint.pt", "--seed", "-3"], f"{SEED} -3"),
    (["evaluate", "run/checkpoint.pt", "--episodes", "0"], "argument --episodes: expected a positive integer, got 0"),
])
def test_a_bad_number_on_the_command_line_is_a_usage_error_naming_it(args, message, capsys):
    # numpy raised on a negative seed (a traceback) and torch on one past 64 bits
    with pytest.raises(SystemExit) as stopped:
        main(args)
    assert stopped.value.code == 2
    assert capsys.readouterr().err.rstrip().endswith(f"error: {message}")


def test_render_refuses_a_name_that_is_not_a_gif(short, tmp_path, capsys):
    assert main(["render", str(short), "-o", str(tmp_path / "wfc.png"), "--steps", "2"]) == 2
    assert "expected a file name ending in .gif" in capsys.readouterr().err
    assert not (tmp_path / "wfc.png").exists()  # GIF bytes under a .png name would have been written


def test_render_writes_an_animated_gif(short, tmp_path):
    out = tmp_path / "wfc.gif"
    assert main(["render", str(short), "-o", str(out), "--steps", "30", "--every", "10"]) == 0
    with Image.open(out) as gif:
        assert gif.n_frames >= 2 and gif.size[0] == gif.size[1] >= 256


def test_schema_is_json_with_the_environment_bounds(capsys):
    assert main(["schema"]) == 0
    schema = json.loads(capsys.readouterr().out)
    variants = [schema["$defs"][o["$ref"].rsplit("/", 1)[-1]] for o in schema["oneOf"]]
    by_env = {v["properties"]["environment"]["const"]: v for v in variants}
    assert by_env["wind_farm_control"]["properties"]["agents"]["maximum"] == 16
    assert by_env["ocean_plastic_collection"]["properties"]["agents"]["maximum"] == 12


def test_bundled_scenarios_resolve_from_another_directory(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    assert main(["validate", "scenarios/wind_farm_control/main.yaml", "wind_farm_control/avoid_damage"]) == 0
    assert main(["list"]) == 0
    assert "wind_farm_control/main.yaml" in capsys.readouterr().out


def test_console_script_exit_code_without_traceback(tmp_path):
    bad = tmp_path / "bad.yaml"
    bad.write_text("hivex: 1\nenvironment: wind_farm_contol\n")
    result = subprocess.run([sys.executable, "-m", "hivex_dsl.cli", "validate", str(bad)],
                            capture_output=True, text=True)
    assert result.returncode == 2
    assert "Traceback" not in result.stderr
    assert result.stderr.startswith(f"{bad}:2:14: environment: unknown environment 'wind_farm_contol'; "
                                    "did you mean 'wind_farm_control'?")


def test_preview_writes_the_sample_figures(tmp_path, capsys):
    assert main(["preview", "-o", str(tmp_path / "figs")]) == 0
    written = sorted(p.name for p in (tmp_path / "figs").glob("*.png"))
    assert written == ["ocean_pollution.png", "terrain_levels.png", "wind_farm_control_layouts.png"]
    with Image.open(tmp_path / "figs" / "wind_farm_control_layouts.png") as image:
        assert image.size[0] > 300


def test_vocab_lists_every_quantity_with_its_unit_range_and_meaning(capsys):
    from hivex_dsl.compiler import registry
    from hivex_dsl.compiler import compile
    from hivex_dsl.sim.reward.vocabulary import vocabulary_of

    for env_id in registry.environments():
        assert main(["vocab", env_id, "--json"]) == 0
        rows = json.loads(capsys.readouterr().out)
        declared = vocabulary_of(env_id).quantities(compile(f"{env_id}/main"))
        assert [row["name"] for row in rows] == list(declared)
        assert all(row["meaning"] and row["low"] <= row["high"] for row in rows)
    assert main(["vocab", "wind_farm_control"]) == 0
    out = capsys.readouterr().out
    assert "  alignment                          per agent  [0, 1] 1" in out
    assert "  wind_speed                         not modelled: " in out  # the wind model has a direction only

def test_vocab_of_a_scenario_file_gives_its_own_ranges(tmp_path, capsys):
    small = tmp_path / "small.yaml"
    small.write_text("hivex: 1\nenvironment: wind_farm_control\nagents: 4\nparams: {farm_half_extent_m: 300}\n")
    assert main(["vocab", str(small)]) == 0
    assert "  x_m                                per agent  [-300, 300] m" in capsys.readouterr().out


def test_vocab_of_an_unknown_environment_names_the_environments(capsys):
    assert main(["vocab", "wind_farm_contrl"]) == 2
    assert capsys.readouterr().err.startswith("hivex: no environment or scenario file 'wind_farm_contrl'; did you mean "
                                              "'wind_farm_control'?; environments: wind_farm_control, ")


PAPER_SUITE = "scenarios/wind_farm_control/paper_suite.yaml"  # 9 patterns x 2 tasks


def test_run_of_a_sweep_asks_for_a_point_and_plays_the_one_chosen(capsys):
    """`hivex run` refused a sweep with a message naming a Python function, and no point could be picked."""
    assert main(["run", PAPER_SUITE, "--episodes", "1"]) == 2
    assert capsys.readouterr().err == (f"hivex: {PAPER_SUITE} sweeps over 18 points: choose one with --point INDEX (0 to 17) "
                                       f"or --point pattern=0,task=0; `hivex compile {PAPER_SUITE}` lists them\n")
    from hivex_dsl.compiler import compile_all

    names = [p.name for p in compile_all(PAPER_SUITE)]
    for selector in ("3", "pattern=1,task=1", " task=1 , pattern=1 "):
        point = names[3] if selector == "3" else next(n for n in names if n.endswith("[pattern=1,task=1]"))
        assert main(["run", PAPER_SUITE, "--point", selector, "--seed", "1"]) == 0
        assert capsys.readouterr().out.startswith(f"{point}: 1 episode(s)")


@pytest.mark.parametrize("selector, message", [
    ("99", "--point 99: scenarios/wind_farm_control/paper_suite.yaml has 18 points (0 to 17)"),
    ("pattern=1", "--point pattern=1: 2 points of scenarios/wind_farm_control/paper_suite.yaml match; give every "
                  "swept value (pattern, task) or the point's index"),
    ("patern=1", "--point patern=1: scenarios/wind_farm_control/paper_suite.yaml does not sweep 'patern'; did you "
                 "mean 'pattern'?; it sweeps pattern, task"),
    ("pattern", "--point pattern: expected an index or key=value pairs joined by commas, got 'pattern'"),
    # str.isdigit took these for indices 3 and 1 (issue 54, item 9): an index is written in ASCII digits
    ("\uff13", "--point \uff13: expected an index or key=value pairs joined by commas, got '\uff13'"),
    ("\u0661", "--point \u0661: expected an index or key=value pairs joined by commas, got '\u0661'"),
])
def test_a_point_that_names_no_single_point_is_refused(selector, message, capsys):
    assert main(["run", PAPER_SUITE, "--point", selector]) == 2
    assert capsys.readouterr().err == f"hivex: {message}\n"


def test_evaluate_takes_a_point_only_of_a_scenario_it_is_given(tmp_path, capsys):
    pytest.importorskip("torch")
    assert main(["evaluate", str(tmp_path / "checkpoint.pt"), "--point", "3"]) == 2
    assert capsys.readouterr().err == ("hivex: --point chooses a point of a sweep SCENARIO: give the SCENARIO after the "
                                       "CHECKPOINT\n")


def test_compile_shows_every_ending_the_expressions_too(tmp_path, capsys):
    """Three ends_on entries (an event and two expressions) were shown as the event alone."""
    scenario = tmp_path / "aws.yaml"
    scenario.write_text("hivex: 1\nenvironment: aerial_wildfire_suppression\n"
                        "ends_on: [fire_out, distance_to_village_m < 100, team_max(x_m) > 500]\n")
    assert main(["compile", str(scenario)]) == 0
    assert ("  ends on         fire_out; `distance_to_village_m < 100` (agent); `team_max(x_m) > 500` (world); "
            "the episode length\n") in capsys.readouterr().out


def test_the_help_summary_names_every_command(capsys):
    # issue 54 item 19: the summary line was written by hand and left out `vocab`
    import re

    with pytest.raises(SystemExit):
        main(["--help"])
    text = capsys.readouterr().out
    summary = re.search(r"The `hivex` command: (.*?)\.\n", text, re.S).group(1)
    listed = {name.strip() for name in summary.split("|")}
    commands = set(re.findall(r"^    (\w+)  ", text, re.M))  # argparse's list of the commands and their help
    assert {"validate", "vocab", "train", "evaluate"} <= commands and listed == commands


def test_compile_prints_every_term_with_its_range(capsys, tmp_path):
    # issue 54 item 19: the quickstart said compile prints the terms with their ranges; it printed weights only
    assert main(["compile", "aerial_wildfire_suppression/main", "-o", str(tmp_path / "lock.json")]) == 0
    printed = capsys.readouterr().out
    lock = json.loads((tmp_path / "lock.json").read_text())
    assert len(lock["scenario"]["weights"]) == len(lock["term_contracts"]) == 10
    for name in lock["scenario"]["weights"]:
        low, high = lock["term_contracts"][name]["range"]
        assert re.search(rf"^ +\S+  {name} +\[{low:g}, {high:g}\]", printed, re.M), name
