"""Every file in tests/bad/ holds one mistake; its first line says where and what compile_all reports.

The first line of each file is ``# expect: LINE:COL: message``: the location (1-based; the
column of the value for bad values, of the key for unknown or duplicate keys) and the full
message of the first problem, without the path. ``{environments}`` in it stands for the registered
environments' ids, as the messages list them (comma-separated, in the registry's order).
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

import hivex_dsl
from hivex_dsl import ScenarioError
from hivex_dsl.compiler import registry

BAD = Path(__file__).parent / "bad"
FILES = sorted(BAD.glob("*.yaml"))
EXPECT = re.compile(rb"^# expect: (\d+:\d+: .+)$")


def _expectation(path: Path) -> str:
    first_line = path.read_bytes().split(b"\n", 1)[0]
    match = EXPECT.match(first_line)
    assert match, f"{path.name}: the first line must be '# expect: LINE:COL: message'"
    return match.group(1).decode("utf-8").replace("{environments}", ", ".join(registry.environments()))


def test_the_corpus_is_large_enough():
    assert len(FILES) >= 30


@pytest.mark.parametrize("path", FILES, ids=[p.stem for p in FILES])
def test_bad_scenario_reports_exactly_its_problem(path: Path):
    expected = _expectation(path)
    with pytest.raises(ScenarioError) as caught:
        hivex_dsl.compile_all(path)
    assert type(caught.value) is ScenarioError  # nothing else, not even a subclass
    problems = caught.value.problems
    assert problems
    first = problems[0]
    assert f"{first.location.line}:{first.location.col}: {first.message}" == expected
    assert first.location.path == str(path)
    assert str(first) == f"{path}:{expected}"
    for problem in problems:
        assert problem.message and "\n" not in problem.message and "\r" not in problem.message
        assert problem.location.line >= 1 and problem.location.col >= 1


@pytest.mark.parametrize("path", FILES, ids=[p.stem for p in FILES])
def test_compile_reports_the_same_first_problem(path: Path):
    """compile() stops at the same place (it also refuses sweeps, which a bad sweep file may hit first)."""
    expected = _expectation(path)
    with pytest.raises(ScenarioError) as caught:
        hivex_dsl.compile(path)
    first = caught.value.problems[0]
    text = f"{first.location.line}:{first.location.col}: {first.message}"
    if text != expected:
        assert "use compile_all()" in first.message


def test_an_environment_of_the_catalogue_without_a_simulator_is_named_as_not_available(monkeypatch):
    registry.environments()
    monkeypatch.delitem(registry._REGISTRY, "ocean_plastic_collection")
    with pytest.raises(ScenarioError) as caught:
        hivex_dsl.compile({"hivex": 1, "environment": "ocean_plastic_collection"})
    others = [env_id for env_id in registry.environments() if env_id != "ocean_plastic_collection"]
    assert others[:4] == ["wind_farm_control", "wildfire_resource_management", "drone_based_reforestation",
                          "aerial_wildfire_suppression"]  # the paper's order, the others after them
    assert caught.value.problems[0].message == (
        "environment: environment 'ocean_plastic_collection' is part of HIVEX but not available in this version yet; "
        f"available: {', '.join(others)}")
