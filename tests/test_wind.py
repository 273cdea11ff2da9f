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


ORIGINAL = dataclasses.replace(SPEC, law="original", lerp_speed=0.3, frame_steps=5.0, drift_m=0.0)


def _facing_east_toward_60_degrees(spec: WindSpec, batch: int = 1):
    state = wind_reset(np.random.default_rng(0), batch, spec)
    east = np.zeros(batch)
    return dataclasses.replace(state, main=east, target=np.full(batch, np.radians(60.0)),
                               vector=np.stack([np.ones(batch), np.zeros(batch)], axis=1))


def test_the_original_law_lerps_the_main_vector_once_a_frame_by_a_growing_fraction():
    """Wind.CalcMainWind by hand: a frame every 5 steps, the fraction growing by 0.3 x 5 x 0.02 s = 0.03 a frame.
    Frame 1: (1, 0) + 0.03 ((0.5, 0.866) - (1, 0)) = (0.985, 0.02598), 1.5109 degrees; frame 2 by 0.06:
    (0.9559, 0.07638), 4.5686 degrees. Between frames the wind stands still."""
    state, rng = _facing_east_toward_60_degrees(ORIGINAL), np.random.default_rng(1)
    mains = []
    for _ in range(10):
        state = wind_step(state, rng, ORIGINAL)
        mains.append(np.degrees(state.main[0]))
    np.testing.assert_allclose(mains[:4], 0.0, atol=1e-12)
    np.testing.assert_allclose(mains[4:9], 1.5109065, atol=1e-6)
    np.testing.assert_allclose(mains[9], 4.5686468, atol=1e-6)
    np.testing.assert_allclose(state.vector[0], [0.9559, 0.0763834], atol=1e-6)
    assert state.fraction[0] == pytest.approx(0.06)


def test_the_original_law_retargets_within_the_tolerance_and_restarts_the_fraction():
    state = _facing_east_toward_60_degrees(ORIGINAL, batch=64)
    state = dataclasses.replace(state, target=np.full(64, np.radians(4.0)), fraction=np.full(64, 0.5))
    state = wind_step(state, np.random.default_rng(2), dataclasses.replace(ORIGINAL, frame_steps=1.0))
    turn = np.degrees(wrap_angle(state.target - np.radians(4.0)))
    np.testing.assert_allclose(np.abs(turn), 60.0, atol=1e-9)
    assert (turn > 0).any() and (turn < 0).any()
    np.testing.assert_allclose(state.fraction, 0.3 * 0.02)  # restarted at 0, then one frame's growth


def test_the_original_law_at_the_aws_scenes_speed_shifts_within_the_hand_bounds():
    """Speed 0.001, frames of 50/3 steps (1/3 s): frame k lerps by f_k = k x 0.001 / 3. Against the target, the
    vector's perpendicular part shrinks by exactly (1 - f_k) and its parallel part (from cos 60 = 0.5) only grows
    toward 1, so tan(angle) lies between sin 60 x prod(1 - f) and tan 60 x prod(1 - f). It falls under tan 5 =
    0.0875, and the target turns, only once prod(1 - f) < 0.101, i.e. sum -ln(1 - f) > 2.29, which needs more than
    100 frames (sum f + f^2 = 1.72 at 100); and surely once prod(1 - f) < 0.0505, within 134 frames (sum f =
    3.02 at 134), the target turning at the frame after."""
    spec = dataclasses.replace(SPEC, law="original", lerp_speed=0.001, frame_steps=50.0 / 3.0, drift_m=0.0)
    state, rng = _facing_east_toward_60_degrees(spec), np.random.default_rng(3)
    for step in range(1, 2_500):
        state = wind_step(state, rng, spec)
        if abs(state.target[0] - np.radians(60.0)) > 1e-9:
            break
    assert 100 * 50 / 3 < step <= 135 * 50 / 3 + 1


def test_the_original_laws_fields_at_their_defaults_leave_the_fingerprint_as_it_was():
    import hivex_dsl

    def wfc(**params):
        scenario = {"hivex": 1, "environment": "wind_farm_control"}
        return hivex_dsl.compile({**scenario, "params": params} if params else scenario)

    plain = wfc()
    assert wfc(wind_lerp_speed=0.001, wind_original_law=0).fingerprint == plain.fingerprint
    assert wfc(wind_lerp_speed=0.5).fingerprint != plain.fingerprint  # inert under law 0, but an edit all the same
    assert type(plain.params).added_fields()["wind_original_law"] == 0  # the law before it
    assert plain.resolved()["params"]["wind_original_law"] == 0
    original = wfc(wind_original_law=1)
    assert original.fingerprint != plain.fingerprint
    assert wfc(wind_original_law=1, wind_lerp_speed=0.5).fingerprint != original.fingerprint
    assert hivex_dsl.compile(original.to_lock()).fingerprint == original.fingerprint


def test_a_wind_farm_under_the_original_law_holds_its_wind_between_frames():
    """Through the simulator: with frames of 4 steps, the main wind and so every turbine's local wind (the noise
    field held still, drift 0) change only on every 4th step."""
    import hivex_dsl
    from hivex_dsl.envs.wind_farm_control.simulator import WindFarmSimulator

    compiled = hivex_dsl.compile({"hivex": 1, "environment": "wind_farm_control", "params": {
        "wind_original_law": 1, "wind_frame_steps": 4.0, "wind_lerp_speed": 0.5, "wind_drift_m": 0.0}})
    sim, rng = WindFarmSimulator(compiled), np.random.default_rng(0)
    state = sim.reset(rng, 2)
    winds = [state.local_wind]
    for _ in range(12):
        state, _ = sim.step(state, np.zeros((2, sim.agents), np.int64), rng)
        winds.append(state.local_wind)
    moved = [not np.array_equal(a, b) for a, b in zip(winds, winds[1:])]
    assert moved == [False, False, False, True] * 3
