"""Quantities researchers reached for: DBR's fertility at the drone, WRM's per-neighbour values, and WFC's
wind speed, which the wind model does not have (the vocabulary says so). Values are checked against
numbers computed by hand from hand-made states."""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

import numpy as np
import pytest

import hivex_dsl
from hivex_dsl import ScenarioError
from hivex_dsl.cli import main
from hivex_dsl.envs.drone_based_reforestation.simulator import DroneReforestationSimulator
from hivex_dsl.envs.wildfire_resource_management.simulator import WildfireResourceSimulator
from hivex_dsl.lang.expr import input_problems
from hivex_dsl.sim.reward.vocabulary import vocabulary_of

DOCS = Path(__file__).resolve().parents[2] / "docs" / "environments"
NEIGHBOUR_NAMES = [f"{prefix}{k}{suffix}" for k in (1, 2, 3) for prefix, suffix in (
    ("resources_given_to_neighbour", ""), ("neighbour", "_resources_received"), ("neighbour", "_sees_fire"),
    ("neighbour", "_distance_to_fire_m"), ("neighbour", "_tower_performance"))]


def _read(compiled, state, names):
    vocabulary = vocabulary_of(compiled.environment)
    values = vocabulary.values(state, {}, compiled, names)
    assert input_problems(vocabulary.quantities(compiled), values) == []  # dtype, shape, declared range
    return values


def test_fertility_at_the_drone_is_the_remapped_tree_distance_sampled_bilinearly():
    compiled = hivex_dsl.compile({"hivex": 1, "environment": "drone_based_reforestation", "agents": 2})
    p, forest = compiled.params, compiled.generators["forest"]
    assert (p.min_tree_distance_m, p.max_tree_distance_m) == (2.5, 75.0)
    state = DroneReforestationSimulator(compiled).reset(np.random.default_rng(0), 2)
    m, cell = forest.cells, forest.spacing_m
    origin = -forest.half_extent_m + cell / 2.0  # the centre of forest cell (0, 0)
    raster = np.full((2, m, m), 40.0, np.float32)
    raster[0, :, 5], raster[0, :, 6] = 20.0, 60.0  # world 0: det 20 m on column 5, 60 m on column 6
    raster[1] = 1.0  # world 1: every point nearer a tree than min_tree_distance_m
    position = state.position.copy()
    position[0, 0, :2] = (origin + 5.5 * cell, origin + 3 * cell)  # halfway between columns 5 and 6: det 40 m
    position[0, 1, :2] = (origin + 5 * cell, origin + 7.25 * cell)  # on column 5: det 20 m
    state = dataclasses.replace(state, tree_distance=raster, position=position)
    fertility = _read(compiled, state, ["fertility"])["fertility"]
    # Remap(det, 2.5, 75, 1, 0) = (75 - det) / 72.5
    np.testing.assert_allclose(fertility, [[35.0 / 72.5, 55.0 / 72.5], [0.0, 0.0]], rtol=1e-12)


def test_per_neighbour_quantities_read_each_agents_neighbours_towers():
    compiled = hivex_dsl.compile({"hivex": 1, "environment": "wildfire_resource_management"})
    assert compiled.params.detection_radius_m == 600.0
    state = WildfireResourceSimulator(compiled).reset(np.random.default_rng(0), 1)
    tower = np.arange(9)
    distance = np.where(tower == 3, np.inf, 50.0 * tower)[None]  # tower 3 sees no fire
    allocation = state.allocation.copy()
    allocation[0, 0] = (2, 3, 1, 4)  # agent 0 keeps 0.2 and gives 0.3, 0.1, 0.4 to its neighbours 1-3
    state = dataclasses.replace(state, support=(10 * tower)[None].astype(np.int32), allocation=allocation,
                                sighting=dataclasses.replace(state.sighting, distance=distance,
                                                             performance=(tower / 10.0)[None]))
    values = _read(compiled, state, NEIGHBOUR_NAMES)
    # neighbours by hand from the 3 x 3 grid (tower 3 * row + col): corner 0 -> 1, 3, 4; centre 4 -> 1, 3, 5
    # (7 ties with 5 and drops, the higher index); corner 8 -> 5, 7, 4
    expected = {0: (1, 3, 4), 4: (1, 3, 5), 8: (5, 7, 4)}
    for agent, towers in expected.items():
        for k, seen in zip((1, 2, 3), towers):
            assert values[f"neighbour{k}_resources_received"][0, agent] == seen  # tower t receives t
            assert values[f"neighbour{k}_tower_performance"][0, agent] == seen / 10.0
            assert values[f"neighbour{k}_sees_fire"][0, agent] == (seen != 3)
            assert values[f"neighbour{k}_distance_to_fire_m"][0, agent] == (600.0 if seen == 3 else 50.0 * seen)
    assert [values[f"resources_given_to_neighbour{k}"][0, 0] for k in (1, 2, 3)] == [0.3, 0.1, 0.4]


def test_a_per_neighbour_quantity_compiles_in_a_term():
    compiled = hivex_dsl.compile({"hivex": 1, "environment": "wildfire_resource_management", "terms": {
        "help_the_nearest": "resources_given_to_neighbour1 * where(neighbour1_sees_fire, 1, 0)"}})
    contract = next(c for c in compiled.term_contracts if c.name == "help_the_nearest")
    assert (contract.low, contract.high) == (0.0, 1.0)


@pytest.mark.parametrize("name", ["wind_speed", "wind_speed_m_s"])
def test_wind_speed_is_not_modelled_in_wind_farm_control_and_an_expression_is_told_why(name):
    with pytest.raises(ScenarioError) as caught:
        hivex_dsl.compile({"hivex": 1, "environment": "wind_farm_control", "terms": {"t": f"wind_force * {name}"}})
    message = caught.value.first.message
    assert message.startswith(f"terms.t.expr: unknown quantity '{name}': wind_speed is not modelled in "
                              "wind_farm_control: the wind (the original's Wind component) has a direction and no speed")
    assert "wind_speed" in vocabulary_of("wind_farm_control").not_modelled


@pytest.mark.parametrize("env_id, names", [("drone_based_reforestation", ["fertility"]),
                                           ("wildfire_resource_management", NEIGHBOUR_NAMES)])
def test_new_quantities_are_listed_by_hivex_vocab_and_in_the_docs(env_id, names, capsys):
    assert main(["vocab", env_id, "--json"]) == 0
    listed = {row["name"]: row for row in json.loads(capsys.readouterr().out)}
    page = (DOCS / f"{env_id}.md").read_text()
    for name in names:
        assert listed[name]["meaning"].endswith(".") and (listed[name]["unit"] or listed[name]["kind"] == "bool")
        assert f"| `{name}` |" in page


def test_the_docs_say_wind_speed_is_not_modelled():
    assert "- `wind_speed`: the wind (the original's Wind component) has a direction and no speed" in (
        DOCS / "wind_farm_control.md").read_text()
