"""A finished run becomes committed data (JSON + learning-curve PNG), and the baselines page is built from it."""

from __future__ import annotations

import json
import os
import shlex
import shutil
from pathlib import Path

import pytest
import yaml

from hivex_dsl.compiler import compile, compile_all
from hivex_dsl.docsgen import render_docs
from hivex_dsl.docsgen.baselines import baselines_context
from hivex_dsl.train.config import PPOConfig, make_config
from hivex_dsl.train.ppo import train

from .conftest import benchmark_script, record_baseline_script, short_scenario

pytest.importorskip("matplotlib")

ROOT = Path(__file__).resolve().parents[2]


pytestmark = pytest.mark.usefixtures("as_if_reproduced")

@pytest.fixture(scope="module")
def recorded(tmp_path_factory):
    from hivex_dsl.train.baselines import record_baseline

    root = tmp_path_factory.mktemp("baseline")
    scenario = root / "wfc.yaml"
    scenario.write_text(yaml.safe_dump(short_scenario("wind_farm_control", episode_length=12)))
    tiny = {"num_worlds": 1, "buffer_fill": "rollout",
            "buffer_size": 32, "batch_size": 16, "hidden_units": 8, "max_steps": 192,
            "checkpoint_every": 64, "keep_checkpoints": 2}
    train(compile(scenario), make_config("wind_farm_control", tiny), root / "run", progress=False)
    out = root / "benchmarks" / "baselines"
    data = record_baseline(root / "run", str(scenario), out, episodes=2, command="hivex train x", note="a note")
    return out, data


def test_the_record_holds_test_levels_and_curve(recorded):
    out, data = recorded
    assert json.loads((out / "wind_farm_control.json").read_text()) == data
    assert (out / "wind_farm_control.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert data["test"]["agent_episodes"] == 2 * 8 and data["test"]["seed"] == 6000
    assert data["published"]["return"]["mean"] == pytest.approx(4611.6462)
    # all-scripted turbines face the wind: they must beat uniformly random ones on the same seeds
    assert data["scripted"]["mean"] > data["random"]["mean"]
    assert all(row[0] > 0 for row in data["curve"])


def test_re_recording_keeps_the_note_and_command_of_the_same_scenario(recorded, tmp_path):
    """A record's note is written by hand over sessions: recording the scenario's run again without --note keeps
    it; a record of another scenario lends it none."""
    from hivex_dsl.train.baselines import record_baseline

    out, data = recorded
    shutil.copytree(out, tmp_path / "out")
    run, scenario = out.parents[1] / "run", data["scenario"]
    again = record_baseline(run, scenario, tmp_path / "out", episodes=1, curve_episodes=1)
    assert (again["command"], again["note"]) == ("hivex train x", "a note")
    record = tmp_path / "out" / "wind_farm_control.json"
    record.write_text(json.dumps(json.loads(record.read_text()) | {"scenario": "scenarios/other.yaml"}))
    other = record_baseline(run, scenario, tmp_path / "out", episodes=1, curve_episodes=1, note="new")
    assert (other["command"], other["note"]) == ("", "new")


def test_the_record_keeps_episode_length_and_every_statistic_beside_the_return(recorded):
    out, data = recorded
    curve = json.loads((out.parents[1] / "run" / "curve.json").read_text())
    assert curve and len(data["curve"]) == len(curve)
    assert data["curve_episodes"] == [p["episodes"] for p in curve]
    assert data["curve_panels"]["Episode Length"] == [round(p["length"], 4) for p in curve]
    names = {name for p in curve for name in p["statistics"]}
    # and the critic's mean estimate and the updates' mean entropy (Wind Farm Control trains no curiosity: one value
    # head and no curiosity losses)
    assert names and set(data["curve_panels"]) == {"Episode Length", "Extrinsic Value Estimate", "Entropy"} | names
    for name in names:
        assert data["curve_panels"][name] == [round(p["statistics"][name], 4) for p in curve]
    assert data["curve_panels"]["Extrinsic Value Estimate"] == [round(p["extrinsic_value_estimate"], 4) for p in curve]
    assert data["curve_panels"]["Entropy"] == [round(p["losses"]["entropy"], 4) for p in curve]


def test_the_test_episode_length_sits_beside_the_original_s_test_average(recorded):
    """12-step episodes that never end early log 11 decisions (ML-Agents counts one less); beside them the
    original's WFC pattern 0 test runs, whose every point in the event files logs 4,999."""
    out, data = recorded
    assert data["test"]["episode_length"] == {"mean": 11.0, "std": 0.0}
    assert data["test"]["original_episode_length"] == 4999.0
    (row,) = baselines_context(out)["trained"]
    assert row["statistics"][0] == {"name": "Episode Length", "ours": "11.00 ± 0.00",
                                    "published": "4,999.00 (the original's test average, unpublished)"}
    older = dict(data, test={k: v for k, v in data["test"].items() if "episode_length" not in k})
    from hivex_dsl.docsgen.baselines import _row

    assert [s["name"] for s in _row("wind_farm_control", older)["statistics"]] == list(data["test"]["statistics"])


def test_every_kept_checkpoint_is_scored_on_the_test_seeds(recorded):
    _, data = recorded
    # checkpoints at 64, 128 and 192 agent-steps; the newest two are kept
    assert [row[0] for row in data["test_curve"]] == [128, 192]
    assert all(0 < row[1] <= data["wall_s"] for row in data["test_curve"])
    # 12-step episodes cannot reach the paper's 4,611 (about 400 per step at most)
    assert all(row[2] < 4611 for row in data["test_curve"]) and data["reached_published"] is None


def test_first_reaching_takes_the_earliest_point_at_or_above_the_published_mean():
    from hivex_dsl.train.baselines import first_reaching

    published = {"return": {"mean": 10.0, "std": 1.0}}
    curve = [[100, 1.0, 4.0, 0.5], [200, 2.0, 10.0, 0.5], [300, 3.0, 12.0, 0.5]]
    assert first_reaching(curve, [400, 4.0, 11.0, 0.1], published) == {"agent_steps": 200, "wall_s": 2.0, "return": 10.0}
    assert first_reaching(curve[:1], [400, 4.0, 11.0, 0.1], published)["agent_steps"] == 400
    assert first_reaching(curve[:1], [400, 4.0, 9.9, 0.1], published) is None
    assert first_reaching(curve, [400, 4.0, 11.0, 0.1], None) is None


def test_the_verdict_pools_every_seeds_test_episodes():
    from hivex_dsl.docsgen.baselines import pooled_return, verdict

    # seed 0 scored episodes [-3, 3], seed 1 scored [3, 5]: together [-3, 3, 3, 5], mean 2, population std 3
    data = {"test": {"return": {"mean": 0.0, "std": 3.0}}, "other_seeds": [{"return": {"mean": 4.0, "std": 1.0}}]}
    assert pooled_return(data) == pytest.approx({"mean": 2.0, "std": 3.0})
    assert pooled_return({"test": data["test"]}) == data["test"]["return"]
    assert verdict(pooled_return(data), {"mean": 3.0, "std": 1.0}) == "matches (within the summary points' spread)"
    # our own spread (3) does not widen the published one (1)
    assert verdict(pooled_return(data), {"mean": 3.5, "std": 1.0}) == "below"
    assert verdict(pooled_return(data), {"mean": 5.5, "std": 1.0}) == "below"
    assert verdict(pooled_return(data), {"mean": -1.5, "std": 0.5}) == "above"
    assert verdict(pooled_return(data), None) == "-"
    # one unlucky record seed no longer decides it: alone it is below a published 8 +- 1, pooled with two
    # seeds at 60 and 70 (as DBR's) it is above
    unlucky = {"test": {"return": {"mean": 2.0, "std": 1.0}},
               "other_seeds": [{"return": {"mean": 60.0, "std": 1.0}}, {"return": {"mean": 70.0, "std": 1.0}}]}
    assert verdict(unlucky["test"]["return"], {"mean": 8.0, "std": 1.0}) == "below"
    assert verdict(pooled_return(unlucky), {"mean": 8.0, "std": 1.0}) == "above"


def test_the_page_names_the_records_that_trained_with_an_earlier_choice(recorded):
    from hivex_dsl.docsgen.baselines import earlier_choices

    out, data = recorded
    assert earlier_choices({"wind_farm_control": data}) == {
        "at_defaults": ["WFC"], "earlier_records": [], "earlier": {key: [] for key in earlier_choices({})["earlier"]}}
    earlier = {"max_grad_norm": 0.5, "weight_init": "cleanrl", "policy_loss": "joint"}
    old = {**data, "hyperparameters": {**data["hyperparameters"], **earlier}}
    # the DBR record here lacks policy_loss (as a record older than the key would): a missing key is no earlier choice
    older = {**data, "hyperparameters": {k: v for k, v in old["hyperparameters"].items() if k != "policy_loss"}}
    found = earlier_choices({"drone_based_reforestation": older, "wind_farm_control": data,
                             "wildfire_resource_management": old})
    assert found["at_defaults"] == ["WFC"] and found["earlier_records"] == ["WRM", "DBR"]  # in the registry's order
    assert found["earlier"]["max_grad_norm"] == found["earlier"]["weight_init"] == ["WRM", "DBR"]
    assert found["earlier"]["policy_loss"] == ["WRM"] and found["earlier"]["curiosity_module"] == []
    (out / "wildfire_resource_management.json").write_text(json.dumps({**old, "environment": "wildfire_resource_management"}))
    try:
        page = render_docs(None, baselines=out)["baselines.md"]
    finally:
        (out / "wildfire_resource_management.json").unlink()
    assert "WFC is recorded at these\ndefaults; the WRM record, trained before a default changed,\nsets" in page
    assert "0.5 was the earlier default (it trained the WRM record)." in page
    assert "PPO's one ratio (it trained the WRM record);" in page


def test_the_choices_sentence_reads_whichever_records_there_are(recorded, tmp_path):
    out, data = recorded
    only_earlier = tmp_path / "earlier"
    only_earlier.mkdir()
    old = {**data, "hyperparameters": {**data["hyperparameters"], "max_grad_norm": 0.5}}
    (only_earlier / "wind_farm_control.json").write_text(json.dumps(old))
    page = render_docs(None, baselines=only_earlier)["baselines.md"]
    assert "ML-Agents by default. The WFC record, trained before a default changed,\nsets" in page
    none = tmp_path / "none"
    none.mkdir()
    assert "ML-Agents by default:\n" in render_docs(None, baselines=none)["baselines.md"]


def test_the_page_sets_ours_beside_the_paper(recorded):
    out, data = recorded
    context = baselines_context(out)
    (row,) = context["trained"]
    assert row["environment"] == "wind_farm_control" and row["commands"] == ["hivex train x"]
    assert row["verdict"] in ("matches (within the summary points' spread)", "above", "below")
    assert {r["environment"] for r in context["left"]} == {
        "wildfire_resource_management", "drone_based_reforestation", "ocean_plastic_collection",
        "aerial_wildfire_suppression"}
    docs = render_docs(None, baselines=out)
    assert "images/baselines/wind_farm_control.png" in docs
    assert "4,611.65 ± 39.95" in docs["baselines.md"]
    assert "hivex train scenarios/aerial_wildfire_suppression/main.yaml" in docs["baselines.md"]
    assert "baselines.md" not in render_docs(None, baselines=out / "missing")


def test_the_page_shows_training_throughput_against_the_targets(recorded):
    out, _ = recorded
    results = out.parent / "results" / "train_throughput.json"
    results.parent.mkdir(exist_ok=True)
    cpu = "x86_64, 2 cores, Linux, Python 3.11.7"
    row = {"environment": "wind_farm_control", "agent_steps": 300_000, "wall_s": 6.0, "agent_steps_per_s": 60_000.0,
           "env_share": 0.061, "num_worlds": 32, "torch_threads": 1, "agents": 8, "buffer_size": 2048,
           "batch_size": 256, "num_epoch": 3}  # a row written before rows named their machine and device
    slow = row | {"environment": "aerial_wildfire_suppression", "agent_steps_per_s": 1_999.4, "num_worlds": 12,
                  "agents": 3, "machine": cpu, "measured": "2026-11-27", "commit": "abc1234+changes"}
    gpu = row | {"environment": "ocean_plastic_collection", "agent_steps_per_s": 28_800.0, "num_worlds": 8,
                 "agents": 3, "device": "cuda", "processes": 16, "machine": "x86_64, 16 cores, an H100"}
    approximate = slow | {"environment": "ocean_plastic_collection", "agent_steps_per_s": 512.0, "num_worlds": 8,
                          "precision": "bf16"}
    exact = approximate | {"precision": "exact"}
    results.write_text(json.dumps({"machine": cpu, "rows": [row, slow, gpu, approximate, exact]}))
    bound = {"machine": cpu, "environment": "wind_farm_control", "threads": 1, "compute_bound_agent_steps_per_s": 1.2e5}
    bounds = results.parent / "compute_bound.json"
    bounds.write_text(json.dumps({"rows": [bound, bound | {"threads": 2}]}))
    try:
        page = render_docs(None, baselines=out)["baselines.md"]
    finally:
        results.unlink()
        bounds.unlink()
    cpu_table, gpu_table = page.split(f"On {cpu}:")[1].split("On x86_64, 16 cores, an H100:")
    # the paper's budgets: WFC 8M at 60,000/s is 133 s; AWS 1.8M at 1,999.4/s 900 s; OPC 3M x 16 at 28,800/s 1,667 s
    # 60,000 of the 120,000 agent-steps/s its arithmetic allows on 1 thread (the 2-thread bound is another row's)
    assert "| `wind_farm_control` | 32 x 8 | cpu | 1 x 1 | exact | 2048 / 256 / 3 | 60,000 | 120,000 (50%) | 6% " \
           "| 8M in 2 min | 60,000 | yes | - |" in cpu_table
    assert "| `aerial_wildfire_suppression` | 12 x 3 | cpu | 1 x 1 | exact | 2048 / 256 / 3 | 1,999 | - | 6% " \
           "| 1.8M in 15 min | 3,500 | no | 2026-11-27, `abc1234+changes` |" in cpu_table
    # one rate (3M at 512/s is 5,859 s) against each precision's target: the exact 450 met, the approximate 600 not
    assert "| `ocean_plastic_collection` | 8 x 3 | cpu | 1 x 1 | bf16 | 2048 / 256 / 3 | 512 | - | 6% " \
           "| 3M in 1.6 h | 600 | no |" in cpu_table
    assert "| `ocean_plastic_collection` | 8 x 3 | cpu | 1 x 1 | exact | 2048 / 256 / 3 | 512 | - | 6% " \
           "| 3M in 1.6 h | 450 | yes |" in cpu_table
    assert "| `ocean_plastic_collection` | 8 x 3 | cuda | 16 x 1 | exact | 2048 / 256 / 3 | 28,800 | - | 6% " \
           "| 3M in 28 min | 50,000 | no |" in gpu_table
    assert "Training throughput" not in render_docs(None, baselines=out)["baselines.md"]


def test_the_gpu_check_runs_its_steps_on_the_cpu(tmp_path):
    """benchmarks/gpu_check.sh with --device cpu: the CUDA test is skipped, not failed, and each environment's
    concurrent runs become one row merged into a copy of the committed table, whose own rows are kept."""
    import subprocess
    import sys

    root = Path(__file__).resolve().parents[2]
    committed = json.loads((root / "benchmarks" / "results" / "train_throughput.json").read_text())["rows"]
    tiny = ["--set", "num_worlds=1", "--set", "buffer_fill=rollout", "--set", "buffer_size=32", "--set", "batch_size=16",
            "--set", "hidden_units=8"]
    command = ["bash", str(root / "benchmarks" / "gpu_check.sh"), "--device", "cpu", "--steps", "64",
               "--processes", "2", "--out", str(tmp_path), "--env", "ocean_plastic_collection", *tiny]
    done = subprocess.run(command, capture_output=True, text=True, env=os.environ | {"PYTHON": sys.executable})
    assert done.returncode == 0, done.stderr
    assert "1 skipped" in done.stdout
    rows = json.loads((tmp_path / "train_throughput.json").read_text())["rows"]
    fresh = [r for r in rows if r not in committed]  # the committed table has 2-process rows of its own
    assert len(fresh) == 1 and fresh[0]["environment"] == "ocean_plastic_collection" and fresh[0]["processes"] == 2
    assert fresh[0]["device"] == "cpu" and fresh[0]["num_worlds"] == 1
    # the row says when and what it measured: today (UTC) and this checkout's commit
    import datetime
    assert fresh[0]["measured"] == datetime.datetime.now(datetime.timezone.utc).date().isoformat()
    assert fresh[0]["commit"] is None or fresh[0]["commit"].split("+")[0].isalnum()
    # each run: rollouts of 32 // 3 = 10 steps of 3 agents until 64 are done, the last cut to the 2 steps left
    # (30 + 30 + 6 = 66, --steps rounded up to a whole step of every slot); two runs
    assert fresh[0]["agent_steps"] == 2 * 66
    assert len(rows) == len(committed) + 1
    refused = subprocess.run(["bash", str(root / "benchmarks" / "gpu_check.sh"), "--gpus", "2"],
                             capture_output=True, text=True)
    assert refused.returncode == 2 and "unknown argument '--gpus'" in refused.stderr


def test_running_mean_by_hand():
    from hivex_dsl.train.plots import running_mean

    assert running_mean([2.0, 4.0, 6.0, 8.0], 2) == [2.0, 3.0, 5.0, 7.0]
    assert running_mean([1.0, 5.0], 1) == [1.0, 5.0]


def test_a_resumed_run_says_so_on_the_page(recorded, tmp_path):
    _, data = recorded
    assert data["resumed_at"] == []  # the recorded run trained in one go
    resumed = data | {"resumed_at": [2_100_000], "wall_s": 600.0}
    (tmp_path / "wind_farm_control.json").write_text(json.dumps(resumed))
    (row,) = baselines_context(tmp_path)["trained"]
    assert row["wall"] == "10.0 min (resumed at 2,100,000)"


@pytest.fixture(scope="module")
def seeds(recorded, tmp_path_factory):
    """The recorded run's record copied aside, and runs of the same tiny config on seed 1 and on seed 0."""
    out, data = recorded
    root = tmp_path_factory.mktemp("seeds")
    record = root / "wind_farm_control.json"
    record.write_text((out / "wind_farm_control.json").read_text())
    compiled = compile(data["scenario"])
    runs = {}
    for name, overrides in (("seed1", {"seed": 1}), ("seed0", {}), ("gamma", {"seed": 2, "gamma": 0.5}),
                            ("worlds", {"seed": 3, "world_seed": 77})):
        hyperparameters = data["hyperparameters"] | overrides
        train(compiled, make_config("wind_farm_control", hyperparameters), root / name, progress=False)
        runs[name] = root / name
    return record, runs


def test_another_seed_is_evaluated_on_the_record_s_test_episodes(seeds):
    from hivex_dsl.train.baselines import add_seed
    from hivex_dsl.train.evaluate import evaluate

    record, runs = seeds
    data = add_seed(record, runs["seed1"])
    (entry,) = data["other_seeds"]
    assert entry["seed"] == 1 and entry["agent_steps"] == 192
    curve = json.loads((runs["seed1"] / "curve.json").read_text())
    assert [row[0] for row in entry["curve"]] == [p["agent_steps"] for p in curve]  # its training curve, kept
    assert [row[2] for row in entry["curve"]] == [round(p["return"], 4) for p in curve]
    assert entry["curve_panels"]["Episode Length"] == [round(p["length"], 4) for p in curve]
    alone = evaluate(runs["seed1"] / "checkpoint.pt", split="test", episodes=data["test"]["episodes"])
    assert entry["return"] == alone["return"]  # the same episodes as the record's own evaluation
    assert entry["episode_length"] == alone["episode_length"]
    assert json.loads(record.read_text()) == data
    assert add_seed(record, runs["seed1"])["other_seeds"] == [entry]  # adding it again replaces it

    (row,) = baselines_context(record.parent)["trained"]
    means = [data["test"]["return"]["mean"], entry["return"]["mean"]]
    across = f"{sum(means) / 2:,.2f} ± {abs(means[0] - means[1]) / 2:,.2f}"  # population std of two values
    assert row["seeds"]["across"] == across and row["seeds"]["count"] == 2
    assert [r["seed"] for r in row["seeds"]["rows"]] == ["0 (the record above)", "1"]
    page = render_docs(None, baselines=record.parent)["baselines.md"]
    assert f"| {across} (2 seeds) |" in page and "| 1 | " in page


def test_only_another_seed_of_the_same_config_is_added(seeds):
    from hivex_dsl.train.baselines import add_seed
    from hivex_dsl.train.config import TrainError

    record, runs = seeds
    with pytest.raises(TrainError, match="seed 0, the record's own"):
        add_seed(record, runs["seed0"])
    with pytest.raises(TrainError, match=r"gamma: 0.9 -> 0.5"):
        add_seed(record, runs["gamma"])


def test_a_seed_on_worlds_of_its_own_is_another_seed_and_says_so(seeds, tmp_path):
    from hivex_dsl.evaluation.original.compare import seed_curves
    from hivex_dsl.train.baselines import add_seed

    record, runs = seeds
    (tmp_path / record.name).write_text(record.read_text())
    data = add_seed(tmp_path / record.name, runs["worlds"])
    assert [(e["seed"], e["world_seed"]) for e in data["other_seeds"] if e["seed"] == 3] == [(3, 77)]
    labels = [run.label for run in seed_curves(data)]
    assert labels[0] == "this toolkit, seed 0" and "this toolkit, seed 3 on worlds 77" in labels
    (row,) = baselines_context(tmp_path)["trained"]
    assert "3 on worlds 77" in [r["seed"] for r in row["seeds"]["rows"]]


def test_a_record_older_than_a_hyperparameter_takes_its_default(seeds, tmp_path):
    from hivex_dsl.train.baselines import add_seed

    record, runs = seeds
    old = json.loads(record.read_text())
    old["hyperparameters"] = {k: v for k, v in old["hyperparameters"].items() if not k.startswith("curiosity_")}
    (tmp_path / record.name).write_text(json.dumps(old))
    assert [e["seed"] for e in add_seed(tmp_path / record.name, runs["seed1"])["other_seeds"]] == [1]


def test_the_script_reports_a_refused_seed_without_a_traceback(seeds, monkeypatch, capsys):
    import sys

    record, runs = seeds
    script = record_baseline_script()
    monkeypatch.setattr(script, "OUT", record.parent)
    monkeypatch.setattr(sys, "argv", ["record_baseline.py", "--add-seed", str(runs["seed0"])])
    with pytest.raises(SystemExit) as exit_:
        script.main()
    assert exit_.value.code == 2
    assert capsys.readouterr().err == f"error: {runs['seed0']} trained on seed 0, the record's own; give another seed's run\n"


@pytest.mark.parametrize("record", sorted((ROOT / "benchmarks" / "baselines").glob("*.json"))
                         + sorted((ROOT / "benchmarks" / "baselines" / "grids").glob("*.json")),
                         ids=lambda p: f"{p.parent.name}/{p.stem}")
def test_a_committed_record_s_command_trains_with_its_hyperparameters(record):
    """The page's command reproduces a record (or a grid record, which trained a sweep): today's defaults with its
    --set values are every hyperparameter the record trained with (keys added since it was written read as they
    meant then)."""
    from hivex_dsl.train.checkpoint import acting_interface, older_defaults

    from hivex_dsl.cli import build_parser
    from hivex_dsl.cli.train_commands import train_config

    data = json.loads(record.read_text())
    scenario = data.get("scenario") or data["sweep"]
    words = shlex.split(data["command"].splitlines()[0])
    assert words[:3] == ["hivex", "train", scenario]
    now = train_config(data["environment"], build_parser().parse_args(words[1:]))  # as `hivex train` reads it
    then = older_defaults(data["hyperparameters"], *acting_interface(compile_all(ROOT / scenario)[0]))
    assert now.model_dump() == PPOConfig(**then).model_dump()


def test_an_approximate_record_says_so_beside_its_return(recorded, tmp_path):
    _, data = recorded
    assert data["hyperparameters"]["precision"] == "exact"
    (tmp_path / "wind_farm_control.json").write_text(json.dumps(data))
    exact_page = render_docs(None, baselines=tmp_path)["baselines.md"]
    approximate = data | {"hyperparameters": data["hyperparameters"] | {"precision": "bf16"}}
    (tmp_path / "wind_farm_control.json").write_text(json.dumps(approximate))
    (row,) = baselines_context(tmp_path)["trained"]
    assert row["precision"] == "bf16"
    page = render_docs(None, baselines=tmp_path)["baselines.md"]
    assert f"| `wind_farm_control` | {row['ours']} (bf16, approximate) |" in page
    assert "(bf16, approximate)" not in exact_page and f"| `wind_farm_control` | {row['ours']} |" in exact_page


def test_a_running_mean_shows_its_pooled_form_on_the_page():
    """A record's running-mean statistic (OPC's Local and Global Reward) compares with the published summary point
    in its pooled form, so the page shows that first; a sum keeps its mean ± std."""
    from hivex_dsl.docsgen.baselines import statistic_cell

    assert statistic_cell({"mean": 78.5, "std": 15.19, "pooled": 81.44}) == "81.44 pooled (per episode 78.50 ± 15.19)"
    assert statistic_cell({"mean": 6.23, "std": 2.5}) == "6.23 ± 2.50"


def test_the_headline_verdict_is_about_the_number_beside_it():
    # issue 54 item 18: DBR's row said "above" beside its recorded seed's 7.02 against a published 8.96 +- 2.74
    # (the three seeds pooled, 12.51, were above); the record's own verdict comes first, the pooled one named
    from hivex_dsl.docsgen.baselines import record_verdict

    dbr = {"test": {"return": {"mean": 7.02, "std": 9.07}},
           "other_seeds": [{"return": {"mean": 0.39, "std": 2.05}}, {"return": {"mean": 30.13, "std": 19.04}}]}
    published = {"mean": 8.96, "std": 2.74}
    assert record_verdict(dbr, published) == ("matches (within the summary points' spread); "
                                              "3 seeds pooled (12.51): above")
    one = {"test": {"return": {"mean": 4.0, "std": 1.0}}}
    assert record_verdict(one, published) == "below" and record_verdict(dbr, None) == "-"


def test_a_throughput_row_replaces_only_its_own_machines_row(tmp_path):
    """benchmarks/train_throughput.py's merge: a new row replaces the row of the same configuration measured on
    the same machine, and keeps another machine's row of that configuration (an H200's rows once replaced the
    H100's committed ones)."""
    merged = benchmark_script("train_throughput").merged
    row = {"environment": "ocean_plastic_collection", "num_worlds": 8, "torch_threads": 1, "device": "cuda",
           "processes": 16, "precision": "exact", "agent_steps_per_s": 28_715.3, "machine": "16 cores, an H100"}
    path = tmp_path / "train_throughput.json"
    path.write_text(json.dumps({"rows": [row]}))
    h200 = row | {"agent_steps_per_s": 30_194.4, "machine": "16 cores, an H200"}
    assert merged(path, [h200])["rows"] == [row, h200]
    again = row | {"agent_steps_per_s": 29_000.0}
    assert merged(path, [again])["rows"] == [again]


def test_a_record_names_the_processor_model_that_made_it(tmp_path):
    """A record reproduces to the digit only on a processor that takes the same kernels, so its machine names the
    model: the first processor's name with its family and model numbers, and a clear stand-in where /proc/cpuinfo
    is absent or names none (an ARM board lists no model name)."""
    from hivex_dsl.train.devices import cpu_model, machine

    cpuinfo = tmp_path / "cpuinfo"
    block = "processor\t: {i}\nvendor_id\t: GenuineIntel\ncpu family\t: 6\nmodel\t\t: {m}\nmodel name\t: Xeon {m}\n"
    cpuinfo.write_text(block.format(i=0, m=167) + "\n" + block.format(i=1, m=85))
    assert cpu_model(cpuinfo) == "Xeon 167 family 6 model 167"
    cpuinfo.write_text("processor\t: 0\nBogoMIPS\t: 50.00\nCPU implementer\t: 0x41\n")
    assert cpu_model(cpuinfo) == "an unnamed processor"
    assert cpu_model(tmp_path / "missing") == "an unnamed processor"
    assert "torch's" in machine() and " kernels, " in machine()
