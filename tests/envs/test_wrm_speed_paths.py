"""The weather's fast paths give exactly the general answers.

weather_fields evaluates the three fields' fractal noise with their sample points' lattice cells, offsets and
fades worked out once, and integer cell indices: the floats of noise.fractal_unchecked on each field's lattice
(weather_at's former formula), for any period and even for coordinates beyond int64. start_islands samples
extra probe points in the weather grid's evaluation: the same values as sampling them alone.
"""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

import hivex_dsl
from hivex_dsl.envs.island import IslandSpecs, sample_conditions, sample_points, start_islands
from hivex_dsl.base.numeric import clamp
from hivex_dsl.sim.procgen.noise import fractal_unchecked
from hivex_dsl.sim.procgen.weather import FIELDS, WeatherSpec, WeatherState, weather_at, weather_fields, weather_reset


def reference_fields(state: WeatherState, points: np.ndarray, spec: WeatherSpec) -> np.ndarray:
    """(F, B, N): each field by fractal_unchecked on its own lattice rows, then mean + contrast * noise, clipped."""
    fields, batch = len(FIELDS), state.offsets.shape[0]
    moved = (points - state.offsets[:, None, :]) / spec.noise_scale_m
    shape = (fields * batch, points.shape[1])
    x = np.broadcast_to(moved[None, ..., 0], (fields,) + moved.shape[:2]).reshape(shape)
    y = np.broadcast_to(moved[None, ..., 1], (fields,) + moved.shape[:2]).reshape(shape)
    noise = fractal_unchecked(state.perm.reshape(fields * batch, -1), state.grads.reshape(fields * batch, -1, 2),
                              x, y, spec.octaves, spec.persistence, spec.lacunarity).reshape((fields,) + moved.shape[:2])
    return np.stack([clamp(getattr(spec, f"{name}_mean") + getattr(spec, f"{name}_contrast") * noise[k], 0.0, 1.0)
                     for k, name in enumerate(FIELDS)])


@settings(max_examples=80, deadline=None)
@given(st.integers(1, 3), st.integers(1, 40), st.sampled_from([2, 3, 7, 64, 255, 256, 257, 1024]),
       st.integers(1, 4), st.floats(0.1, 1.0), st.floats(1.0, 3.0), st.floats(1.0, 1000.0),
       st.sampled_from([1e3, 1e6, 1e17, 1e300]), st.integers(0, 2**32 - 1))
def test_weather_fields_are_each_fields_fractal_noise(batch, count, period, octaves, persistence, lacunarity, scale,
                                                      reach, seed):
    spec = WeatherSpec(noise_period=period, octaves=octaves, persistence=persistence, lacunarity=lacunarity,
                       noise_scale_m=scale, temperature_mean=0.3, humidity_contrast=1.5)
    rng = np.random.default_rng(seed)
    state = weather_reset(rng, batch, spec)
    state = WeatherState(perm=state.perm, grads=state.grads, offsets=rng.normal(0.0, 500.0, (batch, 2)))
    points = rng.uniform(-reach, reach, (batch, count, 2))
    with np.errstate(all="ignore"):  # the reference's float cell indices overflow int64 beyond 2^63
        expected = reference_fields(state, points, spec)
    np.testing.assert_array_equal(weather_fields(state, points, spec), expected)
    at = weather_at(state, points, spec)
    for k, name in enumerate(FIELDS):
        np.testing.assert_array_equal(at[name], expected[k])


def test_probes_sampled_with_the_grid_are_the_probes_sampled_alone():
    compiled = hivex_dsl.compile("wildfire_resource_management/main")
    specs = IslandSpecs.of(compiled)
    probes = np.array([[-450.0, -450.0], [0.0, 0.0], [123.4, -56.7]])
    maps = start_islands(np.random.default_rng(1), 2, specs, None).maps
    plain = start_islands(np.random.default_rng(5), 2, specs, maps)
    probed = start_islands(np.random.default_rng(5), 2, specs, maps, probes=probes)
    assert plain.probe_weather is None
    np.testing.assert_array_equal(probed.conditions, plain.conditions)
    np.testing.assert_array_equal(probed.conditions, sample_conditions(plain.weather, specs.weather,
                                                                       specs.half_extent_m, specs.weather_cells))
    np.testing.assert_array_equal(probed.probe_weather, sample_points(plain.weather, specs.weather, probes))
    for name in ("trees", "burning"):
        np.testing.assert_array_equal(getattr(probed.fire, name), getattr(plain.fire, name))
    at = weather_at(plain.weather, np.broadcast_to(probes, (2,) + probes.shape), specs.weather)
    np.testing.assert_array_equal(probed.probe_weather, np.stack([at[name] for name in FIELDS], -1).astype(np.float32))
