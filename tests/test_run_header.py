"""`hivex run`'s column headers show a term's weight as written: a schedule, not its value at step 0."""

from __future__ import annotations

import pytest

import hivex_dsl
from hivex_dsl.cli import main
from hivex_dsl.evaluation.report import weight_label

YAW = {"title": "Yaw Change", "expr": "where(abs(delta(heading_rad)) > 0.001, 1, 0)", "sign": "bonus"}


def scenario(schedule: dict) -> hivex_dsl.CompiledScenario:
    return hivex_dsl.compile({"hivex": 1, "environment": "wind_farm_control", "agents": 2, "episode_length": 10,
                              "terms": {"yaw_change": YAW},
                              "weights": {"generate_energy": 0.5, "yaw_change": schedule}})


@pytest.mark.parametrize("schedule, label", [
    ({"from": 0.0, "to": -0.2, "over_steps": 1_000_000}, "x0→-0.2 over 1e6"),
    ({"from": 0.1, "to": 1.0, "over_steps": 150_000, "kind": "linear"}, "x0.1→1 over 1.5e5"),
    ({"from": 1.0, "to": 0.0, "over_steps": 1_234_567, "kind": "step"}, "x1→0 at 1,234,567"),
    ({"from": 1.0, "to": 2.0, "over_steps": 500}, "x1→2 over 500"),
])
def test_a_scheduled_weight_is_labelled_by_its_schedule(schedule, label):
    compiled = scenario(schedule)
    assert weight_label(compiled, "yaw_change") == label
    assert weight_label(compiled, "generate_energy") == "x0.5"


def test_the_run_table_heads_a_scheduled_term_with_its_schedule(tmp_path, capsys):
    path = tmp_path / "yaw.yaml"
    path.write_text("hivex: 1\nname: yaw\nenvironment: wind_farm_control\nagents: 2\nepisode_length: 10\n"
                    "terms:\n  yaw_change: {expr: 'where(abs(delta(heading_rad)) > 0.001, 1, 0)', sign: bonus}\n"
                    "weights:\n  yaw_change: {from: 0.0, to: -0.2, over_steps: 1000000}\n")
    assert main(["run", str(path)]) == 0
    header = capsys.readouterr().out.splitlines()[1]
    assert "generate_energy (x1)" in header and "yaw_change (x0→-0.2 over 1e6)" in header
    assert "(x0)" not in header
