"""Params added after scenarios were locked or trained: what an older lock or checkpoint reads, and its fingerprint.

A stored resolved scenario (a lock's, a checkpoint's) holds every param that existed when it was written. Its
fingerprint hashed those; a param added since is no edit of it. The data file is a real one: the scenario and
fingerprint that the Aerial Wildfire Suppression main record's seed-0 checkpoint stored in issue 52's session 39,
before camera_sees_border and water_in_find_tasks (session 40) and camera_images (session 42) existed. Until
session 43, `hivex evaluate` called that checkpoint and every other from before session 40 corrupt."""

from __future__ import annotations

import copy
import json
from pathlib import Path

import pytest

import hivex_dsl
from hivex_dsl.base.errors import ScenarioError
from hivex_dsl.compiler import as_written, registry, written
from hivex_dsl.lang.spec.common import AS_DEFAULT

OLD = json.loads((Path(__file__).parent / "data" / "aws_main_checkpoint_session39.json").read_text())


def read_as_stored(scenario: dict):
    """The scenario as a checkpoint's loader reads it (hivex_dsl.train.checkpoint)."""
    return written(hivex_dsl.compile(as_written(scenario)), scenario)


def old_lock() -> dict:
    """A lock of the session-39 scenario, as `hivex compile` wrote one then: its derived fields are what it
    compiles to (they did not change since), its fingerprint the one stored then."""
    lock = read_as_stored(OLD["scenario"]).to_lock()
    return {**lock, "scenario": copy.deepcopy(OLD["scenario"]), "fingerprint": OLD["fingerprint"]}


def test_the_session_39_checkpoint_scenario_keeps_the_fingerprint_it_was_stored_with():
    compiled = read_as_stored(OLD["scenario"])
    assert compiled.fingerprint == OLD["fingerprint"]
    missing = set(compiled.resolved()["params"]) - set(OLD["scenario"]["params"])
    assert missing == {"camera_images", "camera_sees_border", "water_in_find_tasks", "episodes_continue", "terrain_cast",
                       "drop_mask", "drop_ground", "village_zone", "village_distance", "extinguished_spread",
                       "burn_list", "fire_start", "fire_cadence",
                       "downwind_angle"}


def test_it_plays_what_was_done_when_it_was_written():
    params = read_as_stored(OLD["scenario"]).params
    assert params.camera_images == "rendered"  # the cameras were drawn until session 42
    assert params.water_in_find_tasks is True  # Find tasks' planes dropped and refilled until session 40
    assert params.camera_sees_border is True and params.episodes_continue == 0  # their defaults did so already
    assert params.terrain_cast == "step"  # the ground read every step (session 44 added the release's frames)
    assert params.drop_mask == "flying"  # open to flying planes alone (session 46 added the release's mask)
    assert params.drop_ground == "island"  # drops landed on the forest grid alone (session 48 added the terrain's)
    # the village's circle, its horizontal distance and water that stopped the fire (session 85 added the release's)
    assert (params.village_zone, params.village_distance, params.extinguished_spread) == ("circle", "horizontal", False)
    assert params.burn_list == "age"  # a tree tried its neighbours for its burn alone (session 87 added the queue)
    assert params.fire_start == "running"  # blocks lit until 15 trees burnt (session 87 added the release's one)
    assert params.fire_cadence == "interval"  # every fire_step_interval steps (session 91 added the release's frames)
    assert params.downwind_angle == "horizontal"  # downwind on the map (session 91 added the release's 3-D angle)


def test_an_old_lock_compiles_under_its_stored_fingerprint():
    assert hivex_dsl.compile(old_lock()).fingerprint == OLD["fingerprint"]


def test_every_param_an_old_scenario_holds_is_still_covered():
    """Hashing only the params written does not loosen the check: changing any one of them to another valid value,
    or deleting it (unless it reads back as it was), changes the fingerprint, and an old lock so edited is refused."""
    added = registry.environments()["aerial_wildfire_suppression"].params_model.added_fields()
    unchanged = []
    for name, value in OLD["scenario"]["params"].items():
        deleted = copy.deepcopy(OLD["scenario"])
        del deleted["params"][name]
        # an added field at its earlier value reads back as that value: the same scenario, the same fingerprint
        same = added.get(name, AS_DEFAULT) == value
        assert (read_as_stored(deleted).fingerprint == OLD["fingerprint"]) == same, name
        changed = [fingerprint for fingerprint in map(changed_fingerprint, [name] * 4, other_values(value, name))
                   if fingerprint is not None]
        assert OLD["fingerprint"] not in changed, name
        unchanged += [name] if not changed else []
    assert unchanged == ["island_half_extent_m"]  # it must equal the forest generator's half extent
    lock = old_lock()
    del lock["scenario"]["params"]["plane_speed_m"]
    with pytest.raises(ScenarioError, match="does not match the content"):
        hivex_dsl.compile(lock)


def changed_fingerprint(name: str, value) -> str | None:
    """The stored-scenario fingerprint of the session-39 scenario with param ``name`` set to ``value``; None where
    that does not compile (a bound, or a rule tying params together)."""
    scenario = copy.deepcopy(OLD["scenario"])
    scenario["params"][name] = value
    try:
        return read_as_stored(scenario).fingerprint
    except ScenarioError:
        return None


def other_values(value, name: str) -> list:
    """Values of ``value``'s type other than it, for the Aerial Wildfire Suppression param ``name``."""
    if isinstance(value, bool):
        return [not value]
    if isinstance(value, int):
        return [value + 1, value - 1]
    if isinstance(value, float):
        return [other for other in (value * 1.1, value * 0.9, value + 0.01, value - 0.01) if other != value]
    annotation = registry.environments()["aerial_wildfire_suppression"].params_model.model_fields[name].annotation
    return [other for other in getattr(annotation, "__args__", ()) if other != value]


def test_a_lock_of_today_that_loses_a_param_is_refused():
    """A param that has no earlier value (camera_sees_border was added at what was done before) is no exception:
    deleted from a lock that holds it, the lock no longer matches its fingerprint."""
    lock = hivex_dsl.compile("aerial_wildfire_suppression/main").to_lock()
    del lock["scenario"]["params"]["camera_sees_border"]
    with pytest.raises(ScenarioError, match="does not match the content"):
        hivex_dsl.compile(lock)


@pytest.mark.parametrize("environment", sorted(registry.environments()))
def test_every_added_field_is_a_param_whose_earlier_value_is_valid(environment):
    model = registry.environments()[environment].params_model
    added = model.added_fields()
    assert AS_DEFAULT not in added.values()
    for name, before in added.items():
        assert name in model.model_fields, name
        assert model.model_validate({name: before}).model_dump(mode="json")[name] == before


def test_added_fields_gather_every_base_s():
    """The wind's, the fire's and the cameras' added fields reach the environments whose params take them."""
    model = registry.environments()["aerial_wildfire_suppression"].params_model
    aws = model.added_fields()
    assert aws["camera_images"] == "rendered" and aws["water_in_find_tasks"] is True  # not their defaults
    for name in ("wind_original_law", "spread_wind"):  # the wind's and the fire's, added at their defaults
        assert aws[name] == model.model_fields[name].default, name
    assert aws["finished_planes"] == "respawn" != model.model_fields["finished_planes"].default  # its own: the lone
    # planes' rule until the release's became the default (session 43)
    wrm = registry.environments()["wildfire_resource_management"].params_model.added_fields()
    assert {"wind_original_law", "spread_weather_at"} <= set(wrm) and "camera_images" not in wrm
