"""The published results shipped with the package, checked against numbers read by hand from the JSON."""

from __future__ import annotations

import dataclasses
import json

import pytest

from hivex_dsl.evaluation import published
from hivex_dsl.compiler import compile as compile_scenario



def test_wrm_main_terrain_1_as_read_by_hand():
    cell = published.cell("wildfire_resource_management", 0, 1)
    assert (cell.return_mean, cell.return_std) == (93.9174, 37.0585)
    moved = cell.statistics["WildfireResourceManagement/Reward for Moving Resources to Neighbours"]
    assert moved == (49.371, 24.7632)
    assert cell.statistic("Reward for Moving Resources to Self") == (0.2247, 0.1053)
    assert cell.statistics["Environment/Cumulative Reward"] == (93.9174, 37.0585)


def test_wfc_patterns_start_at_zero_and_opc_has_no_level():
    assert published.cell("wind_farm_control", 0, 8).return_mean == 4602.3256
    assert published.cell("wind_farm_control", 1, 0).statistic("Avoid Damage Reward") == (4826.7562, 36.9559)
    avoid = published.cell("ocean_plastic_collection", 3, None)
    assert (avoid.return_mean, avoid.return_std) == (-2.0388, 1.6475)
    assert avoid.statistic("Local Reward") == (-2.8543, 1.1866)
    assert published.cell("ocean_plastic_collection", 3, 1) is None


def test_cells_missing_from_the_paper_are_none():
    assert published.cell("drone_based_reforestation", 2, 1) is None  # Group Up: no published result
    assert published.cell("wildfire_resource_management", 0, 0) is None  # terrain levels start at 1
    assert published.cell("no_such_env", 0, 1) is None


def test_cells_lists_every_task_and_level_in_order():
    wrm = published.cells("wildfire_resource_management")
    assert len(wrm) == 3 * 10
    assert [(c.task_index, c.level) for c in wrm[:3]] == [(0, 1), (0, 2), (0, 3)]
    dbr_tasks = sorted({c.task_index for c in published.cells("drone_based_reforestation")})
    assert dbr_tasks == [0, 1, 3, 4, 5, 6, 7]
    aws = published.cell("aerial_wildfire_suppression", 5, 10)
    assert aws.statistic("Water Pickup") == (0.9978, 0.0097) and aws.return_mean == 95.0801


def test_cell_is_frozen():
    cell = published.cell("ocean_plastic_collection", 0, None)
    with pytest.raises(dataclasses.FrozenInstanceError):
        cell.return_mean = 0.0


@pytest.mark.parametrize("scenario, expected", [
    ("wildfire_resource_management/main", ("wildfire_resource_management", 0, 1, 93.9174)),
    ("wildfire_resource_management/keep_all", ("wildfire_resource_management", 1, 1, 195.4663)),
    ("ocean_plastic_collection/avoid_plastic", ("ocean_plastic_collection", 3, None, -2.0388)),
    ("wind_farm_control/main", ("wind_farm_control", 0, 0, 4611.6462)),
])
def test_cell_for_a_bundled_scenario(scenario, expected):
    cell = published.cell_for(compile_scenario(scenario))
    assert (cell.environment, cell.task_index, cell.level, cell.return_mean) == expected


def test_cell_for_a_task_without_a_published_result():
    assert published.cell_for(compile_scenario("drone_based_reforestation/group_up")) is None


def test_dbr_cells_are_keyed_by_the_task_whose_original_page_logs_their_statistics():
    """The original ran 7 tasks without Group Up (Pick Up Seed 2, Drop Seed 3 in its configs and page titles); its
    result 2 (no drop, Recharge Energy Count 147) is this toolkit's Pick-up Seed, result 3 (0.93 drops) Drop Seed."""
    pick_up = published.cell_for(compile_scenario("drone_based_reforestation/pick_up_seed"))
    assert (pick_up.task_index, pick_up.return_mean) == (3, 15.074)
    assert pick_up.statistic("Tree Drop Count") == (0.0, 0.0)
    assert pick_up.statistic("Recharge Energy Count") == (147.4054, 114.9151)
    drop = published.cell_for(compile_scenario("drone_based_reforestation/drop_seed"))
    assert (drop.task_index, drop.return_mean) == (4, 99.1604)
    assert drop.statistic("Tree Drop Count") == (0.9308, 0.0388)


def test_the_packaged_file_is_the_shared_one_with_dbr_results_2_and_3_keyed_by_the_configs_that_ran(paper):
    shared = json.loads((paper / "published-test-results.json").read_text())
    packaged = published.raw()
    dbr = shared["results"]["drone_based_reforestation"]
    # the shared file keys DBR by the appendix's comment save results 4-6 (5-7 there); the configs that ran list
    # Pick Up Seed as 2 and Drop Seed as 3, this toolkit's 3 and 4 (its note says why)
    moved = {"3": dbr.pop("2"), "4": dbr.pop("3")}
    assert packaged["results"]["drone_based_reforestation"] == dbr | moved
    assert {k: v for k, v in packaged["results"].items() if k != "drone_based_reforestation"} == {
        k: v for k, v in shared["results"].items() if k != "drone_based_reforestation"}
    dbr_note = [n for n in packaged["notes"] if n.startswith("Drone-Based Reforestation")]
    assert len(dbr_note) == 1 and "keyed here as t below 2 and t + 1 from 2 on" in dbr_note[0]
    assert [n for n in packaged["notes"] if n not in dbr_note] == [
        n for n in shared["notes"] if not n.startswith("Drone-Based Reforestation")]


@pytest.mark.parametrize("changes, differs", [
    ({"agents": 6, "episode_length": 200}, ["agents", "episode_length"]),
    ({"weights": {"generate_energy": 2.0}}, ["weights"]),
    ({"decision_period": 5}, ["decision_period"]),
    ({"params": {"farm_half_extent_m": 300.0}}, ["params"]),
])
def test_a_scenario_that_changes_the_paper_s_setting_reproduces_no_cell(changes, differs):
    """audit and evaluate set the paper's main-task result beside a 200-step, 6-turbine task ('return 4606
    58.22 (0.01x)') with no caveat: that cell is not such a scenario's result."""
    scenario = compile_scenario({"hivex": 1, "environment": "wind_farm_control", **changes})
    assert published.differences_from_paper(scenario) == differs
    assert published.cell_for(scenario) is None and published.paper_cell(scenario).return_mean == pytest.approx(4611.6462)
    assert published.caveat(scenario) == ("the paper's result for this task and level (return 4612) is not this "
                                          f"scenario's: it differs from the paper's setting in {', '.join(differs)}")


def test_other_seeds_and_another_name_still_reproduce_the_cell():
    scenario = compile_scenario({"hivex": 1, "environment": "wind_farm_control", "name": "mine",
                                 "seeds": {"train": 1, "test": 2}})
    assert published.differences_from_paper(scenario) == [] and published.caveat(scenario) is None
    assert published.cell_for(scenario).return_mean == pytest.approx(4611.6462)
