"""The fidelity suite and page: the stored measurements are not stale, and the page shows them beside the paper."""

from __future__ import annotations

from pathlib import Path

import pytest

from hivex_dsl import published, registry
from hivex_dsl.audit import AUDIT_POLICIES, audit_all
from hivex_dsl.docsgen import render_docs
from hivex_dsl.fidelity import FIDELITY_FILE, load_suite, published_level_mean, suite_scenarios

ROOT = Path(__file__).resolve().parents[1]
STORED = load_suite(ROOT / FIDELITY_FILE)
CHEAP = "wildfire_resource_management"  # short episodes: re-measured in full on every test run


def test_the_suite_is_every_task_of_every_environment_at_level_1():
    compiled = suite_scenarios()
    expected = sum(len(entry.reward_table.tasks) for entry in registry.environments().values())
    assert len(compiled) == expected == 26
    assert {(c.environment, c.level) for c in compiled if c.environment == "wind_farm_control"} == {
        ("wind_farm_control", 0)}
    assert all(c.level in (None, 0, 1) for c in compiled)
    assert all(c.seeds.test == 6000 for c in compiled)


def test_the_stored_suite_was_measured_on_the_scenarios_as_they_are_now():
    assert STORED is not None, f"run `hivex audit --suite -o {FIDELITY_FILE}`"
    stored = {row["scenario"]: row["fingerprint"] for row in STORED["scenarios"]}
    now = {c.name: c.fingerprint for c in suite_scenarios()}
    assert stored == now, f"stale: run `hivex audit --suite -o {FIDELITY_FILE}` and `hivex docs`"


def test_the_stored_numbers_are_what_the_code_measures_now():
    """The cheap part of the suite re-measured: any change of its terms, simulator or policies shows here."""
    rows = {row["scenario"]: row for row in STORED["scenarios"] if row["environment"] == CHEAP}
    compiled = suite_scenarios([CHEAP])
    fresh = [a.as_dict() for a in audit_all(compiled, STORED["episodes"], quiet=True)]
    assert len(fresh) == len(rows) == 3
    for audit in fresh:
        stored = rows[audit["scenario"]]
        assert audit["flags"] == stored["flags"]
        for policy in AUDIT_POLICIES:
            assert flat(audit["policies"][policy]) == pytest.approx(flat(stored["policies"][policy]), rel=1e-9,
                                                                     abs=1e-12)


def flat(tree: dict, prefix: str = "") -> dict[str, float]:
    """{"a": {"b": 1.0}} -> {"a/b": 1.0}: pytest.approx compares flat mappings only."""
    out = {}
    for key, value in tree.items():
        if isinstance(value, dict):
            out |= flat(value, f"{prefix}{key}/")
        else:
            out[f"{prefix}{key}"] = value
    return out


def test_published_level_mean_by_hand():
    # Ocean Plastic Collection has one level: the mean is the cell itself
    assert published_level_mean("ocean_plastic_collection", 3)["return"] == pytest.approx(-2.0388)
    # Wind Farm Control Avoid Damage: the nine patterns' returns from the file, averaged
    returns = [c.return_mean for c in published.cells("wind_farm_control") if c.task_index == 1]
    assert len(returns) == 9
    assert published_level_mean("wind_farm_control", 1)["return"] == pytest.approx(sum(returns) / 9)
    assert published_level_mean("drone_based_reforestation", 4) is None


def test_the_page_shows_ours_beside_the_published_cell_and_the_readings():
    page = render_docs(None, ROOT / FIDELITY_FILE)["fidelity.md"]
    assert "| WRM | 0 `main` | 93.92 |" in page
    assert "| Reward for Moving Resources to Neighbours | 49.37 |" in page
    assert "Cumulative Distance to Existing Trees" in page  # listed as not computed, with why
    for entry in registry.environments().values():
        for note in entry.reward_table.notes:
            assert note.split()[0] in page
    assert published.notes()[1][:60] in page
