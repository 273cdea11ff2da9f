"""A trained sweep becomes committed data (grids/<environment>.json), and the baselines page shows every point."""

from __future__ import annotations

import json
import shutil

import pytest
import yaml

from hivex_dsl.compiler import compile_all
from hivex_dsl.docsgen import render_docs
from hivex_dsl.train.baselines import record_grid
from hivex_dsl.train.config import TrainError, make_config
from hivex_dsl.train.evaluate import evaluate
from hivex_dsl.train.grid import run_grid

from .conftest import TINY, record_baseline_script, short_scenario

pytest.importorskip("matplotlib")

# The paper's Generate Energy return on patterns 0 (Default) and 1 (Grid), read by hand from its results table.
PUBLISHED = [(4611.6462, 39.952), (4605.9093, 44.3819)]


def _sweep(patterns: list[int], episode_length: int = 12) -> dict:
    sweep = short_scenario("wind_farm_control", episode_length) | {"sweep": {"pattern": patterns}}
    del sweep["pattern"]
    return sweep


pytestmark = pytest.mark.usefixtures("as_if_reproduced")

@pytest.fixture(scope="module")
def grid(tmp_path_factory):
    root = tmp_path_factory.mktemp("grid")
    sweep = root / "sweep.yaml"
    sweep.write_text(yaml.safe_dump(_sweep([0, 1])))
    points = compile_all(sweep)
    configs = [make_config("wind_farm_control", TINY | {"max_steps": 96}) for _ in points]
    run_grid(points, configs, root / "runs", eval_episodes=2, progress=False)
    return root


def test_every_point_is_recorded_beside_its_published_cell(grid):
    out = grid / "baselines"
    data = record_grid(grid / "runs", str(grid / "sweep.yaml"), out, episodes=2, command="hivex train sweep.yaml")
    assert json.loads((out / "grids" / "wind_farm_control.json").read_text()) == data
    assert [(p["task_index"], p["level"]) for p in data["points"]] == [(0, 0), (0, 1)]
    for point, (mean, std), folder in zip(data["points"], PUBLISHED, sorted((grid / "runs").glob("0*"))):
        assert point["published"]["return"] == pytest.approx({"mean": mean, "std": std})
        # the grid's own two-episode evaluation is the one recorded
        assert point["return"] == json.loads((folder / "evaluation.json").read_text())["return"]
        assert point["agent_steps"] >= 96 and point["seed"] == 0
        curve = json.loads((folder / "curve.json").read_text())  # its training curve, kept as a record keeps one
        assert [row[0] for row in point["curve"]] == [p["agent_steps"] for p in curve] and curve
        assert [row[2] for row in point["curve"]] == [round(p["return"], 4) for p in curve]
        assert point["curve_panels"]["Episode Length"] == [round(p["length"], 4) for p in curve]
        # all-scripted turbines face the wind: on every layout they beat uniformly random ones on the same episodes
        assert point["scripted"]["mean"] > point["random"]["mean"]
    assert data["test"] == {"seed": 6000, "episodes": 2, "actions": "sampled"}
    assert data["hyperparameters"]["max_steps"] == 96


def test_another_episode_count_is_evaluated_afresh(grid):
    data = record_grid(grid / "runs", str(grid / "sweep.yaml"), grid / "fresh", episodes=1)
    folder = sorted((grid / "runs").glob("001-*"))[0]
    assert data["points"][1]["return"] == evaluate(folder / "checkpoint.pt", split="test", episodes=1)["return"]
    assert data["test"]["episodes"] == 1


def test_only_the_sweep_the_grid_trained_is_recorded(grid, tmp_path):
    edited = tmp_path / "edited.yaml"  # the same point names, other episodes
    edited.write_text(yaml.safe_dump(_sweep([0, 1], episode_length=13)))
    with pytest.raises(TrainError, match=r"trained another scenario than 'wfc-main\[pattern=0\]', point 0 of"):
        record_grid(grid / "runs", str(edited), tmp_path / "out")
    other = tmp_path / "other.yaml"
    other.write_text(yaml.safe_dump(_sweep([0, 2])))
    with pytest.raises(TrainError, match=r"has no trained point 1 of .*other.yaml \(no .*001-wfc-main_pattern=2/"):
        record_grid(grid / "runs", str(other), tmp_path / "out")
    assert not (tmp_path / "out").exists()  # nothing half-written


def _edited_copy(grid, tmp_path, name: str, edit) -> None:
    """A copy of the grid's runs at tmp_path/runs with point 1's ``name`` (a JSON file) edited by ``edit``."""
    shutil.copytree(grid / "runs", tmp_path / "runs")
    path = next((tmp_path / "runs").glob("001-*")) / name
    written = json.loads(path.read_text())
    edit(written)
    path.write_text(json.dumps(written))


def test_a_grid_of_mixed_hyperparameters_is_refused(grid, tmp_path):
    _edited_copy(grid, tmp_path, "config.json", lambda c: c["hyperparameters"].update(learning_rate=0.1))
    with pytest.raises(TrainError, match=r"trained with different hyperparameters \(learning_rate\)"):
        record_grid(tmp_path / "runs", str(grid / "sweep.yaml"), tmp_path / "out", episodes=2)


def test_a_point_stopped_before_its_end_is_refused(grid, tmp_path):
    _edited_copy(grid, tmp_path, "summary.json", lambda s: s.update(stopped_early=True))
    with pytest.raises(TrainError, match=r"^point 1 of .*sweep.yaml \(.*001-wfc-main_pattern=1\) did not train to its "
                                         r"end: run the grid's `hivex train` command again with --resume$"):
        record_grid(tmp_path / "runs", str(grid / "sweep.yaml"), tmp_path / "out", episodes=2)


def test_the_page_sets_every_point_beside_the_paper(grid, tmp_path):
    data = record_grid(grid / "runs", str(grid / "sweep.yaml"), tmp_path, episodes=2, note="A grid note.")
    # hand-set returns: 4,600 is within pattern 0's published 4,611.65 ± 39.95; 4,700 is 94 over pattern 1's
    # 4,605.91 ± 44.38, so above it
    data["points"][0]["return"] = {"mean": 4600.0, "std": 10.0}
    data["points"][1]["return"] = {"mean": 4700.0, "std": 12.5}
    data["points"][1]["random"], data["points"][1]["scripted"] = {"mean": 1200.0, "std": 5.0}, {"mean": 4900.0, "std": 1.0}
    (tmp_path / "grids" / "wind_farm_control.json").write_text(json.dumps(data))
    page = render_docs(None, baselines=tmp_path)["baselines.md"]
    assert "a last section per\nenvironment sets every point beside its published cell." in page
    assert "## `wind_farm_control`: every task and level" in page
    assert "| 0 `generate_energy` | 0 default | 4,600.00 ± 10.00 | 4,611.65 ± 39.95 | matches (within the summary points' spread) |" in page
    assert ("| 0 `generate_energy` | 1 grid | 4,700.00 ± 12.50 | 4,605.91 ± 44.38 | above | 1,200.00 ± 5.00 "
            "| 4,900.00 ± 1.00 |") in page
    assert "Of the 2 points, 1 match the published return within its\nsummary points' spread, 1 are above it and 0 below." in page
    assert "A grid note." in page
    without = tmp_path / "without"
    without.mkdir()
    page = render_docs(None, baselines=without)["baselines.md"]
    assert "every task and level" not in page and "a last section" not in page


def test_the_script_reports_a_grid_it_cannot_record_without_a_traceback(grid, monkeypatch, capsys, tmp_path):
    import sys

    script = record_baseline_script()
    monkeypatch.setattr(script, "OUT", tmp_path)
    monkeypatch.setattr(sys, "argv", ["record_baseline.py", "--grid", str(tmp_path / "none"), str(grid / "sweep.yaml")])
    with pytest.raises(SystemExit) as exit_:
        script.main()
    assert exit_.value.code == 2
    assert capsys.readouterr().err == (f"error: {tmp_path / 'none'} has no trained point 0 of {grid / 'sweep.yaml'} "
                                       f"(no {tmp_path / 'none' / '000-wfc-main_pattern=0' / 'checkpoint.pt'})\n")
    monkeypatch.setattr(sys, "argv", ["record_baseline.py", "--grid", str(grid / "runs"), str(grid / "sweep.yaml"),
                                      "--episodes", "2"])
    script.main()
    assert capsys.readouterr().out == f"wrote {tmp_path / 'grids' / 'wind_farm_control'}.json: 2 points\n"


def test_a_grid_still_training_is_recorded_in_part_and_says_so(grid, tmp_path):
    """--partial: point 1 stopped before its end is listed as not trained yet, point 0 is recorded as in a whole
    grid; without --partial the same grid is refused, and a grid with no trained point is refused either way."""
    _edited_copy(grid, tmp_path, "summary.json", lambda s: s.update(stopped_early=True))
    whole = record_grid(grid / "runs", str(grid / "sweep.yaml"), tmp_path / "whole", episodes=2)
    part = record_grid(tmp_path / "runs", str(grid / "sweep.yaml"), tmp_path / "out", episodes=2, partial=True)
    assert part["untrained"] == ["wfc-main[pattern=1]"] and whole["untrained"] == []
    assert part["points"] == whole["points"][:1]
    page = render_docs(None, baselines=tmp_path / "out")["baselines.md"]
    assert "## `wind_farm_control`: every task and level (1 of 2 trained so far)" in page
    assert "and 1 are\nnot trained yet (`wfc-main[pattern=1]`)." in page
    assert "Of the 1 points, " in page
    with pytest.raises(TrainError, match="did not train to its end"):
        record_grid(tmp_path / "runs", str(grid / "sweep.yaml"), tmp_path / "out", episodes=2)
    shutil.rmtree(next((tmp_path / "runs").glob("000-*")))
    with pytest.raises(TrainError, match=r"has no point of .*sweep.yaml trained to its end yet: nothing to record$"):
        record_grid(tmp_path / "runs", str(grid / "sweep.yaml"), tmp_path / "empty", episodes=2, partial=True)


def test_the_script_records_a_grid_in_part_only_when_asked(grid, monkeypatch, capsys, tmp_path):
    import sys

    script = record_baseline_script()
    monkeypatch.setattr(script, "OUT", tmp_path / "out")
    _edited_copy(grid, tmp_path, "summary.json", lambda s: s.update(stopped_early=True))
    base = ["record_baseline.py", "--grid", str(tmp_path / "runs"), str(grid / "sweep.yaml"), "--episodes", "2"]
    monkeypatch.setattr(sys, "argv", base + ["--partial"])
    script.main()
    assert capsys.readouterr().out == (f"wrote {tmp_path / 'out' / 'grids' / 'wind_farm_control'}.json: 1 points, "
                                       "1 not trained yet\n")
    monkeypatch.setattr(sys, "argv", ["record_baseline.py", str(tmp_path / "runs"), str(grid / "sweep.yaml"),
                                      "--partial"])
    with pytest.raises(SystemExit) as exit_:
        script.main()
    assert exit_.value.code == 2
    assert "--partial records a grid still training: it goes with --grid" in capsys.readouterr().err


def test_a_grid_trained_in_parts_keeps_the_points_recorded_before(grid, tmp_path):
    """Point 0 recorded, its run gone (another machine, an earlier session): recording point 1 keeps point 0's
    row as it was, and the record is the one a whole grid gives."""
    whole = record_grid(grid / "runs", str(grid / "sweep.yaml"), tmp_path / "whole", episodes=2)
    assert [row["fingerprint"] for row in whole["points"]] == [p.fingerprint for p in compile_all(grid / "sweep.yaml")]
    shutil.copytree(grid / "runs", tmp_path / "runs")
    point_0, point_1 = sorted((tmp_path / "runs").glob("00*"))
    shutil.move(point_1, tmp_path / "later")
    first = record_grid(tmp_path / "runs", str(grid / "sweep.yaml"), tmp_path / "out", episodes=2, partial=True)
    assert first["untrained"] == ["wfc-main[pattern=1]"]
    shutil.rmtree(point_0)
    shutil.move(tmp_path / "later", point_1)
    both = record_grid(tmp_path / "runs", str(grid / "sweep.yaml"), tmp_path / "out", episodes=2)
    assert both["points"] == whole["points"] and both["untrained"] == []
    assert both["test"] == whole["test"] and both["hyperparameters"] == whole["hyperparameters"]


def test_re_recording_a_grid_keeps_the_note_and_command_written_for_it(grid, tmp_path):
    """Session 63: recording the WRM grid's second part without --note emptied the record's hand-written note.
    Not given, the note and command are the record's own (of the same sweep); given, even empty, they are what is
    given; a record of another sweep, replaced, leaves no words behind."""
    record_grid(grid / "runs", str(grid / "sweep.yaml"), tmp_path, episodes=2, command="hivex train a", note="Part 1.")
    again = record_grid(grid / "runs", str(grid / "sweep.yaml"), tmp_path, episodes=2)
    assert (again["command"], again["note"]) == ("hivex train a", "Part 1.")
    assert record_grid(grid / "runs", str(grid / "sweep.yaml"), tmp_path, episodes=2, note="Both.")["note"] == "Both."
    assert record_grid(grid / "runs", str(grid / "sweep.yaml"), tmp_path, episodes=2, command="")["command"] == ""
    _record_with(tmp_path, lambda d: d.update(sweep_fingerprint="sha256:0"))
    fresh = record_grid(grid / "runs", str(grid / "sweep.yaml"), tmp_path, episodes=2, replace=True)
    assert (fresh["command"], fresh["note"]) == ("", "")


def test_a_grid_trained_in_parts_names_the_machine_of_every_part(grid, tmp_path):
    """Point 0 recorded from an earlier machine's record, from before rows named their machines (its record's
    machine stands for it); point 1 trained here: each row names its own, and the record both, in the points'
    order, so a reader knows which points reproduce on which processor."""
    from hivex_dsl.train.devices import machine

    shutil.copytree(grid / "runs", tmp_path / "runs")
    point_0, point_1 = sorted((tmp_path / "runs").glob("00*"))
    shutil.move(point_1, tmp_path / "later")
    first = record_grid(tmp_path / "runs", str(grid / "sweep.yaml"), tmp_path / "out", episodes=2, partial=True)
    assert first["machine"] == machine() and first["points"][0]["machines"] == [machine()]

    def as_of_an_older_machine(data):
        data["machine"] = "an older machine"
        del data["points"][0]["machines"]

    _record_with(tmp_path / "out", as_of_an_older_machine)
    shutil.rmtree(point_0)
    shutil.move(tmp_path / "later", point_1)
    both = record_grid(tmp_path / "runs", str(grid / "sweep.yaml"), tmp_path / "out", episodes=2)
    assert [row["machines"] for row in both["points"]] == [["an older machine"], [machine()]]
    assert both["machine"] == f"an older machine; {machine()}"


def _record_with(out, edit) -> None:
    path = out / "grids" / "wind_farm_control.json"
    data = json.loads(path.read_text())
    edit(data)
    path.write_text(json.dumps(data))


@pytest.mark.parametrize("edit, said", [
    (lambda d: d["points"][0].update(fingerprint="sha256:0"),
     r"records point 0 \('wfc-main\[pattern=0\]'\) of another scenario \(fingerprint sha256:0, the sweep's point "
     r"now sha256:[0-9a-f]{64}\): train it again, or move the record aside$"),
    (lambda d: d["points"][0].pop("fingerprint"), r"of another scenario \(fingerprint None,"),
    (lambda d: d["test"].update(episodes=3),
     r"on 3 test episodes, not 2: record with --episodes 3, or train it again$"),
    (lambda d: d["hyperparameters"].update(gamma=0.5),
     r"trained with different hyperparameters \(gamma\): a grid record holds one set$"),
])
def test_a_point_recorded_before_is_kept_only_if_it_is_of_this_grid(grid, tmp_path, edit, said):
    """A row kept from the record must be of the sweep's point as it is now, with the grid's hyperparameters and
    test episodes; otherwise the record is refused, and left as it was."""
    record_grid(grid / "runs", str(grid / "sweep.yaml"), tmp_path / "out", episodes=2)
    _record_with(tmp_path / "out", edit)
    before = (tmp_path / "out" / "grids" / "wind_farm_control.json").read_text()
    shutil.copytree(grid / "runs", tmp_path / "runs")
    shutil.rmtree(next((tmp_path / "runs").glob("000-*")))
    with pytest.raises(TrainError, match=said):
        record_grid(tmp_path / "runs", str(grid / "sweep.yaml"), tmp_path / "out", episodes=2, partial=True)
    assert (tmp_path / "out" / "grids" / "wind_farm_control.json").read_text() == before


def test_a_record_of_another_sweep_is_refused_and_replaced_only_when_asked(grid, tmp_path):
    """Issue 54, item 4: recording a grid replaced the committed 18-point record of another sweep with a 4-point one."""
    record_grid(grid / "runs", str(grid / "sweep.yaml"), tmp_path / "out", episodes=2)
    _record_with(tmp_path / "out", lambda d: d.update(sweep_fingerprint="sha256:0"))
    record = tmp_path / "out" / "grids" / "wind_farm_control.json"
    before = record.read_text()
    with pytest.raises(TrainError, match=rf"^{record} records another sweep \('.*sweep.yaml', 2 points recorded\) than "
                                         r".*sweep.yaml \(2 points\): give --replace to replace it, or record into "
                                         r"another folder$"):
        record_grid(grid / "runs", str(grid / "sweep.yaml"), tmp_path / "out", episodes=2)
    assert record.read_text() == before
    data = record_grid(grid / "runs", str(grid / "sweep.yaml"), tmp_path / "out", episodes=2, replace=True)
    assert json.loads(record.read_text()) == data and data["sweep_fingerprint"] != "sha256:0"


def test_a_record_from_before_sweep_fingerprints_is_matched_by_its_rows(grid, tmp_path):
    record_grid(grid / "runs", str(grid / "sweep.yaml"), tmp_path / "out", episodes=2)
    _record_with(tmp_path / "out", lambda d: d.pop("sweep_fingerprint"))
    record_grid(grid / "runs", str(grid / "sweep.yaml"), tmp_path / "out", episodes=2)  # its own rows: the same sweep
    _record_with(tmp_path / "out", lambda d: (d.pop("sweep_fingerprint"), d["points"][1].update(fingerprint="sha256:1")))
    with pytest.raises(TrainError, match=r"records another sweep"):
        record_grid(grid / "runs", str(grid / "sweep.yaml"), tmp_path / "out", episodes=2)


def test_a_record_is_of_its_sweep_by_content_not_by_how_the_path_is_written(grid, tmp_path, monkeypatch):
    """Issue 54, item 4: recording ``./sweep.yaml`` with --partial dropped the rows recorded as ``sweep.yaml``."""
    monkeypatch.chdir(grid)
    record_grid(grid / "runs", "sweep.yaml", tmp_path / "out", episodes=2)
    shutil.copytree(grid / "runs", tmp_path / "runs")
    shutil.rmtree(next((tmp_path / "runs").glob("000-*")))
    data = record_grid(tmp_path / "runs", "./sweep.yaml", tmp_path / "out", episodes=2, partial=True)
    assert [row["name"] for row in data["points"]] == ["wfc-main[pattern=0]", "wfc-main[pattern=1]"]
    assert data["untrained"] == []


def test_a_point_s_evaluation_is_reused_only_for_the_checkpoint_it_played(grid, tmp_path):
    """Issue 54, item 6: a point resumed and trained on kept its earlier, shorter training's evaluation.json, and the
    record's row said 151,552 steps with the 4,096-step evaluation."""
    shutil.copytree(grid / "runs", tmp_path / "runs")
    points = compile_all(grid / "sweep.yaml")
    longer = [make_config("wind_farm_control", TINY | {"max_steps": 192}) for _ in points]
    run_grid(points, longer, tmp_path / "runs", eval_episodes=0, progress=False, resume=True)
    folder = next((tmp_path / "runs").glob("001-*"))
    earlier = json.loads((folder / "evaluation.json").read_text())
    assert earlier["trained_agent_steps"] == 96  # the earlier training's (the grid fixture's max_steps, a whole step of its slots)
    # marked, so the record shows which evaluation it took (a dozen steps' episodes can score alike either way)
    (folder / "evaluation.json").write_text(json.dumps(earlier | {"return": {"mean": -1.0, "std": 0.0}}))
    data = record_grid(tmp_path / "runs", str(grid / "sweep.yaml"), tmp_path / "out", episodes=2)
    fresh = evaluate(folder / "checkpoint.pt", split="test", episodes=2)
    assert fresh["trained_agent_steps"] == data["points"][1]["agent_steps"] == 192
    assert data["points"][1]["return"] == fresh["return"] != {"mean": -1.0, "std": 0.0}


def test_a_reused_evaluation_is_set_beside_the_published_cell_as_the_defaults_read_now(grid, tmp_path):
    """Issue 52, session 92: AWS's grid trained from a copy of its sweep that wrote out two params, the defaults since;
    the evaluations it wrote then found no published cell (the params then differed from the paper's setting), and the
    record took their missing cell although the points are the paper's cells now, the same by their fingerprints."""
    shutil.copytree(grid / "runs", tmp_path / "runs")
    folder = next((tmp_path / "runs").glob("001-*"))
    written = json.loads((folder / "evaluation.json").read_text())
    (folder / "evaluation.json").write_text(json.dumps(written | {"published": None}))
    data = record_grid(tmp_path / "runs", str(grid / "sweep.yaml"), tmp_path / "out", episodes=2)
    assert data["points"][1]["published"]["return"] == pytest.approx(dict(zip(("mean", "std"), PUBLISHED[1])))
    assert data["points"][1]["return"] == written["return"]  # the evaluation itself is still the one written


def test_a_run_is_recorded_only_as_the_scenario_it_trained(tmp_path):
    """Issue 54, item 7: a run of another scenario only named ``wfc-main`` (short episodes) was recorded as the
    bundled main scenario: PPO 0.10 beside random 1,367."""
    from hivex_dsl.compiler import compile
    from hivex_dsl.train.baselines import record_baseline
    from hivex_dsl.train.ppo import train

    other = compile(short_scenario("wind_farm_control"))
    assert other.name == "wfc-main"
    train(other, make_config(other.environment, TINY), tmp_path / "run", progress=False)
    main_yaml = "scenarios/wind_farm_control/main.yaml"
    with pytest.raises(TrainError, match=rf"^{tmp_path / 'run'} trained scenario 'wfc-main' \(fingerprint "
                                         rf"{other.fingerprint}\), not {main_yaml} \(fingerprint sha256:[0-9a-f]+\), "
                                         r"whatever their names$"):
        record_baseline(tmp_path / "run", main_yaml, tmp_path / "out", episodes=1)
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("case", ["truncated summary", "missing sweep", "episodes -3", "episodes 0", "not a record"])
def test_the_script_refuses_what_it_cannot_record_in_one_line(case, grid, monkeypatch, capsys, tmp_path):
    """Issue 54, item 12: each of these was a traceback (and --episodes 0 wrote a record of NaN, invalid JSON)."""
    import sys

    script = record_baseline_script()
    monkeypatch.setattr(script, "OUT", tmp_path / "out")
    shutil.copytree(grid / "runs", tmp_path / "runs")
    point = next((tmp_path / "runs").glob("000-*"))
    args = ["--grid", str(tmp_path / "runs"), str(grid / "sweep.yaml"), "--episodes", "2"]
    said = {"truncated summary": f"error: {point / 'summary.json'} is not a summary hivex can read (JSONDecodeError",
            "missing sweep": f"error: {tmp_path / 'none.yaml'}:1:1: no such file",
            "episodes -3": "argument --episodes: expected a positive integer, got -3",
            "episodes 0": "argument --episodes: expected a positive integer, got 0",
            "not a record": f"error: {tmp_path / 'out' / 'grids' / 'wind_farm_control.json'} is not a grid record hivex "
                            "can read"}[case]
    if case == "truncated summary":
        (point / "summary.json").write_text((point / "summary.json").read_text()[:40])
        args = [str(point), "scenarios/wind_farm_control/main.yaml"]
    elif case == "missing sweep":
        args[2] = str(tmp_path / "none.yaml")
    elif case.startswith("episodes"):
        args[-1] = case.split()[1]
    else:
        (tmp_path / "out" / "grids").mkdir(parents=True)
        (tmp_path / "out" / "grids" / "wind_farm_control.json").write_text('{"points": [')
    monkeypatch.setattr(sys, "argv", ["record_baseline.py", *args])
    with pytest.raises(SystemExit) as exit_:
        script.main()
    assert exit_.value.code == 2
    err = capsys.readouterr().err
    assert said in err and "Traceback" not in err
    assert not (tmp_path / "out" / "grids" / "wind_farm_control.json").exists() or case == "not a record"


def test_a_record_of_no_episodes_is_refused_never_written_as_nan(grid, tmp_path):
    for episodes in (0, -3):
        with pytest.raises(TrainError, match=rf"--episodes must be a positive number of test episodes, got {episodes}"):
            record_grid(grid / "runs", str(grid / "sweep.yaml"), tmp_path / "out", episodes=episodes)
    assert not (tmp_path / "out").exists()
