"""The fidelity suite and page: the stored measurements are not stale, and the page shows them beside the paper."""

from __future__ import annotations

from pathlib import Path

import pytest

from hivex_dsl.evaluation import published
from hivex_dsl.compiler import registry
from hivex_dsl.evaluation.audit import AUDIT_POLICIES, audit_all
from hivex_dsl.docsgen import render_docs
from hivex_dsl.evaluation.fidelity import FIDELITY_FILE, load_suite, published_level_mean, suite_scenarios

ROOT = Path(__file__).resolve().parents[1]
STORED = load_suite(ROOT / FIDELITY_FILE)
# re-measured on every test run: whole environments whose episodes are cheap, one cheap DBR task (its episode
# ends when the drones are back at the station), and one task of each of AWS and OPC, so that every
# environment's simulator and scripted policy is covered; under a minute of CPU in all
CHEAP = ("wrm-main-l1", "wrm-keep-all-l1", "wrm-distribute-all-l1", "wfc-generate-energy-p0",
         "wfc-avoid-damage-p0", "dbr-drop-seed-l1", "aws-main-l1", "opc-avoid-plastic")


def test_the_suite_is_the_whole_published_grid_and_every_task_at_its_first_level():
    compiled = suite_scenarios()
    # the published file: WFC 2 tasks x 9 patterns, WRM 3 x 10 levels, OPC 4 tasks, DBR 7 x 10, AWS 9 x 10
    published_cells = 18 + 30 + 4 + 70 + 90
    assert sum(len(published.cells(env)) for env in published.environments()) == published_cells
    # and Drone-Based Reforestation's Group Up, which the paper published nothing for, at terrain level 1
    assert len(compiled) == published_cells + 1
    keys = {(c.environment, c.task_index, c.level) for c in compiled}
    assert len(keys) == len(compiled)
    assert {c.level for c in compiled if c.environment == "wind_farm_control"} == set(range(9))
    assert {c.level for c in compiled if c.environment == "aerial_wildfire_suppression"} == set(range(1, 11))
    assert ("drone_based_reforestation", 2, 1) in keys
    assert all(c.seeds.test == 6000 for c in compiled)
    first = suite_scenarios(first_only=True)
    # every task of the environments the paper published cells for; an environment it published none for adds none
    with_cells = [entry for env_id, entry in registry.environments().items() if published.cells(env_id)]
    assert {entry.id for entry in with_cells} == set(published.environments())
    assert len(first) == sum(len(entry.reward_table.tasks) for entry in with_cells) == 26
    assert all(c.level in (None, 0, 1) for c in first)


def test_the_stored_suite_was_measured_on_the_scenarios_as_they_are_now():
    assert STORED is not None, f"run `hivex audit --suite -o {FIDELITY_FILE}`"
    stored = {row["scenario"]: row["fingerprint"] for row in STORED["scenarios"]}
    now = {c.name: c.fingerprint for c in suite_scenarios()}
    assert stored == now, f"stale: run `hivex audit --suite -o {FIDELITY_FILE}` and `hivex docs`"


def test_the_stored_numbers_are_what_the_code_measures_now():
    """The cheap part of the suite re-measured: any change of its terms, simulator or policies shows here."""
    rows = {row["scenario"]: row for row in STORED["scenarios"] if row["scenario"] in CHEAP}
    compiled = [c for c in suite_scenarios(first_only=True) if c.name in CHEAP]
    fresh = [audit_all([c], rows[c.name]["episodes"], quiet=True)[0].as_dict() for c in compiled]  # each row's count
    assert len(fresh) == len(rows) == len(CHEAP)
    for audit in fresh:
        stored = rows[audit["scenario"]]
        assert (audit["flags"], audit["notes"]) == (stored["flags"], stored["notes"])
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
    assert published_level_mean("drone_based_reforestation", 2) is None  # Group Up: no published cell


def test_the_page_shows_ours_beside_the_published_cell_and_the_readings():
    page = render_docs(None, ROOT / FIDELITY_FILE)["fidelity.md"]
    assert "| WRM | 0 `main` | 93.92 |" in page
    assert "| Reward for Moving Resources to Neighbours | 49.37 |" in page
    assert "Save Location Count" in page  # listed as not computed, with why
    for entry in registry.environments().values():
        for note in entry.reward_table.notes:
            assert note.split()[0] in page
    assert published.notes()[1][:60] in page


def test_a_cell_is_beaten_when_a_trivial_policy_earns_more_than_the_published_ppo():
    from hivex_dsl.docsgen.fidelity_page import beaten

    ppo = published.cell("aerial_wildfire_suppression", 5, 3).return_mean  # Pick Up Water, level 3: 94.67
    audit = {"environment": "aerial_wildfire_suppression", "task_index": 5, "level": 3, "episodes": 4,
             "policies": {"zeros": {"return": {"mean": ppo - 1, "std": 0.0}},
                          "random": {"return": {"mean": ppo + 0.01, "std": 0.0}}}}
    assert beaten(audit)
    audit["policies"]["random"]["return"]["mean"] = ppo
    assert not beaten(audit)  # a tie is not beaten
    assert not beaten(audit | {"environment": "drone_based_reforestation", "task_index": 2, "level": 1})  # no cell


def test_a_near_tie_within_the_standard_error_is_not_a_win():
    """Issue 52: the suite's few test episodes flipped verdicts in near ties. A lead counts only beyond the standard
    error of the trivial policy's mean, its spread over the square root of the episode count (by hand below)."""
    from hivex_dsl.docsgen.fidelity_page import beaten, standard_error

    ppo = published.cell("wildfire_resource_management", 0, 6).return_mean  # WRM main task, level 6: 107.97
    random = {"mean": ppo + 1.34, "std": 17.33}  # what two test episodes gave (stored before issue 52)
    audit = {"environment": "wildfire_resource_management", "task_index": 0, "level": 6, "episodes": 2,
             "policies": {"zeros": {"return": {"mean": 61.5, "std": 10.0}}, "random": {"return": random}}}
    assert standard_error(audit, "random") == pytest.approx(17.33 / 2 ** 0.5)  # 12.25
    assert not beaten(audit)  # 1.34 ahead, a tenth of its standard error: a tie
    audit["episodes"] = 200  # the same lead and spread over 200 episodes: a standard error of 1.23, below the lead
    assert beaten(audit)
    random["mean"] = ppo + 12.0  # two episodes, a lead just under the standard error: still a tie
    audit["episodes"] = 2
    assert not beaten(audit)
    random["mean"] = ppo + 12.5  # just over it: beaten
    assert beaten(audit)


def test_evidence_is_stated_exactly_for_the_tasks_with_a_beaten_cell():
    """Every task where the stored audit finds a trivial policy above the paper's PPO says why in its reward table
    (`trivial_beats_ppo`), and no task keeps such a statement after its cells stop being beaten."""
    from hivex_dsl.docsgen.fidelity_page import beaten

    beaten_tasks = {(row["environment"], row["task"]) for row in STORED["scenarios"] if beaten(row)}
    stated = {(env_id, task.name) for env_id, entry in registry.environments().items()
              for task in entry.reward_table.tasks if task.trivial_beats_ppo}
    assert beaten_tasks == stated
    assert ("ocean_plastic_collection", "avoid_plastic") in beaten_tasks  # 0 is Avoid Plastic's best return


def test_the_page_shows_the_whole_grid_with_the_beaten_cells_marked():
    page = render_docs(None, ROOT / FIDELITY_FILE)["fidelity.md"]
    assert "### Aerial Wildfire Suppression: 90 published cells," in page
    assert "### Wind Farm Control: 18 published cells, 0 beaten by a trivial policy" in page
    rows = {row["scenario"]: row for row in STORED["scenarios"]}
    avoid = rows["opc-avoid-plastic"]
    assert f"| 3 `avoid_plastic` | **-2.039 / 0 / {avoid['policies']['scripted']['return']['mean']:,.4g}** ⚠ |" in page
    # one row per task, one column per pattern: WFC's nine
    (header,) = [line for line in page.splitlines() if line.startswith("| Task | pattern 0 |")]
    assert header.count("pattern") == 9
    # issue 52: over 10 test episodes random play beats AWS's published Protect Village at level 1 (33.3 against
    # -69.6, the original's PPO crashing) and a straight flight its Pick Up Water at level 1 (95.0 against 93.0: about
    # 94 expected by hand, the published cell below the original's own test curve), each with the reason its reward
    # table states; since the release's weather (session 94) Protect Village and Drop Water at level 5, beaten under
    # this toolkit's weather on their first ten episodes (232.3 and 356.7 against 172.3 and 274.5; over 40 episodes
    # 197.6 and 262.9), are ties, and Drop Water states no reason any more; WRM's main task, beaten at level 10 while
    # a tower's performance read the fire alone (112.6 against 103.7), is not since it reads the resources the towers
    # hold
    assert "### Aerial Wildfire Suppression: 90 published cells, 2 beaten by a trivial policy" in page
    for tie in ("task 4 `protect_village` at level 5 (random 197.2 ± 64.64 against 172.3)",
                "task 6 `drop_water` at level 5 (random 282.6 ± 61.46 against 274.5)",
                "task 8 `find_village` at level 9 (random 20 ± 46.48 against 4.583)"):
        assert tie in page
    assert "- Task 4 `protect_village`, beaten by a trivial policy: At level 1 the random policy earns" in page
    assert "- Task 5 `pick_up_water`, beaten by a trivial policy: At level 1 the all-zeros policy" in page
    assert "`drop_water`, beaten by a trivial policy" not in page
    assert "### Wildfire Resource Management: 30 published cells, 0 beaten by a trivial policy" in page


def test_a_trivial_lead_within_the_standard_error_is_listed_as_a_tie():
    """Issue 52's last condition: a trivial policy above the published PPO is either beaten (bold, with its reading)
    or a tie within the standard error, which the page lists by name with its numbers (worked by hand below)."""
    from hivex_dsl.docsgen.fidelity_page import beaten, ties

    ppo = published.cell("aerial_wildfire_suppression", 5, 3).return_mean  # Pick Up Water, level 3: 94.67
    random = {"mean": ppo + 1.0, "std": 4.0}  # 4 episodes: a standard error of 2.0, twice the lead
    audit = {"environment": "aerial_wildfire_suppression", "task_index": 5, "level": 3, "episodes": 4,
             "policies": {"zeros": {"return": {"mean": ppo - 1.0, "std": 0.0}}, "random": {"return": random}}}
    assert not beaten(audit)
    assert ties(audit) == [{"policy": "random", "mean": f"{ppo + 1.0:,.4g}", "error": "2", "ppo": f"{ppo:,.4g}"}]
    random["mean"] = ppo + 2.5  # beyond the error: beaten, no longer a tie
    assert beaten(audit) and ties(audit) == []
    random["mean"] = ppo - 0.5  # below the PPO: neither
    assert not beaten(audit) and ties(audit) == []
    assert ties(audit | {"environment": "drone_based_reforestation", "task_index": 2, "level": 1}) == []  # no cell
