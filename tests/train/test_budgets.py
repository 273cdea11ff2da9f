"""`hivex train`'s defaults are the ML-Agents configs that ran (the original's plots' axes follow them), the paper
appendix's values named beside them; summary_freq spaces the learning curve as ML-Agents' does."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest
import yaml

from hivex_dsl.compiler import compile
from hivex_dsl.train.config import appendix, make_config, paper_defaults
from hivex_dsl.train.ppo import train

from .conftest import ENVIRONMENTS, short_scenario

CONFIG_NAMES = {"wind_farm_control": "WindFarmControl", "ocean_plastic_collection": "OceanPlasticCollection",
                "drone_based_reforestation": "DroneBasedReforestation",
                "wildfire_resource_management": "WildfireResourceManagement",
                "aerial_wildfire_suppression": "AerialWildfireSuppression"}
APPENDIX_TITLES = {"wind_farm_control": "Wind Farm Control", "ocean_plastic_collection": "Ocean Plastic Collection",
                   "drone_based_reforestation": "Drone-Based Reforestation",
                   "wildfire_resource_management": "Wildfire Resource Management",
                   "aerial_wildfire_suppression": "Aerial Wildfire Suppression"}
ML_AGENTS_HIDDEN_UNITS = 128  # NetworkSettings.hidden_units' default in mlagents/trainers/settings.py


def flat(config: dict) -> dict:
    """An ML-Agents trainer config's ``behaviors.Agent`` as this toolkit's flat keys (config.py's mapping)."""
    agent = config["behaviors"]["Agent"]
    signals = agent["reward_signals"]
    keys = dict(agent["hyperparameters"])
    keys |= {k: v for k, v in agent["network_settings"].items()}
    keys.setdefault("vis_encode_type", "simple")  # ML-Agents' default, which WFC's config leaves unsaid
    keys |= {"gamma": signals["extrinsic"]["gamma"], "reward_strength": signals["extrinsic"]["strength"]}
    if "curiosity" in signals:
        keys |= {f"curiosity_{k}": v for k, v in signals["curiosity"].items() if k != "network_settings"}
        keys["curiosity_encoding_size"] = curiosity_width(signals["curiosity"])
    keys |= {k: agent[k] for k in ("max_steps", "time_horizon", "summary_freq", "keep_checkpoints")}
    keys["num_worlds"] = config["env_settings"].get("num_envs", 1)  # mlagents-learn's default: one environment
    return keys


def curiosity_width(curiosity: dict) -> int:
    """The width of the curiosity module's encoder that ML-Agents (release_20, the one hivex's README installs) builds
    from a config's curiosity block: RewardSignalSettings.structure warns that encoding_size is deprecated and uses it
    as the module's hidden_units only where the block names no network_settings; a block that names them gets
    NetworkSettings' hidden_units, 128 by default (mlagents/trainers/settings.py)."""
    if "network_settings" in curiosity:
        return curiosity["network_settings"].get("hidden_units", ML_AGENTS_HIDDEN_UNITS)
    return curiosity["encoding_size"]


def appendix_config(paper: Path, environment: str) -> dict:
    """The appendix's verbatim config of ``environment`` from the paper's source, read as YAML (its "# testing"
    comments are comments)."""
    tex = (paper / "hivex-paper-extract.tex").read_text()
    block = re.search(rf"Hyperparameters: {APPENDIX_TITLES[environment]}\}}\s*\\begin\{{verbatim\}}(.*?)"
                      r"\\end\{verbatim\}", tex, re.S)
    return yaml.safe_load(block.group(1))


@pytest.mark.parametrize("environment", ENVIRONMENTS)
def test_the_defaults_are_the_config_that_ran(paper, environment):
    ran = yaml.safe_load((paper / "original-configs" / "train" / f"{CONFIG_NAMES[environment]}_hivex.yaml").read_text())
    defaults = make_config(environment).model_dump()
    expected = flat(ran)
    expected.pop("threaded", None)
    assert {k: defaults[k] for k in expected} == expected


@pytest.mark.parametrize("environment", ENVIRONMENTS)
def test_a_config_that_ran_counts_one_world_and_one_world_fills_as_ml_agents(paper, environment):
    """Every config that ran names no num_envs (one Unity environment) and counts its summary point as one world's
    episode in a comment ("3 agents a 3000 steps = 9000"): agents x steps is its summary_freq. One world trains on
    finished trajectories, as ML-Agents' trainer fills its buffer (tests/train/test_buffer_fill.py)."""
    text = (paper / "original-configs" / "train" / f"{CONFIG_NAMES[environment]}_hivex.yaml").read_text()
    assert "num_envs" not in yaml.safe_load(text)["env_settings"]
    counted = re.search(r"summary_freq: (\d+) # (\d+) \w+ a (\d+) steps = (\d+)", text)
    assert counted and int(counted[1]) == int(counted[2]) * int(counted[3]) == int(counted[4])
    cfg = make_config(environment)
    assert cfg.num_worlds == 1 and cfg.buffer_fill == "trajectories"


@pytest.mark.parametrize("environment", ENVIRONMENTS)
def test_the_appendix_block_names_every_value_where_the_appendix_differs(paper, environment):
    ran, written = paper_defaults(environment), flat(appendix_config(paper, environment))
    differing = {k: v for k, v in written.items() if k in ran and ran[k] != v}
    assert appendix(environment) == differing


def test_the_budgets_that_differ_from_the_appendix():
    """The issue's reading of the configs that ran (issue 52 item 2), by hand."""
    dbr = paper_defaults("drone_based_reforestation")
    assert {k: dbr[k] for k in ("max_steps", "summary_freq", "buffer_size", "time_horizon")} == {
        "max_steps": 1_200_000, "summary_freq": 6_000, "buffer_size": 8_192, "time_horizon": 8_192}
    assert appendix("drone_based_reforestation") == {"max_steps": 2_000_000, "summary_freq": 10_000,
                                                     "buffer_size": 10_240, "time_horizon": 10_240}
    assert paper_defaults("wildfire_resource_management")["max_steps"] == 450_000
    assert appendix("wildfire_resource_management") == {"max_steps": 4_500_000}
    assert all(appendix(env) == {} for env in ("wind_farm_control", "ocean_plastic_collection"))
    assert appendix("aerial_wildfire_suppression") == {"num_worlds": 12}  # its env_settings' num_envs


def test_the_appendix_block_is_no_hyperparameter():
    assert "appendix" not in make_config("drone_based_reforestation").model_dump()


@pytest.fixture(scope="module")
def every_update_and_every_128(tmp_path_factory):
    """One tiny WFC run twice, a curve point every update and every 128 agent-steps (5 updates of 64)."""
    compiled = compile(short_scenario("wind_farm_control", episode_length=6))
    runs = {}
    for freq in (1, 128):
        cfg = make_config("wind_farm_control", {"num_worlds": 1, "buffer_fill": "rollout",
                                                "buffer_size": 64, "batch_size": 32, "num_epoch": 1,
                                                "hidden_units": 8, "max_steps": 320, "torch_threads": 1,
                                                "summary_freq": freq})
        run = tmp_path_factory.mktemp(f"freq{freq}")
        train(compiled, cfg, run, progress=False)
        runs[freq] = json.loads((run / "curve.json").read_text())
    return runs


def test_a_point_is_written_at_each_multiple_of_summary_freq_and_at_the_end(every_update_and_every_128):
    every, spaced = every_update_and_every_128[1], every_update_and_every_128[128]
    assert [p["agent_steps"] for p in every] == [64, 128, 192, 256, 320]
    assert [p["agent_steps"] for p in spaced] == [128, 256, 320]


def test_summary_freq_only_groups_the_same_episodes(every_update_and_every_128):
    """Logging only: the same training, so the spaced points pool exactly the per-update points' episodes."""
    every, spaced = every_update_and_every_128[1], every_update_and_every_128[128]
    groups = [every[0:2], every[2:4], every[4:5]]
    assert [p["episodes"] for p in spaced] == [sum(q["episodes"] for q in g) for g in groups]
    for point, group in zip(spaced, groups):
        pooled = sum(q["return"] * q["episodes"] for q in group) / point["episodes"]
        assert point["return"] == pytest.approx(pooled, rel=1e-9)
        assert point["length"] == pytest.approx(sum(q["length"] * q["episodes"] for q in group) / point["episodes"])


def test_the_evidence_module_s_appendix_budgets_are_the_hyperparameter_files():
    """evidence.APPENDIX (the budgets the original's curves are read against) and the files' appendix blocks are one
    reading of the appendix."""
    from hivex_dsl.evaluation.original import evidence

    for environment, (max_steps, summary_freq) in evidence.APPENDIX.items():
        written = paper_defaults(environment) | appendix(environment)
        assert (written["max_steps"], written["summary_freq"]) == (max_steps, summary_freq), environment


@pytest.mark.parametrize("environment", ["wildfire_resource_management", "drone_based_reforestation",
                                         "ocean_plastic_collection"])
def test_the_curiosity_encoder_s_settings_are_the_run_s(paper, environment):
    """The curiosity module encodes with the run's vis_encode_type and num_layers and no normalisation
    (hivex_dsl/train/curiosity.py); the network_settings each config that ran gives its curiosity block (ML-Agents'
    defaults where it names none: simple, 2 layers, no normalisation) say the same, so only the width needs a key."""
    ran = yaml.safe_load((paper / "original-configs" / "train" / f"{CONFIG_NAMES[environment]}_hivex.yaml").read_text())
    settings = ran["behaviors"]["Agent"]["reward_signals"]["curiosity"].get("network_settings", {})
    cfg = make_config(environment)
    assert settings.get("vis_encode_type", "simple") == cfg.vis_encode_type
    assert settings.get("num_layers", 2) == cfg.num_layers
    assert settings.get("normalize", False) is False
