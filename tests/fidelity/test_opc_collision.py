"""Ocean Plastic Collection's collision distance against the original's trained vessel lives (issue 52).

No source gives the vessels' size. The original's trained vessel-episodes end after about 150 decisions (its Episode
Length at half the budget: 146, band 133-162), nearly all on a crash that ends the world's episode (the reward
table's ending note). This toolkit's record until session 69 (benchmarks/results/opc_record_5m.json), trained with
vessels colliding within 5 m (the first choice), learned to outlive that by half again (193-246 decisions at half
the budget), and its return ran 2-3 times the original's. Runs of the same scenario and hyperparameters (the
record's: 8 worlds on the fixed rollout, the protocol before session 51) at other distances
(benchmarks/results/opc_collision.json, written by benchmarks/opc_collision.py from the runs `hivex train` wrote;
one seed a distance) outlive the original's at 7.5 m as at 5 m, and at 10 and 15 m live within its band at a quarter
of the budget: the default, 10 m, is the smallest distance that did.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest

import hivex_dsl
from hivex_dsl.compiler.locks import as_written
from hivex_dsl.envs.ocean_plastic_collection.params import OceanPlasticCollectionParams
from hivex_dsl.evaluation.original import compare
from hivex_dsl.evaluation.original.seeds import SeedsRow, measure_seeds

from ..benchmark_scripts import benchmark_script

ROOT = Path(__file__).resolve().parents[2]
RESULTS = ROOT / "benchmarks" / "results" / "opc_collision.json"
# the record committed until session 69 (trained at 5 m on 8 worlds), kept as this evidence when its three seeds were
# re-trained at today's defaults
RECORD = ROOT / "benchmarks" / "results" / "opc_record_5m.json"
ENV = "ocean_plastic_collection"
LENGTH, RETURN = "Episode Length", "Cumulative Reward"
DEFAULT = OceanPlasticCollectionParams().collision_distance_m

script = benchmark_script("opc_collision")


def recorded_runs() -> list[dict]:
    return json.loads(RESULTS.read_text())["runs"]


def curves_at(distance: float) -> list[compare.RunCurve]:
    return [compare.from_points(run["curve"], f"seed {run['seed']}") for run in recorded_runs()
            if run["collision_distance_m"] == distance]


def rows(runs: list[compare.RunCurve], fractions=(0.25, 0.5)) -> dict[tuple[str, float], SeedsRow]:
    """The seeds' mean of each panel at ``fractions`` of the budget against the original's band."""
    measured = measure_seeds(runs, compare.original_cell(ENV, 0, None), fractions)
    return {(row.panel, row.fraction): row for row in measured}


def five_metre_record() -> list[compare.RunCurve]:
    """The 5 m record's three seeds, trained before the default changed (its note marks it stale)."""
    record = json.loads(RECORD.read_text())
    assert compare.is_stale(record) and "colliding within 5 m" in record["note"]
    return compare.seed_curves({**record, "environment": ENV})


def test_every_recorded_run_is_the_main_scenario_at_its_distance():
    """The runs differ from the main scenario at today's defaults in the collision distance and the camera alone
    (they saw the pebbles), so their lives compare with each other and with the record's (trained at 5 m and 8
    worlds with the pebble camera, its other choices today's)."""
    main = hivex_dsl.compile(ROOT / "scenarios" / ENV / "main.yaml").resolved()
    for run in recorded_runs():
        scenario = as_written(run["scenario"])  # params added since take the value that did what was done then
        assert scenario["params"]["camera_source"] == "pebbles"  # as the record's, whatever the default
        assert {**scenario["params"], "collision_distance_m": DEFAULT, "camera_source": main["params"]["camera_source"]
                } == main["params"]
        for key in ("task", "agents", "episode_length", "decision_period", "weights", "generators", "seeds"):
            assert scenario[key] == main[key], key
        assert run["agent_steps"] >= 0.2 * run["max_steps"]


# what a run may set apart from the record without changing what it learns: its seed, threads, device and logging
BOOKKEEPING = {"seed", "torch_threads", "device", "checkpoint_every", "keep_checkpoints", "summary_freq"}


def test_every_recorded_run_trained_as_the_record_did():
    """Like for like: the runs' hyperparameters are the 5 m record's (8 worlds on the fixed rollout, where
    `hivex train` now trains one world on finished trajectories), so their lives differ by the distance alone. The
    keys added since the record (action_masks) change nothing here: Ocean Plastic Collection masks no action."""
    record = json.loads(RECORD.read_text())["hyperparameters"]
    assert (record["num_worlds"], record["buffer_fill"]) == (8, "rollout")
    for run in recorded_runs():
        differing = {key for key in record if record[key] != run["hyperparameters"].get(key)}  # keys since: none
        assert differing <= BOOKKEEPING, (run["collision_distance_m"], differing)


def test_the_default_distance_was_trained():
    assert curves_at(DEFAULT), f"no run at the default collision distance, {DEFAULT} m"


def test_at_five_metres_the_record_outlives_the_original_at_half_the_budget():
    """The gap the default closes: the record's seeds live 218 decisions on average against the band's 162."""
    row = rows(five_metre_record())[(LENGTH, 0.5)]
    assert row.value > row.upper, (row.value, row.upper)


@pytest.mark.parametrize("fraction", [0.25, 0.5])
def test_at_the_default_distance_trained_vessels_live_about_as_long_as_the_originals(fraction):
    """Within the original's band at a quarter of the budget; at half of it nearer the original's mean (146, band
    133-162) than the 5 m record's seeds are (216): 184 decisions, about half the record's excess left."""
    runs = [run for run in curves_at(DEFAULT) if run.steps[-1] >= fraction * 3_000_000]
    assert runs, f"no run at {DEFAULT} m reached {fraction:.0%} of the budget"
    row = rows(runs)[(LENGTH, fraction)]
    if fraction == 0.25:
        assert row.lower <= row.value <= row.upper, (row.value, row.lower, row.upper)
    else:
        record = rows(five_metre_record())[(LENGTH, fraction)]
        assert abs(row.value - row.mean) < 0.6 * abs(record.value - record.mean), (row.value, record.value, row.mean)


def test_the_return_comes_nearer_the_originals_as_the_lives_shorten():
    """At a quarter and half of the budget the default's return is nearer the original's mean than the record's
    seeds' mean is; at a quarter of it every run at the default distance or beyond lives shorter and returns less
    than each of the record's three seeds (one seed a distance: 7.5 m lived and returned as the record did)."""
    ours, record = rows(curves_at(DEFAULT)), rows(five_metre_record())
    for fraction in (0.25, 0.5):
        mine, theirs = ours[(RETURN, fraction)], record[(RETURN, fraction)]
        assert mine.value is not None, f"no run at {DEFAULT} m reached {fraction:.0%} of the budget"
        assert abs(mine.value - mine.mean) < abs(theirs.value - theirs.mean), fraction
    seeds = {panel: [seed.value for seed in record[(panel, 0.25)].seeds] for panel in (LENGTH, RETURN)}
    for distance in sorted({run["collision_distance_m"] for run in recorded_runs()}):
        if distance < DEFAULT:
            continue
        quarter = rows(curves_at(distance), (0.25,))
        for panel in (LENGTH, RETURN):
            assert quarter[(panel, 0.25)].value < min(seeds[panel]), (distance, panel)


def test_the_script_reports_a_folder_that_is_no_run(tmp_path, capsys):
    assert script.main([str(tmp_path)]) == 2
    assert "not a training run's folder" in capsys.readouterr().err
