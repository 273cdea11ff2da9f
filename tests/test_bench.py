"""`hivex bench`: one-core measurements in child processes, medians, targets, JSON and the docs page."""

from __future__ import annotations

import json

import pytest

from hivex_dsl.compiler import registry
from hivex_dsl.evaluation import bench
from hivex_dsl.cli import main
from hivex_dsl.docsgen import render_docs


def test_bench_measures_both_adapters_in_one_core_children_and_prints_json(capsys, tmp_path):
    out = tmp_path / "r.json"
    code = main(["bench", "--env", "wind_farm_control", "--seconds", "0.2", "--repeats", "2", "--batch", "4",
                 "--no-reference", "--json", "-o", str(out)])
    assert code == 0
    report = json.loads(capsys.readouterr().out)
    assert report == json.loads(out.read_text())
    assert report["machine"]["threads"] == 1 and report["repeats"] == 2
    parallel, vector = report["results"]
    assert (parallel["adapter"], parallel["batch"], vector["adapter"], vector["batch"]) == ("parallel", 1, "vector", 4)
    assert parallel["agents"] == vector["agents"] == 8 and parallel["runs"] == 2
    assert parallel["agent_steps_per_s"] == pytest.approx(8 * parallel["env_steps_per_s"])
    assert vector["agent_steps_per_s"] == pytest.approx(4 * 8 * vector["env_steps_per_s"])
    assert parallel["env_steps_per_s"] > 0 and parallel["peak_memory_mb"] > 10
    assert parallel["target_rate"] == 20_000 and isinstance(parallel["meets_target"], bool)
    assert "env_steps_vs_reference" not in parallel
    # the API floor is measured for the ParallelEnv only; it is a part of the step, so below its time
    assert vector["api_floor_us"] is None and 0 < parallel["api_floor_us"] < 1e6 / parallel["env_steps_per_s"]


@pytest.mark.parametrize("env_id", list(registry.environments()))
def test_the_parallel_measurement_and_its_api_floor_run_on_every_environment(env_id):
    # issue 54 item 14: the API floor's stand-in composer lacked the weights the running-mean statistics read (OPC)
    m = bench.measure_parallel(env_id, 0.02)
    assert m.env_steps_per_s > 0 and m.api_floor_us > 0


def test_children_run_on_one_thread():
    code = "import os, json; print(json.dumps({k: os.environ.get(k) for k in %r}))" % list(bench.ONE_CORE)
    import subprocess
    import sys

    env = dict(__import__("os").environ, **bench.ONE_CORE)
    seen = json.loads(subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True).stdout)
    assert set(seen.values()) == {"1"}


def test_medians_and_ratios():
    runs = [{"target": "x", "adapter": "parallel", "env_steps_per_s": v, "agent_steps_per_s": 2 * v,
             "peak_memory_mb": m} for v, m in [(10.0, 5.0), (30.0, 9.0), (20.0, 7.0)]]
    median = bench.median_of(runs)
    assert (median["env_steps_per_s"], median["agent_steps_per_s"], median["peak_memory_mb"]) == (20.0, 40.0, 7.0)


def test_unknown_environment_is_a_clear_error(capsys):
    assert main(["bench", "--env", "wind_farm", "--no-reference"]) == 2
    assert "unknown environment 'wind_farm'" in capsys.readouterr().err


def test_the_performance_page_shows_a_report(tmp_path):
    report = {"machine": {"processor": "x86_64", "cpu_count": 2, "platform": "Linux", "python": "3.11",
                          "numpy": "2.0", "threads": 1}, "seconds_per_run": 3.0, "repeats": 3,
              "results": [{"target": "wind_farm_control", "adapter": "parallel", "batch": 1, "agents": 8,
                           "env_steps_per_s": 12345.6, "agent_steps_per_s": 98764.8, "peak_memory_mb": 55.0,
                           "env_steps_vs_reference": 3.5, "agent_steps_vs_reference": 3.5, "target_rate": 20000,
                           "meets_target": False, "api_floor_us": 24.84}]}
    path = tmp_path / "latest.json"
    path.write_text(json.dumps(report))
    docs = render_docs(path)
    page = docs["performance.md"]
    row = "| `wind_farm_control` | parallel | 1 | 8 | 12,346 | 98,765 | 81.0 | 24.8 | 55 | 3.5 | missed: 20,000 env-steps/s |"
    assert row in page
    assert "[Performance](performance.md)" in docs["index.md"]
    assert "performance.md" not in render_docs(None)


def test_a_replayed_step_keeps_the_api_layer_and_drops_the_environment_work():
    """What `api_floor_us` times: the env answers every step with the recorded step's results, through the
    whole PettingZoo path (checks, bookkeeping, dicts), without calling the simulator or the reward terms."""
    import numpy as np

    import hivex_dsl
    from hivex_dsl.sim.spaces import stack_agent_actions

    env = hivex_dsl.parallel_env(hivex_dsl.compile("wildfire_resource_management/main"))
    env.reset(seed=0)
    space = env.core.sim.action_space
    actions = {a: np.array([1, 0, 2, 0]) for a in env.agents}
    sim, composer = env.core.sim, env.core.composer
    bench.replay_one_step(env, stack_agent_actions(space, actions, env.possible_agents))

    def not_called(*args, **kwargs):
        raise AssertionError("the replay called the environment")

    sim.step = sim.observe = sim.reset = sim.reset_where = not_called
    composer._plan = ()  # a composer asked again would report no terms at all
    steps = [env.step(actions) for _ in range(3)]
    for obs, rewards, _, _, infos in steps[1:]:
        assert all(np.array_equal(obs[a], steps[0][0][a]) for a in env.agents)
        assert rewards == steps[0][1] and infos == steps[0][4]
    obs, rewards, terminations, truncations, infos = steps[0]
    assert all(env.observation_space(a).contains(obs[a]) for a in env.agents)
    assert set(infos["tower_0"]["reward_terms"]) == {"watch_tower_performance", "neighbour_performance",
                                                     "collective_performance"}
    assert not any(terminations.values()) and not any(truncations.values())
    assert env.core.clock[0] == 3 and env.core.lengths[0, 0] == 3  # the runtime keeps counting (the recording step is not its)
    first, _ = env.reset()
    assert all(np.array_equal(first[a], obs[a]) for a in env.agents)


def test_expression_terms_are_timed_against_their_hand_written_twins():
    """Structure only: the ratios are for `hivex bench` on a quiet machine, never asserted here."""
    from hivex_dsl.evaluation import bench_expressions

    results = bench_expressions.run(0.05, 1, bench.ONE_CORE)
    assert [(r["term"], r["batch"]) for r in results] == [
        (term, batch) for term in bench_expressions.PAIRS for batch in bench_expressions.BATCHES]
    for r in results:
        assert r["hand_written_us"] > 0 and r["expression_us"] > 0
        assert r["ratio"] == pytest.approx(r["expression_us"] / r["hand_written_us"])
        assert isinstance(r["meets_target"], bool) and r["target_ratio"] == 1.5
    assert "expression term vs hand-written" in bench_expressions.format_table(results)
