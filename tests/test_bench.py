"""`hivex bench`: one-core measurements in child processes, medians, targets, JSON and the docs page."""

from __future__ import annotations

import json

import pytest

from hivex_dsl import bench
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
                           "meets_target": False}]}
    path = tmp_path / "latest.json"
    path.write_text(json.dumps(report))
    docs = render_docs(path)
    page = docs["performance.md"]
    assert "| `wind_farm_control` | parallel | 1 | 8 | 12,346 | 98,765 | 55 | 3.5 | missed: 20,000 env-steps/s |" in page
    assert "[Performance](performance.md)" in docs["index.md"]
    assert "performance.md" not in render_docs(None)
