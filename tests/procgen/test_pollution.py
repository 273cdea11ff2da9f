"""Ocean Plastic Collection content in ``hivex_dsl.sim.procgen.pollution``: heat maps, pebbles, spawns."""

from __future__ import annotations

import math

import numpy as np
import pytest
from pydantic import ValidationError

from hivex_dsl.sim.procgen.pollution import (
    PollutionPreset,
    PollutionSpec,
    SpawnSpec,
    load_pollution_preset,
    pollution_map,
    sample_pebbles,
    spawn_problem,
    spawn_vessels,
)
from hivex_dsl.sim.procgen.presets import load_preset

H = 200.0  # [orig] world half extent in metres (ENVIRONMENTS.md)
SPEC = PollutionSpec()
SPAWN = SpawnSpec()


def rng(seed: int) -> np.random.Generator:
    return np.random.default_rng(seed)


def heat_maps(seed: int, batch: int = 1, spec: PollutionSpec = SPEC) -> np.ndarray:
    return pollution_map(rng(seed), spec, batch)


def bin_counts(points: np.ndarray, resolution: int) -> np.ndarray:
    """(R, R) pebble counts per cell, binned with the documented convention (row = y, column = x)."""
    cell = 2.0 * H / resolution
    column = np.clip(np.floor((points[:, 0] + H) / cell).astype(int), 0, resolution - 1)
    row = np.clip(np.floor((points[:, 1] + H) / cell).astype(int), 0, resolution - 1)
    return np.bincount(row * resolution + column, minlength=resolution**2).reshape(resolution, resolution)


def pearson(counts: np.ndarray, probabilities: np.ndarray) -> tuple[float, int]:
    """Pearson chi-square statistic and degrees of freedom of ``counts`` against ``probabilities``.

    Cells expecting fewer than 5 pebbles are pooled into one bin (the usual validity rule).
    """
    counts, expected = counts.ravel(), counts.sum() * probabilities.ravel()
    if (counts[expected == 0.0] > 0).any():
        return math.inf, 0
    small = expected < 5.0
    observed = np.append(counts[~small], counts[small].sum())
    expected = np.append(expected[~small], expected[small].sum())
    observed, expected = observed[expected > 0.0], expected[expected > 0.0]
    return float(((observed - expected) ** 2 / expected).sum()), len(expected) - 1


def chi2_bound(df: int) -> float:
    """99.9% quantile of chi-square(df), normal approximation: z(0.999) = 3.09 < 3.1."""
    return df + 3.1 * math.sqrt(2.0 * df)


def min_pair_distance(points: np.ndarray) -> np.ndarray:
    """(B,) smallest distance between two vessels of each world (inf with one vessel)."""
    gaps = np.linalg.norm(points[:, :, None, :] - points[:, None, :, :], axis=-1)
    gaps[:, np.arange(points.shape[1]), np.arange(points.shape[1])] = np.inf
    return gaps.min(axis=(1, 2))


# --- specs and preset ----------------------------------------------------------------------------


def test_preset_file_equals_the_code_defaults():
    preset = load_preset("pollution.yaml", PollutionPreset)
    assert preset == PollutionPreset(hivex=1, generator="pollution", pollution=PollutionSpec(), spawn=SpawnSpec())
    assert load_pollution_preset() == preset


def test_preset_requires_one_world_size():
    with pytest.raises(ValidationError, match="must be equal"):
        PollutionPreset(hivex=1, generator="pollution", pollution=PollutionSpec(),
                        spawn=SpawnSpec(half_extent_m=300.0))


@pytest.mark.parametrize("model", [PollutionSpec, SpawnSpec])
def test_every_field_is_tagged_and_bounded(model):
    for name, field in model.model_fields.items():
        assert field.description.startswith(("[orig] ", "[ours] ")), name
        bounds = {type(m).__name__ for m in field.metadata}
        assert bounds & {"Ge", "Gt"} and bounds & {"Le", "Lt"}, name
    assert model().half_extent_m == H
    assert model.model_fields["half_extent_m"].description.startswith("[orig]")


@pytest.mark.parametrize("model, bad", [
    (PollutionSpec, {"resolution": 1000}),
    (PollutionSpec, {"resolution": "64"}),  # strict: no coercion
    (PollutionSpec, {"hotspot_margin_m": 200.0}),  # margin must be below the half extent
    (PollutionSpec, {"noise_persistence": 0.0}),
    (PollutionSpec, {"colour": "blue"}),
    (SpawnSpec, {"border_margin_m": 250.0}),
    (SpawnSpec, {"min_spacing_m": -1.0}),
])
def test_specs_reject_bad_values(model, bad):
    with pytest.raises(ValidationError):
        model(**bad)


# --- heat maps -----------------------------------------------------------------------------------


def test_maps_are_probabilities_over_the_grid():
    heat = heat_maps(0, batch=20)
    assert heat.shape == (20, 64, 64) and heat.dtype == np.float64
    assert (heat >= 0.0).all()
    np.testing.assert_allclose(heat.sum(axis=(1, 2)), 1.0, rtol=0, atol=1e-12)
    small = heat_maps(0, spec=PollutionSpec(resolution=16))
    assert small.shape == (1, 16, 16)


def test_maps_are_patchy_not_uniform():
    """The default map (fractal noise stretched to [0, 1] and raised to 1.5, no hotspots: fitted to the original's
    untrained records, the reward table's supply note) has patches: its richest cell holds at least twice a uniform
    map's share, its least polluted tenth of the cells far less than a tenth of the plastic, its richest tenth
    more than 15% (a uniform map gives 10% to each)."""
    heat = heat_maps(1, batch=20)
    mean = 1.0 / 64**2
    assert (heat.max(axis=(1, 2)) >= 2.0 * mean).all()
    ordered = np.sort(heat.reshape(20, -1), axis=1)
    assert (ordered[:, : 64**2 // 10].sum(axis=1) < 0.05).all()
    assert (ordered[:, -(64**2 // 10):].sum(axis=1) > 0.15).all()


def test_hotspots_concentrate_the_plastic_several_times_the_mean():
    heat = heat_maps(1, batch=20, spec=PollutionSpec(hotspot_count=4, contrast=2.0))
    assert (heat.max(axis=(1, 2)) >= 4.0 * (1.0 / 64**2)).all()


def test_maps_are_reproducible_and_seeded():
    np.testing.assert_array_equal(heat_maps(7, batch=3), heat_maps(7, batch=3))
    assert not np.allclose(heat_maps(7), heat_maps(8))
    batch = heat_maps(7, batch=3)
    assert not np.allclose(batch[0], batch[1]) and not np.allclose(batch[1], batch[2])


def test_map_rejects_bad_arguments():
    for bad in ({"rng": None}, {"batch": 0}, {"batch": 2.0}, {"spec": SPAWN}):
        args = {"rng": rng(0), "spec": SPEC, "batch": 1, **bad}
        with pytest.raises(ValueError):
            pollution_map(**args)


# --- pebbles -------------------------------------------------------------------------------------


def test_pebbles_lie_inside_the_world_and_are_seeded():
    heat = heat_maps(2, batch=4)
    pebbles = sample_pebbles(rng(3), heat, SPEC.pebble_count, H)
    assert pebbles.shape == (4, SPEC.pebble_count, 2) and pebbles.dtype == np.float64
    assert (np.abs(pebbles) <= H).all()
    np.testing.assert_array_equal(pebbles, sample_pebbles(rng(3), heat, SPEC.pebble_count, H))
    assert not np.allclose(pebbles, sample_pebbles(rng(4), heat, SPEC.pebble_count, H))


def test_pebble_density_follows_the_heat_map():
    own, other = heat_maps(5, batch=2)
    pebbles = sample_pebbles(rng(6), own[None], 200_000, H)[0]
    statistic, df = pearson(bin_counts(pebbles, 64), own)
    assert df > 1000 and statistic < chi2_bound(df)
    # the same test rejects pebbles drawn from a different map's distribution
    foreign = sample_pebbles(rng(6), other[None], 200_000, H)[0]
    statistic, df = pearson(bin_counts(foreign, 64), own)
    assert statistic > 10.0 * chi2_bound(df)


def test_each_world_uses_its_own_map_with_rows_along_y():
    resolution, cell = 8, 2.0 * H / 8
    heat = np.zeros((2, resolution, resolution))
    heat[0, 0, resolution - 1] = 1.0  # row 0 (lowest y), last column (highest x): south-east
    heat[1, resolution - 1, 0] = 5.0  # top row, first column: north-west; unnormalised is fine
    pebbles = sample_pebbles(rng(0), heat, 500, H)
    assert (pebbles[0, :, 0] >= H - cell).all() and (pebbles[0, :, 1] <= -H + cell).all()
    assert (pebbles[1, :, 0] <= -H + cell).all() and (pebbles[1, :, 1] >= H - cell).all()
    # uniform within the cell: both halves of the cell are used about equally
    assert abs(np.mean(pebbles[0, :, 0] > H - cell / 2) - 0.5) < 0.1


def test_zero_heat_cells_never_get_pebbles_and_weights_set_the_odds():
    heat = np.zeros((1, 4, 4))
    heat[0, 1, 2], heat[0, 2, 1] = 1.0, 3.0  # every other cell, including the last ones, is zero
    counts = bin_counts(sample_pebbles(rng(1), heat, 40_000, H)[0], 4)
    assert counts.sum() == 40_000 and counts[1, 2] + counts[2, 1] == 40_000
    share = counts[2, 1] / 40_000  # binomial(40000, 0.75): sd ~ 0.0022
    assert abs(share - 0.75) < 0.01


def test_scaling_the_heat_by_a_power_of_two_changes_nothing():
    heat = heat_maps(9)
    np.testing.assert_array_equal(sample_pebbles(rng(1), heat, 300, H), sample_pebbles(rng(1), 8.0 * heat, 300, H))


@pytest.mark.parametrize("heat, count, half", [
    (-np.ones((1, 4, 4)), 10, H),  # negative heat
    (np.zeros((1, 4, 4)), 10, H),  # nothing to sample from
    (np.ones((4, 4)), 10, H),  # not batched
    (np.ones((1, 4, 5)), 10, H),  # not square
    (np.full((1, 4, 4), np.nan), 10, H),
    (np.ones((1, 4, 4)), 0, H),
    (np.ones((1, 4, 4)), 10, -1.0),
    (np.ones((1, 4, 4)), 10, math.inf),
])
def test_pebbles_reject_bad_arguments(heat, count, half):
    with pytest.raises(ValueError):
        sample_pebbles(rng(0), heat, count, half)


# --- vessel spawn points -------------------------------------------------------------------------


@pytest.mark.parametrize("agents", range(1, 13))
def test_vessels_keep_spacing_and_margin_over_many_seeds(agents):
    reach = H - SPAWN.border_margin_m
    for seed in range(3):
        positions, headings = spawn_vessels(rng(seed), SPAWN, 100, agents)
        assert positions.shape == (100, agents, 2) and headings.shape == (100, agents)
        assert (np.abs(positions) <= reach).all()  # >= 20 m from every border
        assert (min_pair_distance(positions) >= SPAWN.min_spacing_m).all()
        assert (headings >= -np.pi).all() and (headings < np.pi).all()
    assert spawn_problem(SPAWN, agents) is None


def test_spawns_are_seeded_and_spread_out():
    first = spawn_vessels(rng(4), SPAWN, 200, 3)
    np.testing.assert_array_equal(first[0], spawn_vessels(rng(4), SPAWN, 200, 3)[0])
    assert not np.allclose(first[0], spawn_vessels(rng(5), SPAWN, 200, 3)[0])
    positions, headings = first
    # uniform over [-180, 180]^2 and [-pi, pi): the means are near 0 (sd 104/sqrt(600), pi/sqrt(1800))
    assert np.abs(positions.reshape(-1, 2).mean(axis=0)).max() < 20.0
    assert abs(headings.mean()) < 0.3 and headings.std() > 1.5


def test_tight_but_feasible_spacing_still_works():
    # 12 x s^2 = 1/4 x 360^2 exactly at the feasibility bound
    spec = SpawnSpec(min_spacing_m=math.sqrt(0.25 * 360.0**2 / 12) - 1e-9)
    assert spawn_problem(spec, 12) is None
    positions, _ = spawn_vessels(rng(0), spec, 50, 12)
    assert (min_pair_distance(positions) >= spec.min_spacing_m).all()


def test_impossible_spacing_is_reported_and_refused():
    # 12 points at least 150 m apart cannot fit a 360 m square: the best spread of 12 points in
    # a unit square has minimum distance about 0.389 < 150 / 360 = 0.417 (point-spreading tables)
    spec = SpawnSpec(min_spacing_m=150.0)
    problem = spawn_problem(spec, 12)
    assert isinstance(problem, str) and "12 vessels" in problem and "150" in problem
    with pytest.raises(ValueError, match="12 vessels"):
        spawn_vessels(rng(0), spec, 4, 12)
    assert spawn_problem(spec, 1) is None  # a single vessel needs no spacing


def test_spawn_rejects_bad_arguments():
    for agents in (0, True, 2.5):
        with pytest.raises(ValueError):
            spawn_problem(SPAWN, agents)
    with pytest.raises(ValueError):
        spawn_vessels(rng(0), SPAWN, 0, 3)
    with pytest.raises(ValueError):
        spawn_vessels(None, SPAWN, 1, 3)
    with pytest.raises(ValueError):
        spawn_problem(SPEC, 3)
