"""`hivex audit` checks a scenario's expression terms like registered ones (their contracts come from the scenario)."""

from __future__ import annotations

import hivex_dsl
from hivex_dsl.evaluation.audit import audit_scenario


def test_the_audit_flags_an_expression_term_the_actions_do_not_change():
    compiled = hivex_dsl.compile({
        "hivex": 1, "environment": "wind_farm_control", "agents": 3, "episode_length": 30,
        "params": {"rotation_speed_deg": 30.0},  # at 0.1 degrees a step, 30 steps leave the actions no effect
        "terms": {"steady": "x_m / 600 + 1", "yaw_change": "where(abs(delta(heading_rad)) > 0.001, 1, 0)"},
        "weights": {"yaw_change": -0.2}})
    audit = audit_scenario(compiled, episodes=1)
    assert set(audit.rollouts["scripted"].terms) == {"generate_energy", "steady", "yaw_change"}
    assert [(f.kind, f.term) for f in audit.flags] == [("action_independent", "steady")]
