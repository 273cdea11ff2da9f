"""Scenario-level `generators:` overrides: merged over the level's preset, revalidated, located.

A stand-in environment (Wind Farm Control with two generator slots attached) keeps these tests
independent of which real environments use which generators.
"""

from __future__ import annotations

import dataclasses

import pytest

from hivex_dsl import compiler
from hivex_dsl.compiler import registry
from hivex_dsl.base.errors import ScenarioError
from hivex_dsl.sim.procgen.pollution import PollutionSpec
from hivex_dsl.sim.procgen.terrain import TerrainSpec, terrain_spec_for_level
from hivex_dsl.compiler.registry import GeneratorSlot

BASE = {"hivex": 1, "environment": "wind_farm_control"}


@pytest.fixture()
def with_slots(monkeypatch):
    wfc = registry.get("wind_farm_control")
    slots = {"terrain": GeneratorSlot(TerrainSpec, lambda level: terrain_spec_for_level(level + 1), "island terrain"),
             "pollution": GeneratorSlot(PollutionSpec, lambda level: PollutionSpec(), "pollution heat map")}
    monkeypatch.setitem(registry._REGISTRY, "wind_farm_control", dataclasses.replace(wfc, generators=slots))


def problems(data: dict) -> list[str]:
    with pytest.raises(ScenarioError) as info:
        compiler.compile(data)
    return [p.message for p in info.value.problems]


def test_without_overrides_every_slot_gets_its_preset_for_the_level(with_slots):
    compiled = compiler.compile(BASE | {"pattern": 4})
    assert compiled.generators["terrain"] == terrain_spec_for_level(5)
    assert compiled.generators["pollution"] == PollutionSpec()


def test_an_override_changes_only_the_fields_written(with_slots):
    compiled = compiler.compile(BASE | {"pattern": 9 - 1, "generators": {"terrain": {"octaves": 2}}})
    preset = terrain_spec_for_level(9)
    assert compiled.generators["terrain"] == preset.model_copy(update={"octaves": 2})
    assert compiled.generators["terrain"].height_multiplier == preset.height_multiplier


def test_overrides_are_part_of_the_resolved_scenario_and_its_fingerprint(with_slots):
    plain = compiler.compile(BASE)
    changed = compiler.compile(BASE | {"generators": {"pollution": {"pebble_count": 50}}})
    assert changed.resolved()["generators"]["pollution"]["pebble_count"] == 50
    assert plain.resolved()["generators"]["pollution"]["pebble_count"] == PollutionSpec().pebble_count
    assert plain.fingerprint != changed.fingerprint
    again = compiler.compile(changed.resolved())
    assert again.fingerprint == changed.fingerprint and again.generators == changed.generators


@pytest.mark.parametrize("generators, message", [
    ({"terrain": {"octaves": 20}}, "generators.terrain.octaves: 20 is out of range: expected an integer from 1 to 8"),
    ({"terrain": {"octaves": "2"}}, "generators.terrain.octaves: expected an integer from 1 to 8, got '2' (a string)"),
    ({"terain": {}}, "unknown generator 'terain' in 'generators'; did you mean 'terrain'?"),
    ({"terrain": {"octave": 2}}, "unknown key 'octave' in 'generators.terrain'; did you mean 'octaves'?"),
    ({"terrain": None}, "generators.terrain: expected a mapping, got null"),
    ({"pollution": {"hotspot_margin_m": 500.0}},
     "generators.pollution: hotspot_margin_m (500 m) must be smaller than half_extent_m (200 m)"),
])
def test_bad_overrides_are_located_errors(with_slots, generators, message):
    found = problems(BASE | {"generators": generators})
    assert any(m.startswith(message) for m in found), found


def test_a_cross_field_error_points_at_the_slot_in_the_file(with_slots, tmp_path):
    path = tmp_path / "s.yaml"
    path.write_text("hivex: 1\nenvironment: wind_farm_control\ngenerators:\n  pollution:\n    hotspot_margin_m: 500.0\n")
    with pytest.raises(ScenarioError) as info:
        compiler.compile(path)
    first = info.value.problems[0]
    assert (first.location.line, first.location.col) == (5, 5)


def test_environments_without_generators_reject_the_key():
    found = problems(BASE | {"generators": {"terrain": {}}})
    assert any("unknown key 'generators'" in m for m in found), found


def test_a_sweep_may_range_over_a_generator_field(with_slots):
    points = compiler.compile_all(BASE | {"generators": {"terrain": {"octaves": 3}},
                                          "sweep": {"generators.pollution.pebble_count": [10, 20]}})
    assert [p.generators["pollution"].pebble_count for p in points] == [10, 20]
    assert all(p.generators["terrain"].octaves == 3 for p in points)
    assert points[0].name == "scenario[generators.pollution.pebble_count=10]"


def test_a_swept_generator_value_out_of_bounds_is_located_at_its_list_item(with_slots, tmp_path):
    path = tmp_path / "s.yaml"
    path.write_text("hivex: 1\nenvironment: wind_farm_control\nsweep:\n  generators.terrain.octaves: [2, 99]\n")
    with pytest.raises(ScenarioError) as info:
        compiler.compile_all(path)
    (problem,) = info.value.problems
    assert (problem.location.line, problem.location.col) == (4, 35)  # the 99 in "  generators.terrain.octaves: [2, 99]"
    assert problem.message.startswith("generators.terrain.octaves: 99 is out of range")
