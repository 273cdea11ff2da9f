"""A reward table may declare expression terms and expression endings, like a scenario."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest

import hivex_dsl
from hivex_dsl.compiler import registry
from hivex_dsl.base.errors import ScenarioError
from hivex_dsl.lang.loader import load_file
from hivex_dsl.base.resources import data_dir
from hivex_dsl.runtime import BatchedEnv

WFC = "wind_farm_control"


def _with_table(monkeypatch, tmp_path: Path, terms: str, ends_on: str, rows: str):
    """Wind Farm Control with its reward table extended by ``terms``, task 0's ``ends_on`` and matrix ``rows``."""
    text = (data_dir("rewards") / f"{WFC}.yaml").read_text()
    text = text.replace("matrix:\n", f"terms:\n{terms}matrix:\n{rows}", 1)
    text = text.replace("    name: generate_energy\n", f"    name: generate_energy\n    ends_on: {ends_on}\n", 1)
    path = tmp_path / f"{WFC}.yaml"
    path.write_text(text)
    entry = dataclasses.replace(registry.get(WFC))
    entry.__dict__["reward_table_file"] = load_file(path)
    entry.__dict__["reward_table"] = registry.load_reward_table(entry)
    monkeypatch.setitem(registry._REGISTRY, WFC, entry)
    return path


def test_table_terms_are_weighted_by_their_row_and_table_endings_end_agents(monkeypatch, tmp_path):
    _with_table(monkeypatch, tmp_path, "  facing_wind:\n    expr: alignment\n",
                "['team_min(alignment) > -1']", "  facing_wind: [0.5, 0]\n")
    compiled = hivex_dsl.compile({"hivex": 1, "environment": WFC, "agents": 2})
    assert compiled.weights["facing_wind"] == 0.5
    assert "facing_wind" in {c.name for c in compiled.term_contracts}
    env = BatchedEnv(compiled, batch=2)
    env.reset(seed=1)
    transition = env.step(np.zeros(env.shape, int))
    assert transition.ended.all()  # team_min(alignment) > -1 always holds: every agent ends after one step
    np.testing.assert_allclose(transition.rewards,
                               transition.terms["generate_energy"] + 0.5 * transition.terms["facing_wind"], atol=1e-12)
    other_task = hivex_dsl.compile({"hivex": 1, "environment": WFC, "task": 1})
    assert other_task.weights["facing_wind"] == 0.0 and other_task.expressions.endings == ()  # task 1 ends on time


def test_a_table_expression_mistake_is_located_in_the_table(monkeypatch, tmp_path):
    path = _with_table(monkeypatch, tmp_path, "  facing_wind:\n    expr: alignmnt + 1\n", "[]",
                       "  facing_wind: [1, 0]\n")
    with pytest.raises(ScenarioError) as caught:
        hivex_dsl.compile({"hivex": 1, "environment": WFC})
    problem = caught.value.first
    line = path.read_text().split("\n").index("    expr: alignmnt + 1") + 1
    assert (problem.location.path, problem.location.line, problem.location.col) == (str(path), line, 11)
    assert "unknown quantity 'alignmnt'; did you mean 'alignment'?" in problem.message


def test_a_table_term_may_not_shadow_a_registered_one(monkeypatch, tmp_path):
    with pytest.raises(ScenarioError, match="'avoid_damage' is already a registered reward term"):
        _with_table(monkeypatch, tmp_path, "  avoid_damage:\n    expr: alignment\n", "[]", "")
