"""The baselines and fidelity pages set every recorded main-task curve beside the original's, and say where the
record's budget is not the original's."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from hivex_dsl.docsgen import _jinja
from hivex_dsl.docsgen.baselines import baselines_context
from hivex_dsl.docsgen.curves import budget_source, curve_comparisons
from hivex_dsl.docsgen.fidelity_page import fidelity_context

pytest.importorskip("matplotlib")

BASELINES = Path(__file__).resolve().parents[1] / "benchmarks" / "baselines"
MAIN_TASKS = {"wind_farm_control", "wildfire_resource_management", "ocean_plastic_collection",
              "drone_based_reforestation", "aerial_wildfire_suppression"}


@pytest.fixture(scope="module")
def committed():
    return curve_comparisons(BASELINES)


def test_every_committed_main_task_record_is_drawn_once(committed):
    comparisons, images = committed
    assert {c["environment"] for c in comparisons} == MAIN_TASKS
    assert set(images) == {f"images/curves/{env}.png" for env in MAIN_TASKS}
    assert all(image.dtype == np.uint8 and image.ndim == 3 and image.shape[2] == 3 for image in images.values())


def test_the_records_trained_at_the_appendix_budget_say_so(committed):
    by_env = {c["environment"]: c for c in committed[0]}
    # the configs that ran: DBR 1.2M and WRM 450k agent-steps; the records trained the appendix's 2M and 4.5M
    assert by_env["drone_based_reforestation"]["record_which"] == "the paper appendix"
    assert by_env["drone_based_reforestation"]["record_differs"].startswith(
        "The budgets differ: the original trained 1,200,000 (the config that ran, which its curves' axes follow), "
        "this record 2,000,000;")
    assert by_env["wildfire_resource_management"]["record_differs"].startswith(
        "The budgets differ: the original trained 450,000 (the config that ran, which its curves' axes follow), "
        "this record 4,500,000;")
    assert {env for env, c in by_env.items() if c["record_differs"]} == {"drone_based_reforestation",
                                                                        "wildfire_resource_management"}


def test_whose_budget_a_max_steps_is():
    assert budget_source("wind_farm_control", 8_000_000) == "the config that ran"
    assert budget_source("drone_based_reforestation", 2_000_000) == "the paper appendix"
    assert budget_source("drone_based_reforestation", 1_200_000) == "the config that ran"
    assert budget_source("drone_based_reforestation", 300_000) == "its own"


def test_a_record_without_a_curve_is_not_drawn(tmp_path):
    record = json.loads((BASELINES / "wind_farm_control.json").read_text())
    (tmp_path / "wind_farm_control.json").write_text(json.dumps(record | {"curve": []}))
    assert curve_comparisons(tmp_path) == ([], {})
    assert curve_comparisons(tmp_path / "missing") == ([], {})


def test_both_pages_show_the_measure_and_the_figure(committed):
    comparisons, _ = committed
    jinja = _jinja()
    baselines = jinja.get_template("baselines.md.j2").render(**baselines_context(BASELINES, comparisons))
    fidelity = jinja.get_template("fidelity.md.j2").render(**fidelity_context(Path("-")), comparisons=comparisons)
    for page in (baselines, fidelity):
        for env in MAIN_TASKS:
            assert f"](images/curves/{env}.png)" in page
        assert "| Cumulative Reward | 100% | 8,000,000 |" in page  # WFC's budget, the config that ran
        assert "the original trained 1,200,000 (the config that ran" in page
    assert "## Learning curves beside the original's" in fidelity
    assert "| `max_steps` | 8000000 | 450000 (appendix: 4500000) |" in baselines
    assert "(2,000,000: the paper appendix)" in baselines


def test_the_fidelity_page_has_no_curve_section_without_records():
    page = _jinja().get_template("fidelity.md.j2").render(**fidelity_context(Path("-")), comparisons=[])
    assert "Learning curves beside the original's" not in page


def test_the_grids_say_whose_budget_they_trained():
    page = _jinja().get_template("baselines.md.j2").render(**baselines_context(BASELINES))
    # the committed WRM grid trained the appendix's 4.5M agent-steps a point, the WFC grid the 8M of both
    assert "(4,500,000 agent-steps each, the max_steps of the paper appendix; training" in page
    assert "(8,000,000 agent-steps each, the max_steps of the config that ran; training" in page
