"""Short scenarios, a tiny trained checkpoint and the headless browser of the replay tests."""

from __future__ import annotations

import json
import os
from pathlib import Path

import pytest
import yaml

SCENARIOS = Path(__file__).resolve().parents[2] / "scenarios"
ENVIRONMENTS = ("wind_farm_control", "wildfire_resource_management", "ocean_plastic_collection",
                "drone_based_reforestation", "aerial_wildfire_suppression")


def short_scenario(folder: Path, environment: str, episode_length: int = 24, name: str = "main", **changes) -> Path:
    """The environment's scenario ``name`` with short episodes (and ``changes``), written as JSON into ``folder``."""
    data = yaml.safe_load((SCENARIOS / environment / f"{name}.yaml").read_text())
    path = folder / f"{environment}-{name}-{episode_length}.json"
    path.write_text(json.dumps(data | {"episode_length": episode_length} | changes))
    return path


@pytest.fixture(scope="session")
def trained(tmp_path_factory):
    """(scenario file, run directory) of a 64-agent-step Wind Farm Control run with 16-step episodes."""
    pytest.importorskip("torch")
    from hivex_dsl.cli import main

    folder = tmp_path_factory.mktemp("trained")
    scenario = short_scenario(folder, "wind_farm_control", episode_length=16)
    tiny = ["--set", "num_worlds=1", "--set", "hidden_units=8", "--set", "buffer_size=64", "--set", "batch_size=64"]
    assert main(["train", str(scenario), "-o", str(folder / "run"), "--steps", "64", "--no-progress", *tiny]) == 0
    return scenario, folder / "run"


@pytest.fixture(scope="session")
def browser():
    """Headless Chromium (Debian's, through Playwright's Python package). Skipped where none is installed, unless
    CI=true, where the browser tests must run; HIVEX_SKIP_BROWSER=1 skips them anywhere."""
    from hivex_dsl.replay.browser import chromium, find_chromium

    if os.environ.get("HIVEX_SKIP_BROWSER") == "1":
        pytest.skip("HIVEX_SKIP_BROWSER=1: the browser tests are skipped")
    missing = []
    try:
        import playwright  # noqa: F401
    except ImportError:
        missing.append("the playwright package (pip install -e '.[browser]')")
    if find_chromium() is None:
        missing.append("a Chromium (apt-get install chromium, or HIVEX_CHROMIUM=/path/to/chromium)")
    if missing:
        reason = "the replay page's browser tests need " + " and ".join(missing)
        if os.environ.get("CI", "").lower() == "true":
            pytest.fail(reason + ": CI must run them (.ci/run installs Debian's chromium)")
        pytest.skip(reason + "; HIVEX_SKIP_BROWSER=1 skips them quietly")
    with chromium() as launched:
        yield launched
