"""Shared fixtures; hypothesis runs derandomized in CI so a red build is reproducible."""

from __future__ import annotations

import dataclasses
import json
import os
from pathlib import Path

import pytest
from hypothesis import settings

settings.register_profile("ci", derandomize=True, deadline=None, print_blob=True)
settings.register_profile("dev", deadline=None)
settings.load_profile("ci" if os.environ.get("CI") else "dev")

PAPER = Path(__file__).resolve().parents[1].parent / "shared" / "paper"  # beside the clone, as CI lays it


def pytest_configure(config):
    config.addinivalue_line(
        "markers", "ecosystem(library): the test proves the library runs on each environment it is parametrized by; "
                   "docs/ecosystem.md's library x environment table is read from these (hivex_dsl.docsgen.ecosystem_matrix)")


@pytest.fixture(scope="session")
def paper() -> Path:
    """The paper and the original's records (`../shared/paper` beside the clone: ORIGINAL-DATA.md), which the
    package does not ship; a test that reads them skips in a clone without them."""
    if not PAPER.is_dir():
        pytest.skip(f"the original's records are not at {PAPER}")
    return PAPER


@pytest.fixture(scope="session")
def wfc_event_runs(paper) -> dict[str, dict[str, list[list[float]]]]:
    """The original WFC pattern 0 main task's TensorBoard scalars: per run (``train_run_0`` .. ``test_run_2``), per
    tag, its (step, value) pairs."""
    return json.loads((paper / "original-wfc-event-scalars.json").read_text())["runs"]


@pytest.fixture
def wfc_dict():
    """A minimal valid Wind Farm Control scenario as a plain dict."""
    return {"hivex": 1, "environment": "wind_farm_control"}


class _SteppedBy:
    """A simulator like ``sim`` in everything but its step, which ``step(sim, state, actions, rng)`` takes."""

    def __init__(self, sim, step):
        self.sim, self._step = sim, step

    def __getattr__(self, name):
        return getattr(self.sim, name)

    def step(self, state, actions, rng):
        return self._step(self.sim, state, actions, rng)


@pytest.fixture(scope="session")
def restepped():
    """``restepped(compiled, step, events=None, ends_on=None)``: the compiled scenario with its simulator's
    step replaced by ``step(sim, state, actions, rng)``, declaring ``events`` {name: meaning} and ending
    agents on ``ends_on`` if given. For tests that need an environment to end agents on cue."""

    def rewire(compiled, step, events=None, ends_on=None):
        def make_simulator(c):
            return _SteppedBy(compiled.entry.make_simulator(c), step)

        entry = dataclasses.replace(compiled.entry, make_simulator=make_simulator,
                                    **({} if events is None else {"events": events}))
        return dataclasses.replace(compiled, entry=entry, **({} if ends_on is None else {"ends_on": ends_on}))

    return rewire


@pytest.fixture()
def aws_fire_ticks(monkeypatch) -> list[int]:
    """How many worlds each fire step Aerial Wildfire Suppression's simulator makes steps, in order, recorded as it
    makes them (its burn clock decides when: params.fire_cadence)."""
    from hivex_dsl.envs.aerial_wildfire_suppression import simulator

    ticks = []
    real = simulator.fire_step_unchecked

    def recording(fire, *args):
        ticks.append(fire.batch)
        return real(fire, *args)

    monkeypatch.setattr(simulator, "fire_step_unchecked", recording)
    return ticks
