"""Facts about the drifting weather fields of ``hivex_dsl.sim.procgen.weather``."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from hivex_dsl.sim.procgen.weather import (
    FIELDS,
    WeatherSpec,
    load_weather_preset,
    weather_at,
    weather_fields,
    weather_reset,
    weather_reset_where,
    weather_step,
)

SPEC = WeatherSpec()


def points(seed: int, batch: int, count: int, half: float = 750.0) -> np.ndarray:
    return np.random.default_rng(seed).uniform(-half, half, (batch, count, 2))


def test_fields_are_named_shaped_and_within_unit_interval():
    state = weather_reset(np.random.default_rng(0), 16, SPEC)
    # high contrast makes clipping happen: values must still stay in [0, 1]
    for spec in (SPEC, WeatherSpec(temperature_contrast=2.0, humidity_mean=0.0, overcast_mean=1.0)):
        values = weather_at(state, points(1, 16, 300), spec)
        assert tuple(values) == FIELDS == ("temperature", "humidity", "overcast")
        for name, field in values.items():
            assert field.shape == (16, 300) and field.dtype == np.float64, name
            assert np.all((field >= 0.0) & (field <= 1.0)), name
            assert np.ptp(field) > 0.3, name  # a field, not a constant


def test_fields_are_distinct_and_smooth():
    state = weather_reset(np.random.default_rng(2), 4, SPEC)
    p = points(3, 4, 100)
    values = weather_at(state, p, SPEC)
    assert not np.allclose(values["temperature"], values["humidity"])
    assert not np.allclose(values["humidity"], values["overcast"])
    nudged = weather_at(state, p + 1.0, SPEC)  # 1 m away on a 500 m noise scale
    for name in FIELDS:
        assert np.max(np.abs(nudged[name] - values[name])) < 0.05, name


def test_same_seed_identical_different_seed_differs():
    p = points(4, 8, 50)
    a, b, c = (weather_at(weather_reset(np.random.default_rng(s), 8, SPEC), p, SPEC) for s in (5, 5, 6))
    for name in FIELDS:
        np.testing.assert_array_equal(a[name], b[name])
        assert not np.allclose(a[name], c[name])


@pytest.mark.parametrize("angle, direction", [(0.0, (1.0, 0.0)), (np.pi / 2, (0.0, 1.0)), (np.pi, (-1.0, 0.0))])
def test_a_step_moves_the_fields_with_the_main_wind(angle, direction):
    spec = WeatherSpec(drift_m_per_step=25.0)
    before = weather_reset(np.random.default_rng(7), 3, spec)
    after = weather_step(before, np.full(3, angle), spec)
    p = points(8, 3, 40)
    moved = weather_at(after, p, spec)
    upwind = weather_at(before, p - 25.0 * np.array(direction), spec)
    for name in FIELDS:
        np.testing.assert_allclose(moved[name], upwind[name], atol=1e-9)
        assert not np.allclose(moved[name], weather_at(before, p, spec)[name])


def test_steps_accumulate_and_zero_drift_stands_still():
    state = weather_reset(np.random.default_rng(9), 2, SPEC)
    wind = np.array([0.0, np.pi / 2])
    stepped = weather_step(weather_step(state, wind, SPEC), wind, SPEC)
    np.testing.assert_allclose(stepped.offsets, [[2.0, 0.0], [0.0, 2.0]], atol=1e-12)
    still = WeatherSpec(drift_m_per_step=0.0)
    np.testing.assert_array_equal(weather_step(state, wind, still).offsets, state.offsets)


def test_batch_rows_are_independent():
    state = weather_reset(np.random.default_rng(10), 3, SPEC)
    p = points(11, 3, 30)
    full = weather_at(state, p, SPEC)
    row = replace(state, perm=state.perm[:, 1:2], grads=state.grads[:, 1:2], offsets=state.offsets[1:2])
    alone = weather_at(row, p[1:2], SPEC)
    shifted = weather_at(replace(state, offsets=state.offsets + [[500.0, 0.0], [0.0, 0.0], [0.0, 0.0]]), p, SPEC)
    for name in FIELDS:
        np.testing.assert_array_equal(alone[name][0], full[name][1])
        np.testing.assert_array_equal(shifted[name][1:], full[name][1:])  # moving world 0 leaves the others
        assert not np.allclose(full[name][0], full[name][1])  # same points, different worlds


def test_reset_where_replaces_only_the_masked_worlds():
    state = weather_step(weather_reset(np.random.default_rng(12), 3, SPEC), np.zeros(3), SPEC)
    mask = np.array([False, True, False])
    mixed = weather_reset_where(state, mask, np.random.default_rng(13), SPEC)
    np.testing.assert_array_equal(mixed.perm[:, ~mask], state.perm[:, ~mask])
    np.testing.assert_array_equal(mixed.offsets, [[1.0, 0.0], [0.0, 0.0], [1.0, 0.0]])
    assert not np.array_equal(mixed.perm[:, 1], state.perm[:, 1])


def test_bad_arguments_are_value_errors():
    state = weather_reset(np.random.default_rng(0), 2, SPEC)
    with pytest.raises(ValueError, match="points must have shape"):
        weather_at(state, np.zeros((3, 5, 2)), SPEC)
    with pytest.raises(ValueError, match="points must have shape"):
        weather_at(state, np.zeros((2, 5)), SPEC)
    with pytest.raises(ValueError, match="finite"):
        weather_at(state, np.full((2, 1, 2), np.nan), SPEC)
    with pytest.raises(ValueError, match="wind_main"):
        weather_step(state, np.zeros(3), SPEC)
    with pytest.raises(ValueError, match="mask"):
        weather_reset_where(state, np.array([1, 0]), np.random.default_rng(0), SPEC)
    with pytest.raises(ValueError):
        WeatherSpec(humidity_mean=1.5)
    with pytest.raises(ValueError):
        weather_reset(np.random.default_rng(0), 0, SPEC)


def test_preset_matches_the_code():
    assert load_weather_preset().defaults == WeatherSpec()


def test_the_release_s_weather_reads_the_aws_scene():
    """The scene (the reward tables' note 'The release's weather'): temperature's and humidity's noise step 0.0075
    units a map cell over 243 cells laid on 241 x 7 m, so a lattice cell is 1 / 0.0075 x 1,687 / 243 m; the fields
    shift 0.001 units a rendered frame, one frame every 50 / 3 academy steps; one octave; 0.465 where the noise is 0
    ((0 + 0.69) / 1.483); and a contrast that spreads one octave of this noise by the release's 0.17."""
    release = load_weather_preset().release
    cell_m = (1 / 0.0075) * (241 * 7.0 / 243)
    assert release.noise_scale_m == pytest.approx(cell_m, abs=0.5)
    assert release.drift_m_per_step == pytest.approx(0.001 * cell_m / (50 / 3), abs=1e-4)
    assert release.octaves == 1 and release.temperature_mean == pytest.approx(0.69 / 1.483, abs=5e-4)
    state = weather_reset(np.random.default_rng(0), 64, release)
    points = np.random.default_rng(1).uniform(-600.0, 600.0, (64, 400, 2))
    temperature = weather_fields(state, points, release)[0]
    assert temperature.std() == pytest.approx(0.17, abs=0.02)


def test_aws_draws_the_release_s_weather_and_wrm_the_shared_defaults():
    """Aerial Wildfire Suppression's fire runs on the release's rules alone, so it takes the release's weather; Wildfire
    Resource Management's fire spread was fitted under the shared defaults, which it keeps (the note 'The release's
    weather'). A scenario's own ``generators: weather:`` still wins over either."""
    import hivex_dsl

    def weather_of(environment, **generators):
        agents = {"aerial_wildfire_suppression": 3, "wildfire_resource_management": 9}[environment]
        return hivex_dsl.compile({"hivex": 1, "name": "w", "environment": environment, "task": "main", "agents": agents,
                                  "episode_length": 300, "generators": generators}).generators["weather"]

    preset = load_weather_preset()
    assert weather_of("aerial_wildfire_suppression") == preset.release
    assert weather_of("wildfire_resource_management") == preset.defaults
    assert weather_of("aerial_wildfire_suppression", weather={"octaves": 2}).octaves == 2


@pytest.mark.parametrize("bad", [np.nan, np.inf])
def test_a_wind_that_is_not_finite_is_refused(bad):
    state = weather_reset(np.random.default_rng(3), 2, SPEC)
    with pytest.raises(ValueError, match="wind_main must be finite"):
        weather_step(state, np.array([0.0, bad]), SPEC)
