"""`hivex audit`: hand-made terms that must raise each flag, and well-behaved ones that must not."""

from __future__ import annotations

import dataclasses
import json
from types import MappingProxyType

import numpy as np
import pytest

import hivex_dsl
from hivex_dsl.evaluation import published
from hivex_dsl.evaluation.audit import AUDIT_POLICIES, ScenarioAudit, audit_scenario, describe, find_flags
from hivex_dsl.cli import main
from hivex_dsl.sim.reward.terms import TermRegistry
from hivex_dsl.evaluation.rollout import Rollout, TermTrace

EPISODE = 30
# the faster world these audits were written for: at the default 0.1 degrees a step, 30 steps leave the actions
# next to no effect on the energy
EARLIER_WORLD = {"rotation_speed_deg": 2.0, "initial_heading_spread_deg": 360.0, "wind_ease_rate": 0.01,
             "wind_drift_m": 1.0, "episodes_continue": 0}


def _terms(*specs):
    """A WFC term registry of (name, fn, contract fields) triples."""
    registry = TermRegistry("wind_farm_control")
    for name, fn, contract in specs:
        registry.term(name, title=name, description=name, **contract)(fn)
    return registry


def _compiled(registry, weights, task="generate_energy"):
    """WFC (3 turbines, pattern 0: a published cell) whose reward is the hand-made terms with ``weights``."""
    compiled = hivex_dsl.compile({"hivex": 1, "environment": "wind_farm_control", "task": task, "agents": 3,
                                  "episode_length": EPISODE, "params": EARLIER_WORLD})
    entry = dataclasses.replace(compiled.entry, terms=registry)
    entry.__dict__["reward_table"] = compiled.entry.reward_table  # the real table: its rows name the real terms
    return dataclasses.replace(compiled, entry=entry, weights=MappingProxyType(weights))


def _kinds(audit, term=None):
    return {f.kind for f in audit.flags if term is None or f.term == term}


DENSE = dict(low=0.0, high=1.0, sign="bonus", timing="dense", scope="agent")


def turning(prev, state, actions, params):
    return (np.asarray(actions) == 1).astype(np.float64)


def steady(prev, state, actions, params):
    return np.ones(state.heading.shape)


def energy(prev, state, actions, params):
    return np.clip(state.performance, 0.0, 1.0)


@pytest.fixture
def as_if_reproduced(monkeypatch):
    """These short, few-agent scenarios with terms of their own reproduce no published cell (their audit says so,
    below); to test the flags that compare with a cell, they are audited as if they reproduced their task's."""
    monkeypatch.setattr(published, "cell_for", published.paper_cell)


def test_a_well_behaved_reward_raises_no_flag(as_if_reproduced):
    audit = audit_scenario(_compiled(_terms(("turning", turning, DENSE), ("energy", energy, DENSE)),
                                     {"turning": 0.2, "energy": 1.0}))
    assert audit.flags == []
    assert audit.cell is not None and audit.cell.return_mean == pytest.approx(4611.6462)


def test_a_term_the_actions_do_not_change_is_flagged_when_it_matters():
    audit = audit_scenario(_compiled(_terms(("turning", turning, DENSE), ("steady", steady, DENSE)),
                                     {"turning": 1.0, "steady": 1.0}))
    assert _kinds(audit, "steady") == {"action_independent"}
    assert "action_independent" not in _kinds(audit, "turning")
    tiny = audit_scenario(_compiled(_terms(("turning", turning, DENSE), ("steady", steady, DENSE)),
                                    {"turning": 1.0, "steady": 0.001}))
    assert "action_independent" not in _kinds(tiny)  # 0.1% of the return does not matter


def test_a_global_term_the_actions_do_not_change_is_a_note():
    world = dict(DENSE, scope="global")
    audit = audit_scenario(_compiled(_terms(("turning", turning, DENSE), ("steady", steady, world)),
                                     {"turning": 1.0, "steady": 1.0}))
    assert "action_independent" not in _kinds(audit)
    assert [(n.kind, n.term) for n in audit.notes] == [("action_independent", "steady")]
    assert "note action_independent: steady" in describe(audit.as_dict())


def test_reward_on_the_first_step_after_reset_is_flagged_for_events_only():
    def from_reset(prev, state, actions, params):
        return (prev.performance == 0.0).astype(np.float64)

    event = dict(DENSE, timing="event")
    audit = audit_scenario(_compiled(_terms(("turning", turning, DENSE), ("from_reset", from_reset, event)),
                                     {"turning": 1.0, "from_reset": 0.01}))
    assert "first_step" in _kinds(audit, "from_reset")
    dense = audit_scenario(_compiled(_terms(("turning", turning, DENSE), ("from_reset", from_reset, DENSE)),
                                     {"turning": 1.0, "from_reset": 0.01}))
    assert "first_step" not in _kinds(dense)


def test_a_dominant_term_is_flagged():
    audit = audit_scenario(_compiled(_terms(("turning", turning, DENSE), ("energy", energy, DENSE)),
                                     {"turning": 0.001, "energy": 1.0}))
    assert _kinds(audit, "energy") == {"dominant"}


def test_the_one_bonus_of_a_task_dominates_nothing():
    def cost(prev, state, actions, params):
        return -(np.asarray(actions) == 2).astype(np.float64)

    penalty = dict(DENSE, sign="penalty", low=-1.0, high=0.0)
    audit = audit_scenario(_compiled(_terms(("energy", energy, DENSE), ("cost", cost, penalty)),
                                     {"energy": 1.0, "cost": 0.001}))
    assert "dominant" not in _kinds(audit)


@pytest.mark.parametrize("value, contract, kind", [
    (2.0, DENSE, "contract_range"),
    (-1.0, DENSE, "contract_sign"),
    (0.5, dict(DENSE, sign="mixed", low=-1.0), None),
    (1.0, dict(DENSE, timing="terminal"), "contract_timing"),
    (1.0, dict(DENSE, timing="event"), "contract_timing"),
])
def test_contract_violations(value, contract, kind):
    def constant_when_turning(prev, state, actions, params):
        return value * turning(prev, state, actions, params) + 0.5 * (value < 0) * 0

    def paid(prev, state, actions, params):
        return np.full(state.heading.shape, value)

    audit = audit_scenario(_compiled(_terms(("turning", turning, DENSE), ("paid", paid, contract)),
                                     {"turning": 10.0, "paid": 0.01}))
    contract_kinds = {k for k in _kinds(audit, "paid") if k.startswith("contract")}
    assert contract_kinds == ({kind} if kind else set())


def test_a_trivial_policy_beating_published_ppo_and_a_far_scale_are_flagged(as_if_reproduced):
    big = audit_scenario(_compiled(_terms(("turning", turning, DENSE), ("steady", steady, DENSE)),
                                   {"turning": 1.0, "steady": 200.0}))  # 6000 per episode > 4611.6 + 10%
    assert {f.policy for f in big.flags if f.kind == "beats_published"} == {"zeros", "random"}
    assert "published_scale" not in _kinds(big)
    huge = audit_scenario(_compiled(_terms(("turning", turning, DENSE), ("steady", steady, DENSE)),
                                    {"turning": 1.0, "steady": 2000.0}))
    assert {f.policy for f in huge.flags if f.kind == "published_scale"} == {"zeros", "random"}


def test_text_and_json_reports_show_published_statistics_beside_ours(as_if_reproduced):
    audit = audit_scenario(hivex_dsl.compile({"hivex": 1, "environment": "wind_farm_control", "agents": 2,
                                              "episode_length": EPISODE, "params": EARLIER_WORLD}), episodes=1)
    data = audit.as_dict()
    assert data["published"]["return"]["mean"] == pytest.approx(4611.6462)
    ours = data["policies"]["scripted"]
    assert ours["statistics"]["Individual Performance"]["mean"] == pytest.approx(ours["return"]["mean"])
    assert ours["terms"]["generate_energy"]["share"] == pytest.approx(1.0)
    text = describe(data)
    assert "Individual Performance" in text and "published PPO" in text
    json.dumps(data)  # plain data


def test_the_command_prints_json_and_strict_fails_on_flags(tmp_path, capsys):
    scenario = tmp_path / "wfc.yaml"
    scenario.write_text("hivex: 1\nenvironment: wind_farm_control\nagents: 2\nepisode_length: 20\n"
                        "sweep:\n  pattern: [0, 1]\n")
    assert main(["audit", str(scenario), "--episodes", "1", "--json"]) == 0
    out, err = capsys.readouterr()
    audits = json.loads(out)
    assert [a["level"] for a in audits] == [0, 1]
    assert err == ""  # no progress under --json (nor where stderr is not a terminal)
    strict = main(["audit", str(scenario), "--episodes", "1", "--strict"])
    assert strict == (1 if any(a["flags"] for a in audits) else 0)


def test_the_command_wants_a_file_or_the_suite(capsys):
    assert main(["audit"]) == 2
    assert main(["audit", "wind_farm_control/main", "--suite"]) == 2
    assert "give a scenario FILE or --suite" in capsys.readouterr().err


def test_only_is_refused_without_the_suite(capsys):
    assert main(["audit", "wind_farm_control/main", "--only", "wind_farm_control"]) == 2
    assert "--only picks environments of the --suite" in capsys.readouterr().err


def _row(environment, scenario, value, episodes=3):
    return {"environment": environment, "scenario": scenario, "value": value, "flags": [], "episodes": episodes}


@pytest.mark.parametrize("asked", [None, 7])
def test_only_remeasures_one_environment_and_keeps_every_other_row_in_suite_order(tmp_path, monkeypatch, asked):
    """A stored report of three environments; --only ocean_plastic_collection re-measures that one, at the stored
    episode count or at --episodes where given (issue 52: a changed environment re-measured at the suite's 10 while
    the rest keep theirs), and writes the others back untouched, in the registry's order. Each row keeps its own
    count; the report's is the fewest of any row."""
    from hivex_dsl.evaluation import fidelity

    stored = {"hivex_fidelity": 1, "episodes": 3, "split": "test", "scenarios": [
        _row("wind_farm_control", "wfc-a", 1), _row("ocean_plastic_collection", "opc-old", 2),
        _row("aerial_wildfire_suppression", "aws-a", 3)]}
    output = tmp_path / "fidelity.json"
    fidelity.write_suite(stored, output)
    calls = []

    def fake_measure(episodes, environments, stream=None, quiet=False):
        calls.append((episodes, environments))
        return {"scenarios": [_row("ocean_plastic_collection", "opc-new", 20, episodes),
                              _row("ocean_plastic_collection", "opc-new-2", 21, episodes)]}

    monkeypatch.setattr(fidelity, "measure_suite", fake_measure)
    more = ["--episodes", str(asked)] if asked else []
    assert main(["audit", "--suite", "--only", "ocean_plastic_collection", *more, "-o", str(output), "--json"]) == 0
    assert calls == [(asked or 3, ["ocean_plastic_collection"])]
    written = fidelity.load_suite(output)
    assert [r["scenario"] for r in written["scenarios"]] == ["wfc-a", "opc-new", "opc-new-2", "aws-a"]
    assert [r["episodes"] for r in written["scenarios"]] == [3, asked or 3, asked or 3, 3]
    assert {k: v for k, v in written.items() if k != "scenarios"} == {"hivex_fidelity": 1, "episodes": 3,
                                                                      "split": "test"}


def test_a_fresh_suite_measures_the_suites_standard_episode_count_and_a_file_two(tmp_path, monkeypatch):
    """Issue 52: two test episodes flipped the suite's verdicts in near ties; the suite measures ten by default,
    while a scenario FILE's quick audit keeps two."""
    from hivex_dsl.evaluation import audit, fidelity

    calls = []
    monkeypatch.setattr(fidelity, "measure_suite", lambda episodes, environments, stream=None, quiet=False: (
        calls.append(episodes) or {"hivex_fidelity": 1, "episodes": episodes, "split": "test", "scenarios": []}))
    assert main(["audit", "--suite", "--only", "ocean_plastic_collection", "-o", str(tmp_path / "f.json")]) == 0
    assert calls == [10]
    monkeypatch.setattr(audit, "audit_all", lambda compiled, episodes, **kw: calls.append(episodes) or [])
    assert main(["audit", "wind_farm_control/main"]) == 0
    assert calls == [10, 2]


def test_only_an_unknown_environment_is_refused_with_the_choices(capsys):
    with pytest.raises(SystemExit):
        main(["audit", "--suite", "--only", "ocean_plastic"])
    assert "invalid choice: 'ocean_plastic'" in capsys.readouterr().err


def _ending_term_audit(lengths_by_policy, before_end=0):
    """An audit of three hand-made rollouts in which term ``pick`` pays 1 once per episode under every policy,
    on the step that ends it (``before_end`` payments did not), after episodes of the given lengths."""
    compiled = _compiled(_terms(("pick", turning, dict(DENSE, timing="event"))), {"pick": 1.0})
    rollouts = {}
    for policy, length in zip(AUDIT_POLICIES, lengths_by_policy):
        trace = TermTrace(low=0.0, high=1.0, nonzero=6, live=6 * length, before_end=before_end)
        rollouts[policy] = Rollout(compiled, policy, returns=np.ones((2, 3)), lengths=np.full((2, 3), length),
                                   decisions=np.full((2, 3), length), terms={"pick": np.ones((2, 3))},
                                   statistics={}, traces={"pick": trace})
    return find_flags(ScenarioAudit(compiled, rollouts, None))


def test_a_term_paid_on_the_event_that_ends_the_episode_depends_on_when_the_actions_trigger_it():
    """Once per episode under every policy, on the ending step: the all-zeros policy drifts onto the water
    after 400 steps, random after 250, the scripted pilot heads there in 40. Equal sums, yet the actions
    decide the term (when it is earned), so it is not flagged as action-independent."""
    assert not [f for f in _ending_term_audit([400, 250, 40]) if f.kind == "action_independent"]
    # the same payments after equally long episodes: nothing the actions did shows, so it is flagged
    assert [f.kind for f in _ending_term_audit([30, 30, 30])] == ["action_independent"]
    # paid before the episode ended too (a step that did not end it): equal sums are action-independence
    assert [f.kind for f in _ending_term_audit([400, 250, 40], before_end=2)] == ["action_independent"]


def test_a_scenario_that_is_not_the_paper_s_gets_no_published_cell_and_says_why():
    audit = audit_scenario(hivex_dsl.compile({"hivex": 1, "environment": "wind_farm_control", "agents": 2,
                                              "episode_length": EPISODE}), episodes=1)
    data = audit.as_dict()
    assert audit.cell is None and data["published"] is None
    assert not {f.kind for f in audit.flags} & {"beats_published", "published_scale"}
    assert ("  no published result: the paper's result for this task and level (return 4612) is not this scenario's: "
            "it differs from the paper's setting in agents, episode_length") in describe(data)
    assert ", pattern 0;" in describe(data)  # WFC's levels are layout patterns



def test_scripted_policies_decide_in_float64_whatever_the_observation_dtype():
    """numpy's float32 arctan2 is not correctly rounded and differs by CPU (SIMD path): the scripted policies get
    their float32 observations as float64, so a last-bit difference cannot flip a decision from machine to machine."""
    from types import SimpleNamespace

    from hivex_dsl.evaluation.policies import make_policy

    angles = np.random.default_rng(0).uniform(-np.pi, np.pi, 100_000)
    sin32, cos32 = np.sin(angles).astype(np.float32), np.cos(angles).astype(np.float32)
    exact = np.arctan2(sin32.astype(np.float64), cos32.astype(np.float64)).astype(np.float32)
    assert np.any(np.arctan2(sin32, cos32) != exact)  # the premise: float32 arctan2 is not the exact angle rounded

    seen = []
    spy = SimpleNamespace(entry=SimpleNamespace(scripted_policy=lambda compiled: seen.append))
    scripted = make_policy("scripted", spy, None, (2, 3))
    vector, camera = cos32[:6].reshape(2, 3), np.zeros((2, 3, 4), np.uint8)
    scripted({"vector": vector, "camera": camera})
    scripted(vector)
    (as_dict, as_array) = seen
    assert as_dict["vector"].dtype == np.float64 and np.array_equal(as_dict["vector"], vector)
    assert as_dict["camera"] is camera and as_array.dtype == np.float64
    assert vector.dtype == np.float32  # the caller's array is not changed


def test_a_trained_policy_below_all_zeros_is_flagged():
    # issue 54 item 18: `hivex audit --checkpoint` raised nothing for a trained policy scoring below doing nothing.
    # On OPC, full throttle straight ahead runs the vessels over the border (-23.6 in 300 steps); doing nothing, 0.
    compiled = hivex_dsl.compile({"hivex": 1, "environment": "ocean_plastic_collection", "episode_length": 300})
    full_throttle = lambda obs: np.tile(np.array([1, 0]), (1, compiled.agents, 1))  # noqa: E731
    audit = audit_scenario(compiled, episodes=1, trained=lambda c: full_throttle)
    flagged = [f for f in audit.flags if f.kind == "below_zeros"]
    assert [f.policy for f in flagged] == ["trained"]
    assert audit.rollouts["trained"].returns.mean() < audit.rollouts["zeros"].returns.mean() == 0
    assert "FLAG below_zeros" in describe(audit.as_dict())
    scripted = audit_scenario(compiled, episodes=1, trained=lambda c: "scripted")
    assert scripted.rollouts["trained"].returns.mean() > 0 and not [f for f in scripted.flags if f.kind == "below_zeros"]
