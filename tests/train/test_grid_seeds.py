"""A grid record's points gain other training seeds, and the fidelity page measures the mean of a point's seeds."""

from __future__ import annotations

import json
import shutil

import pytest
import yaml

from hivex_dsl.compiler import compile_all
from hivex_dsl.docsgen import render_docs
from hivex_dsl.evaluation.original import compare
from hivex_dsl.train.baselines import record_grid
from hivex_dsl.train.config import TrainError, make_config
from hivex_dsl.train.grid import run_grid
from hivex_dsl.train.grid_seeds import add_grid_seed

from .conftest import TINY, record_baseline_script, short_scenario

pytest.importorskip("matplotlib")

pytestmark = pytest.mark.usefixtures("as_if_reproduced")

RECORD = "grids/wind_farm_control.json"


@pytest.fixture(scope="module")
def grids(tmp_path_factory):
    """A two-pattern Wind Farm Control sweep trained on seed 0 (both points) and on seed 1 (point 1 only)."""
    root = tmp_path_factory.mktemp("grid_seeds")
    sweep = short_scenario("wind_farm_control", 12) | {"sweep": {"pattern": [0, 1]}}
    del sweep["pattern"]
    (root / "sweep.yaml").write_text(yaml.safe_dump(sweep))
    points = compile_all(root / "sweep.yaml")
    config = TINY | {"max_steps": 96}
    run_grid(points, [make_config("wind_farm_control", config) for _ in points], root / "seed0", eval_episodes=2,
             progress=False)
    run_grid(points[1:], [make_config("wind_farm_control", config | {"seed": 1})], root / "seed1", eval_episodes=2,
             progress=False, indices=[1])
    return root


def _recorded(grids, out):
    return record_grid(grids / "seed0", str(grids / "sweep.yaml"), out, episodes=2)


def test_a_point_trained_on_another_seed_joins_its_row(grids, tmp_path):
    _recorded(grids, tmp_path)
    data = add_grid_seed(tmp_path / RECORD, grids / "seed1")
    assert json.loads((tmp_path / RECORD).read_text()) == data
    first, second = data["points"]
    assert "other_seeds" not in first  # the seed-1 grid trained point 1 alone
    (entry,) = second["other_seeds"]
    folder = next((grids / "seed1").glob("001-*"))
    assert entry["seed"] == 1 and entry["agent_steps"] == second["agent_steps"]
    # its own test evaluation on the record's two episodes, and its training curve as the point's is kept
    assert entry["return"] == json.loads((folder / "evaluation.json").read_text())["return"]
    curve = json.loads((folder / "curve.json").read_text())
    assert [row[2] for row in entry["curve"]] == [round(p["return"], 4) for p in curve]
    assert entry["curve_panels"]["Episode Length"] == [round(p["length"], 4) for p in curve]
    assert add_grid_seed(tmp_path / RECORD, grids / "seed1")["points"][1]["other_seeds"] == [entry]  # replaced


def test_re_recording_the_grid_keeps_its_seeds_only_while_they_trained_the_same(grids, tmp_path):
    _recorded(grids, tmp_path)
    seeds = add_grid_seed(tmp_path / RECORD, grids / "seed1")["points"][1]["other_seeds"]
    assert _recorded(grids, tmp_path)["points"][1]["other_seeds"] == seeds
    record = json.loads((tmp_path / RECORD).read_text())
    record["hyperparameters"]["learning_rate"] = 0.5  # the record's seeds trained at another rate than the grid now
    (tmp_path / RECORD).write_text(json.dumps(record))
    assert "other_seeds" not in _recorded(grids, tmp_path)["points"][1]
    add_grid_seed(tmp_path / RECORD, grids / "seed1")
    replaced = record_grid(grids / "seed0", str(grids / "sweep.yaml"), tmp_path, episodes=2, replace=True)
    assert all("other_seeds" not in point for point in replaced["points"])


def _copy_edited(grids, tmp_path, name: str, edit):
    shutil.copytree(grids / "seed1", tmp_path / "seed1")
    path = next((tmp_path / "seed1").glob("001-*")) / name
    written = json.loads(path.read_text())
    edit(written)
    path.write_text(json.dumps(written))
    return tmp_path / "seed1"


def test_only_another_seed_of_the_grid_s_points_and_config_is_added(grids, tmp_path):
    _recorded(grids, tmp_path / "out")
    record = tmp_path / "out" / RECORD
    with pytest.raises(TrainError, match="trained on seed 0, the record's own"):
        add_grid_seed(record, grids / "seed0")
    other = _copy_edited(grids, tmp_path / "rate", "config.json", lambda c: c["hyperparameters"].update(gamma=0.5))
    with pytest.raises(TrainError, match=r"is not another seed of wind_farm_control.json's point 1: its "
                                         r"hyperparameters differ \(gamma: 0.9 -> 0.5\)"):
        add_grid_seed(record, other)
    stopped = _copy_edited(grids, tmp_path / "stopped", "summary.json", lambda s: s.update(stopped_early=True))
    with pytest.raises(TrainError, match=r"point 1 of .* did not train to its end: run its `hivex train` command "
                                         r"again with --resume"):
        add_grid_seed(record, stopped)
    (tmp_path / "empty").mkdir()
    with pytest.raises(TrainError, match=r"holds no point of .*sweep.yaml: nothing to add"):
        add_grid_seed(record, tmp_path / "empty")
    assert "other_seeds" not in json.loads(record.read_text())["points"][1]  # nothing refused was written


def test_the_fidelity_page_measures_the_mean_of_a_point_s_seeds(grids, tmp_path):
    _recorded(grids, tmp_path)
    data = add_grid_seed(tmp_path / RECORD, grids / "seed1")
    # the tiny runs hold one curve point each: hand-made curves over the original's 8M agent-steps instead, a point
    # every 200k, two seeds apart
    steps = range(200_000, 8_000_001, 200_000)
    for run, (start, slope) in zip((data["points"][1], data["points"][1]["other_seeds"][0]), ((1000, 2e-4), (2500, 1e-4))):
        run |= {"curve": [[s, 1.0, start + slope * s] for s in steps], "curve_episodes": [8] * len(steps),
                "curve_panels": {}}
    (tmp_path / RECORD).write_text(json.dumps(data))
    page = render_docs(None, baselines=tmp_path)["fidelity.md"]
    assert "the mean of the point's training seeds, as many as the Seeds column counts" in page
    cell = compare.original_cell("wind_farm_control", 0, 1)
    point = data["points"][1] | {"environment": "wind_farm_control"}
    alone = [[r for r in compare.measure(compare.from_record(run | {"environment": "wind_farm_control"}), cell)
              if r.panel == compare.RETURN] for run in (point, point["other_seeds"][0])]
    cells, both = [], 0
    for first, second in zip(*alone):  # a seed without a point near a fraction counts as none there
        known = [r.ours.value for r in (first, second) if r.ours.value is not None]
        both += len(known) == 2
        mean = sum(known) / len(known) if known else None
        cells.append("no point" if mean is None else
                     f"{compare.number(mean)}, {compare.verdict(mean, first.lower, first.upper)}")
    assert both == len(cells) == 4
    assert f"| 0 `generate_energy` | 1 | 2 | {' | '.join(cells)} |" in page
    assert "| 0 `generate_energy` | 0 | 1 | " in page


def test_the_script_adds_a_grid_seed_and_refuses_without_a_traceback(grids, monkeypatch, capsys, tmp_path):
    import sys

    script = record_baseline_script()
    monkeypatch.setattr(script, "OUT", tmp_path)
    monkeypatch.setattr(sys, "argv", ["record_baseline.py", "--grid-add-seed", str(grids / "seed1")])
    with pytest.raises(SystemExit) as exit_:
        script.main()
    assert exit_.value.code == 2
    assert capsys.readouterr().err == (f"error: no grid record of wind_farm_control at {tmp_path / RECORD}: record "
                                       "its grid with --grid first\n")
    _recorded(grids, tmp_path)
    script.main()
    assert capsys.readouterr().out == f"added seed 1 to {tmp_path / RECORD} at 1 points\n"
