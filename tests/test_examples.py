"""The examples train for a few hundred agent-steps on every environment (CI installs torch and SB3;
without them these tests skip). RLlib's example runs in CI's optional RLlib step (`make rllib`)."""

from __future__ import annotations

import importlib.util
import json
import math
from pathlib import Path

import pytest

from hivex_dsl.compiler import compile, registry

ENV_IDS = list(registry.environments())
EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


def load(name: str):
    spec = importlib.util.spec_from_file_location(f"example_{name}", EXAMPLES / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.mark.ecosystem("cleanrl")
@pytest.mark.parametrize("env_id", ENV_IDS)
def test_cleanrl_ppo_trains_a_few_hundred_steps(env_id):
    pytest.importorskip("torch")
    returns = load("cleanrl_ppo").main(["--scenario", f"{env_id}/main", "--num-worlds", "1", "--num-steps", "32",
                                        "--total-timesteps", "300", "--episode-length", "20"])
    assert returns and all(math.isfinite(r) for r in returns)  # episodes ended and were summed


@pytest.mark.ecosystem("sb3")
@pytest.mark.parametrize("env_id", ENV_IDS)
def test_sb3_ppo_trains_a_few_hundred_steps(env_id, tmp_path, monkeypatch):
    pytest.importorskip("stable_baselines3")
    monkeypatch.setenv("SB3_LOGDIR", str(tmp_path))  # SB3's logger makes a folder, by default a new one in /tmp
    model = load("sb3_ppo").main(["--scenario", f"{env_id}/main", "--num-worlds", "1", "--n-steps", "32",
                                  "--total-timesteps", "300", "--episode-length", "20"])
    assert model.num_timesteps >= 300
    episodes = list(model.ep_info_buffer)
    assert episodes and all(e["l"] <= 20 and math.isfinite(e["r"]) for e in episodes)


@pytest.mark.ecosystem("rllib")
@pytest.mark.parametrize("env_id", ENV_IDS)
def test_rllib_ppo_trains_an_iteration(env_id):
    pytest.importorskip("ray.rllib")
    results = load("rllib_ppo").main(["--scenario", f"{env_id}/main", "--episode-length", "20",
                                      "--iterations", "1", "--batch-size", "100"])
    assert len(results) == 1
    sampled, learned = results[0]["env_runners"], results[0]["learners"]["shared"]
    assert sampled["num_env_steps_sampled"] >= 100 and sampled["num_episodes"] >= 1  # 20-step episodes ended
    assert math.isfinite(sampled["episode_return_mean"]) and math.isfinite(learned["total_loss"])


def test_first_run_trains_evaluates_and_compares_with_the_paper(tmp_path, capsys):
    """`make run`'s script, on a tiny budget: a run directory, a curve, and a verdict beside the paper."""
    pytest.importorskip("torch")
    result = load("first_run").main(["--steps", "256", "--episodes", "1", "-o", str(tmp_path / "run"),
                                     "--set", "num_worlds=1", "--set", "buffer_size=128", "--set", "batch_size=64",
                                     "--set", "hidden_units=8", "--replay-steps", "20"])
    out = capsys.readouterr().out
    assert result["published"]["mean"] == pytest.approx(4611.6462)  # WFC's main task in the paper
    assert result["scripted"]["mean"] > result["random"]["mean"]  # turbines facing the wind beat random ones
    assert f"the paper's PPO (published)       4611.6 ± 40.0" in out
    assert "verdict: below the paper's return" in out  # 256 agent-steps learn nothing yet
    assert (tmp_path / "run" / "checkpoint.pt").is_file() and json.loads((tmp_path / "run" / "first_run.json").read_text())
    page = tmp_path / "run" / "replay.html"
    assert result["replay"] == str(page) and f"replay (open it in a browser): {page}" in out
    assert 'id="replay-data"' in page.read_text()
    if importlib.util.find_spec("matplotlib"):
        assert (tmp_path / "run" / "curve.png").read_bytes()[:4] == b"\x89PNG"


def test_first_run_s_default_budget_draws_a_learning_curve_of_several_points():
    """Issue 54, item 18: `make run`'s curve.json held one training point: in 32 worlds of 8 turbines the 2.56M
    agent-steps end one 5,000-step episode of each world before the last update. The worlds end their episodes
    together, so the curve has a point per episode: 2,560,000 / (8 worlds x 8 turbines x 5,000) = 8."""
    pytest.importorskip("torch")
    first_run = load("first_run")
    args = first_run.parse_args([])
    compiled = compile(args.scenario)
    cfg = first_run.run_config(compiled.environment, args)
    decisions = compiled.episode_length // compiled.decision_period
    assert (cfg.num_worlds, compiled.agents, decisions) == (8, 8, 5000)
    assert cfg.max_steps // (cfg.num_worlds * compiled.agents * decisions) == 8
    # a fixed 2,048-experience rollout: every 32 steps of the 64 turbines (hivex train's one-world default would
    # update on 2,048 steps of all 64, 131,072 experiences, a few dozen updates in the budget)
    assert (cfg.buffer_fill, cfg.rollout_length(64)) == ("rollout", 32)
    assert first_run.run_config("wind_farm_control", first_run.parse_args(["--set", "num_worlds=2"])).num_worlds == 2


def test_first_run_never_replaces_an_earlier_run(tmp_path, monkeypatch, capsys):
    # issue 54 item 18: make run overwrote runs/first-run silently, and its final return was a mid-run value
    pytest.importorskip("torch")
    monkeypatch.chdir(tmp_path)
    earlier = tmp_path / "runs" / "first-run"
    earlier.mkdir(parents=True)
    (earlier / "summary.json").write_text('{"mine": 1}')
    tiny = ["--steps", "64", "--episodes", "1", "--set", "num_worlds=1", "--set", "buffer_size=64",
            "--set", "batch_size=64", "--set", "hidden_units=8"]
    first_run = load("first_run")
    with pytest.raises(SystemExit, match="is not empty"):
        first_run.main(tiny + ["-o", str(earlier)])
    result = first_run.main(tiny)
    assert (earlier / "summary.json").read_text() == '{"mine": 1}' and list(earlier.iterdir()) == [earlier / "summary.json"]
    assert result["run_dir"] == str(Path("runs") / "first-run-2") and (tmp_path / "runs" / "first-run-2" / "checkpoint.pt").is_file()
    assert "runs/first-run holds an earlier run (kept): this run goes to runs/first-run-2" in capsys.readouterr().err
    assert result["final_return"] == result["trained"]["mean"]
