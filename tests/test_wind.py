"""The wind model: easing toward a target, retargeting by +/-60 degrees, bounded local deviation."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from hypothesis import given, strategies as st

from hivex_dsl.sim.procgen.wind import (WindSpec, local_wind, probe_wind, wind_reset, wind_reset_where, wind_step,
                                        wrap_angle)

SPEC = WindSpec(ease_rate=0.01, target_shift_deg=60.0, retarget_tolerance_deg=5.0, deviation_max_deg=90.0,
                noise_scale_m=400.0, noise_octaves=2, drift_m=1.0)


def test_main_direction_eases_toward_the_target():
    state = wind_reset(np.random.default_rng(0), 4, SPEC)
    gap = np.abs(wrap_angle(state.target - state.main))
    np.testing.assert_allclose(gap, np.radians(60.0))
    nxt = wind_step(state, np.random.default_rng(1), SPEC)
    np.testing.assert_allclose(np.abs(wrap_angle(nxt.target - nxt.main)), 0.99 * gap)


def test_target_turns_by_the_shift_once_reached_and_signs_vary():
    rng = np.random.default_rng(5)
    state = wind_reset(rng, 64, SPEC)
    first_target = state.target.copy()
    # (1 - 0.01)^n * 60 < 5  <=>  n > ln(12)/-ln(0.99) = 247.2: every world retargets at step 248
    for _ in range(247):
        state = wind_step(state, rng, SPEC)
    np.testing.assert_array_equal(state.target, first_target)
    state = wind_step(state, rng, SPEC)
    turn = wrap_angle(state.target - first_target)
    np.testing.assert_allclose(np.abs(turn), np.radians(60.0), atol=1e-9)
    assert (turn > 0).any() and (turn < 0).any()


@given(seed=st.integers(0, 2**32 - 1), steps=st.integers(0, 50))
def test_local_wind_stays_within_the_maximum_deviation(seed, steps):
    rng = np.random.default_rng(seed)
    state = wind_reset(rng, 2, SPEC)
    for _ in range(steps):
        state = wind_step(state, rng, SPEC)
    points = rng.uniform(-600, 600, (2, 50, 2))
    deviation = np.abs(wrap_angle(local_wind(state, points, SPEC) - state.main[:, None]))
    assert np.all(deviation <= np.radians(90.0) + 1e-9)


def test_noise_field_drifts_with_the_main_wind():
    state = wind_reset(np.random.default_rng(2), 1, SPEC)
    nxt = wind_step(state, np.random.default_rng(3), SPEC)
    np.testing.assert_allclose(nxt.drift[0], [np.cos(nxt.main[0]), np.sin(nxt.main[0])])


def test_reset_where_changes_only_masked_worlds():
    rng = np.random.default_rng(4)
    state = wind_reset(rng, 3, SPEC)
    mask = np.array([False, True, False])
    fresh = wind_reset_where(state, mask, rng, SPEC)
    for name in ("main", "target", "perm", "grads"):
        old, new = getattr(state, name), getattr(fresh, name)
        np.testing.assert_array_equal(old[~mask], new[~mask])
        assert not np.array_equal(old[mask], new[mask])


@pytest.mark.parametrize("angle, expected", [(np.pi, -np.pi), (3 * np.pi / 2, -np.pi / 2), (-0.1, -0.1)])
def test_wrap_angle(angle, expected):
    assert wrap_angle(angle) == pytest.approx(expected)


@given(seed=st.integers(0, 2**32 - 1), drift_m=st.sampled_from([1.0, 37.0, 100.0]))
def test_a_kept_probe_gives_exactly_the_fresh_wind(seed, drift_m):
    """Chained probes (cell lookups skipped while points stay in their cells) equal fresh evaluations,
    also while points cross cells (large drift) and after a partial reset draws a new lattice."""
    spec = dataclasses.replace(SPEC, drift_m=drift_m)
    rng = np.random.default_rng(seed)
    state = wind_reset(rng, 3, spec)
    points = rng.uniform(-900.0, 900.0, (3, 5, 2))
    wind, probe = probe_wind(state, points, spec)
    reused = 0
    for step in range(60):
        state = wind_step(state, rng, spec)
        if step == 30:
            state = wind_reset_where(state, np.array([False, True, False]), rng, spec)
        before = probe
        wind, probe = probe_wind(state, points, spec, probe)
        reused += probe is before
        np.testing.assert_array_equal(wind, local_wind(state, points, spec))
    assert drift_m > 1.0 or reused > 0  # with a metre of drift per step the probe is really reused


@given(st.integers(0, 2**31 - 1), st.integers(1, 4))
def test_local_wind_is_the_main_direction_turned_by_the_shared_fractal_noise(seed, octaves):
    """The wind's own octave layout against noise.fractal_unchecked, the field it stands for."""
    from hivex_dsl.sim.procgen.noise import fractal_unchecked

    rng = np.random.default_rng(seed)
    spec = dataclasses.replace(SPEC, noise_octaves=octaves)
    state = wind_reset(rng, 3, spec)
    for _ in range(5):
        state = wind_step(state, rng, spec)
    points = rng.uniform(-900.0, 900.0, (3, 5, 2))
    moved = (points - state.drift[:, None, :]) / spec.noise_scale_m
    noise = fractal_unchecked(state.perm, state.grads, moved[..., 0], moved[..., 1], octaves, 0.5, 2.0)
    expected = wrap_angle(state.main[:, None] + np.radians(spec.deviation_max_deg) * noise)
    np.testing.assert_array_equal(local_wind(state, points, spec), expected)
