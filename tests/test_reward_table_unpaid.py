"""A task column's ``unpaid`` terms: logged in the statistics at the matrix's weight, not added to the reward.

Only Ocean Plastic Collection's Avoid Plastic lists one (Collect Trash: the reward table's Local note); every
other task lists none, and their compiled scenarios, rewards and fingerprints are what they were without the field.
"""

from __future__ import annotations

from dataclasses import replace

import pytest

import hivex_dsl
from hivex_dsl.compiler import registry
from hivex_dsl.lang.spec.reward_table import table_problems


def opc_table():
    return registry.get("ocean_plastic_collection").reward_table


def problems_with(task: int, unpaid: list[str]) -> list[str]:
    entry = registry.get("ocean_plastic_collection")
    table = opc_table()
    tasks = list(table.tasks)
    tasks[task] = tasks[task].model_copy(update={"unpaid": tuple(unpaid)})
    changed = table.model_copy(update={"tasks": tuple(tasks)})
    return [message for _, message in table_problems(changed, entry.id, entry.term_names, tuple(entry.events))]


def test_an_unpaid_term_must_have_a_weight_to_log():
    assert problems_with(3, ["collect_trash"]) == []
    # Avoid Plastic weighs Nearby Trash Count Delta 0: there is nothing to log
    assert problems_with(3, ["nearby_trash_count_delta"]) == [
        "unpaid term 'nearby_trash_count_delta' has no non-zero weight in task 'avoid_plastic': nothing to log"]


@pytest.mark.parametrize("env_id", [e for e in registry.environments()])
def test_only_avoid_plastic_lists_an_unpaid_term(env_id):
    listed = {task.name: task.unpaid for task in registry.get(env_id).reward_table.tasks if task.unpaid}
    assert listed == ({"avoid_plastic": ("collect_trash",)} if env_id == "ocean_plastic_collection" else {})


def test_the_unpaid_term_changes_the_fingerprint_of_its_task_alone():
    """The fingerprint holds the unpaid terms only where a task lists some, so every other scenario keeps its own."""
    def compiled(task: int):
        return hivex_dsl.compile({"hivex": 1, "environment": "ocean_plastic_collection", "task": task})

    avoid, main = compiled(3), compiled(0)
    assert avoid.unpaid == {"collect_trash"} and main.unpaid == frozenset()
    assert avoid.weights["collect_trash"] == -1.0  # the matrix's weight stays: the statistics log with it
    assert replace(avoid, unpaid=frozenset()).fingerprint != avoid.fingerprint
    assert replace(main, unpaid=frozenset({"collect_trash"})).fingerprint != main.fingerprint
