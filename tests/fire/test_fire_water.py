"""Water drops (``douse``) and the closest-fire search (``closest_burning``) of ``hivex_dsl.sim.fire``.

ENVIRONMENTS.md, AWS "Drop water": every existing or burning tree within the radius of a drop point
becomes wet; prepared (existing -> wet) and extinguished (burning -> wet) trees are credited per
plane. Distances are from the points to cell centres, in cell units (the centre of cell (r, c) is
at (r, c)). Hand-built cases check the geometry and crediting; hypothesis checks both functions
against brute force over every cell, closest_burning under each of its two pairings (every burning
cell of the world, or the block index) on small grids and on large, dense fronts.
"""

from __future__ import annotations

import contextlib
from unittest import mock

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from hivex_dsl.sim.fire import FireSpec, FireState, TreeState, closest_burning, douse, fire_reset, fire_step
from hivex_dsl.sim.fire import blocks as blocks_module
from hivex_dsl.sim.fire import search as search_module

SYMBOLS = {".": TreeState.NONE, "T": TreeState.EXISTING, "B": TreeState.BURNING, "X": TreeState.BURNT, "W": TreeState.WET}


def drawn(*worlds):
    return np.array([[[SYMBOLS[ch] for ch in line] for line in world] for world in worlds], dtype=np.uint8)


def state_of(trees, ages=None):
    """A FireState over ``trees`` (B, C, C) uint8 with the burning list in flat order."""
    trees = np.ascontiguousarray(trees, dtype=np.uint8)
    burning = np.flatnonzero(trees == TreeState.BURNING).astype(np.int64)
    age = np.zeros(len(burning), np.int32) if ages is None else np.asarray(ages, np.int32)
    batch = trees.shape[0]
    return FireState(trees=trees, burning=burning, age=age, quiet=np.zeros(batch, np.int32), out=np.zeros(batch, bool),
                     ignited=np.zeros(batch, np.int64), burnt_out=np.zeros(batch, np.int64))


def drop(state, points, radius, owners=4):
    """douse at points [(world, row, col, owner), ...]."""
    world, rows, cols, owner = (np.array(v) for v in zip(*points))
    return douse(state, world.astype(int), rows.astype(float), cols.astype(float), radius, owner.astype(int), owners)


FOREST_7 = ["TTTTTTT"] * 7


def test_radius_one_at_a_centre_wets_a_plus_and_counts_prepared_trees():
    state, extinguished, prepared = drop(state_of(drawn(FOREST_7)), [(0, 3, 3, 2)], 1.0)
    expected = drawn(FOREST_7)[0]
    expected[[2, 3, 3, 3, 4], [3, 2, 3, 4, 3]] = TreeState.WET  # diagonals are sqrt(2) > 1 away
    np.testing.assert_array_equal(state.trees[0], expected)
    assert prepared.tolist() == [0, 0, 5, 0] and extinguished.tolist() == [0, 0, 0, 0]


def test_a_point_between_four_centres_reaches_exactly_those_four():
    state, _, prepared = drop(state_of(drawn(FOREST_7)), [(0, 3.5, 3.5, 0)], 0.75)  # they are sqrt(0.5) = 0.707 away
    assert {(int(r), int(c)) for r, c in zip(*np.nonzero(state.trees[0] == TreeState.WET))} == {(3, 3), (3, 4), (4, 3), (4, 4)}
    assert prepared.tolist() == [4, 0, 0, 0]


def test_only_existing_and_burning_trees_get_wet_and_the_burning_list_follows():
    grid = drawn([".TX", "BWB", "TBT"])
    state = state_of(grid, ages=[3, 5, 7])  # burning (1, 0), (1, 2), (2, 1) in flat order
    state, extinguished, prepared = drop(state, [(0, 1.0, 0.0, 1)], 1.0)  # reaches (0,0) (1,0) (1,1) (2,0)
    np.testing.assert_array_equal(state.trees[0], drawn([".TX", "WWB", "WBT"])[0])
    assert extinguished.tolist() == [0, 1, 0, 0] and prepared.tolist() == [0, 1, 0, 0]  # (0,0) is no tree, (1,1) already wet
    assert state.burning.tolist() == [5, 7] and state.age.tolist() == [5, 7]


def test_overlapping_drops_credit_each_tree_once_to_the_lowest_owner():
    # owner 3 listed first; owner 1 overlaps it on column 3; owner 3's own two points overlap on (1, 5)
    points = [(0, 1, 4, 3), (0, 1, 5, 3), (0, 1, 2, 1)]
    grid = drawn(["TTTTTTT", "TTBBTTT", "TTTTTTT"] + ["......."] * 4)
    state, extinguished, prepared = drop(state_of(grid), points, 1.0)
    # owner 1 at (1, 2): (0,2) (1,1) (1,2)* (1,3)* (2,2), * burning
    # owner 3 at (1, 4) and (1, 5): (0,4) (0,5) (1,4) (1,5) (1,6) (2,4) (2,5); (1,3) goes to owner 1
    assert extinguished.tolist() == [0, 2, 0, 0] and prepared.tolist() == [0, 3, 0, 7]
    assert np.count_nonzero(state.trees == TreeState.WET) == 12 and len(state.burning) == 0


def test_drops_only_touch_their_own_world_and_may_lie_off_the_grid():
    state = state_of(drawn(FOREST_7, FOREST_7))
    state, _, prepared = drop(state, [(1, -2.0, 0.0, 0)], 2.5)  # 2 cells below row 0: reaches (0, 0) and (0, +-1)
    assert np.count_nonzero(state.trees[0] == TreeState.WET) == 0
    assert {(int(r), int(c)) for r, c in zip(*np.nonzero(state.trees[1] == TreeState.WET))} == {(0, 0), (0, 1)}
    assert prepared.tolist() == [2, 0, 0, 0]
    _, _, prepared = drop(state, [(0, 1e9, -1e9, 0)], 3.0)  # far away: nothing
    assert prepared.tolist() == [0, 0, 0, 0]


def test_wet_trees_never_burn():
    ignite = np.zeros((1, 5, 5), bool)
    ignite[0, 2, 2] = True
    state = fire_reset(np.ones((1, 5, 5), bool), ignite)
    state, _, _ = drop(state, [(0, 0.0, 0.0, 0), (0, 4.0, 4.0, 0)], 1.5)  # each wets its corner's 2x2 cells
    spec = FireSpec(downwind_cone_deg=180.0)  # with the bowl and hot, dry, clear weather every try succeeds
    hot = lambda w, r, c: (np.ones(len(w)), np.zeros(len(w)), np.zeros(len(w)))  # noqa: E731
    span = (np.arange(5) - 2) ** 2
    bowl = np.add.outer(span, span).astype(np.float32)[None]
    for seed in range(12):
        state = fire_step(state, np.random.default_rng(seed), spec, np.zeros(1), bowl, hot)
    wet = np.zeros((5, 5), bool)
    wet[:2, :2] = wet[3:, 3:] = True
    assert np.all(state.trees[0][wet] == TreeState.WET)
    assert np.all(state.trees[0][~wet] == TreeState.BURNT)


def test_douse_rejects_bad_arguments():
    state = state_of(drawn(FOREST_7))
    with pytest.raises(ValueError, match="owner"):
        drop(state, [(0, 1, 1, 4)], 1.0, owners=4)
    with pytest.raises(ValueError, match="world"):
        drop(state, [(1, 1, 1, 0)], 1.0)
    with pytest.raises(ValueError, match="rows"):
        drop(state, [(0, np.nan, 1, 0)], 1.0)
    with pytest.raises(ValueError, match="radius"):
        drop(state, [(0, 1, 1, 0)], -1.0)


def test_closest_burning_picks_the_nearest_in_the_box_with_ties_to_the_lowest_index():
    grid = drawn(["B......", ".......", ".......", "...T...", ".......", ".....B.", "B......"], ["......."] * 7)
    state = state_of(grid)
    found, row, col = closest_burning(state, np.array([0, 0, 0, 0, 1]), np.array([3.0, 3.0, 3.0, 0.0, 3.0]),
                                      np.array([3.0, 3.0, 0.0, 3.0, 3.0]), 3.0)
    # from (3, 3): (5, 5) at sqrt(8), (0, 0) and (6, 0) at sqrt(18); from (3, 0): (0, 0) and (6, 0) tie at 3 -> (0, 0);
    # from (0, 3): (0, 0) at 3, the others outside the box; world 1 has no fire
    assert found.tolist() == [True, True, True, True, False]
    assert list(zip(row.tolist(), col.tolist())) == [(5, 5), (5, 5), (0, 0), (0, 0), (-1, -1)]
    found, row, col = closest_burning(state, np.array([0]), np.array([3.0]), np.array([3.0]), 1.9)
    assert found.tolist() == [False] and row.tolist() == [-1]  # (5, 5) is 2 rows away: outside the box


@st.composite
def fires(draw):
    """A random fire state (any mix of tree states) on a small batch of small grids."""
    batch, cells = draw(st.integers(1, 3)), draw(st.integers(1, 8))
    seed = draw(st.integers(0, 2**32 - 1))
    trees = np.random.default_rng(seed).integers(0, 5, (batch, cells, cells)).astype(np.uint8)
    state = state_of(trees)
    order = np.random.default_rng(seed + 1).permutation(len(state.burning))  # the list order must not matter
    return FireState(trees=state.trees, burning=state.burning[order], age=state.age, quiet=state.quiet, out=state.out,
                     ignited=state.ignited, burnt_out=state.burnt_out)


def coordinate(cells_hint: int = 8):
    return st.one_of(st.integers(-6, 2 * cells_hint + 6).map(lambda v: v / 2.0), st.floats(-5.0, cells_hint + 5.0))


HALF_BOX = st.one_of(st.sampled_from([0.0, 0.5, 1.0, 2.0, 100.0]), st.floats(0.0, 6.0))


def each_pairing(state, world, rows, cols, half_box):
    """closest_burning's answers as chosen by cost (a single world: its dense one-world matrix), then with
    the dense path off: forced to pair whole worlds, forced to use the block index with the side it picks,
    and with the smallest side (most blocks)."""
    answers = [closest_burning(state, world, rows, cols, half_box)]
    smallest = mock.patch.object(search_module, "block_side", lambda *args: blocks_module.MIN_SIDE)
    for small_work, side in ((10**18, None), (-1, None), (-1, smallest)):
        with mock.patch.object(search_module, "SMALL_WORK", small_work), side or contextlib.nullcontext(), \
                mock.patch.object(search_module, "ONE_WORLD_PAIRS", -1):
            answers.append(closest_burning(state, world, rows, cols, half_box))
    return answers


@settings(max_examples=150, deadline=None)
@given(fires(), st.lists(st.tuples(st.integers(0, 2), coordinate(), coordinate(), HALF_BOX), min_size=0, max_size=6),
       st.one_of(st.none(), HALF_BOX))
def test_closest_burning_matches_brute_force(state, queries, shared_half):
    """One box for all queries (shared_half) or one per query."""
    queries = [(w % state.batch, r, c, h if shared_half is None else shared_half) for w, r, c, h in queries]
    world = np.array([q[0] for q in queries], dtype=np.int64)
    rows, cols = np.array([q[1] for q in queries], float), np.array([q[2] for q in queries], float)
    half_box = shared_half if shared_half is not None else np.array([q[3] for q in queries], float)
    expected = [brute_closest(state, *query) for query in queries]
    for found, row, col in each_pairing(state, world, rows, cols, half_box):
        assert list(zip(found.tolist(), row.tolist(), col.tolist())) == expected


def brute_closest(state, w, qr, qc, half):
    """(found, row, col) of the nearest burning cell of world w in the box, by trying every cell."""
    best = None
    for r, c in zip(*np.nonzero(state.trees[w] == TreeState.BURNING)):  # row-major: lowest flat index first
        dr, dc = r - qr, c - qc
        if abs(dr) <= half and abs(dc) <= half and (best is None or dr * dr + dc * dc < best[0]):
            best = (dr * dr + dc * dc, r, c)
    return (True, int(best[1]), int(best[2])) if best else (False, -1, -1)


def test_closest_burning_with_far_points_and_huge_boxes_matches_brute_force():
    """Points up to 1e17 cells away, where a float sum loses whole cells, with boxes reaching the grid."""
    trees = np.where(np.random.default_rng(5).random((1, 9, 9)) < 0.5, TreeState.BURNING, TreeState.EXISTING)
    state = state_of(trees)
    queries = [(0, 2.0**41 + 3.0, 4.0, 2.0**41), (0, -1e17, 1e17, 1e17), (0, 4.5, -3e16, 3e16 + 2.0),
               (0, 1e17, 1e17, 1e16), (0, 2.0**53, 5.0, 2.0**53 - 4.0)]
    world, rows, cols, half = (np.array(v) for v in zip(*queries))
    expected = [brute_closest(state, *query) for query in queries]
    assert any(hit[0] for hit in expected) and not all(hit[0] for hit in expected)
    for found, row, col in each_pairing(state, world.astype(np.int64), rows, cols, half):
        assert list(zip(found.tolist(), row.tolist(), col.tolist())) == expected
    # 2**60 + 256 - r rounds to 2**60 (inside the box) for rows r > 128, though 2**60 + 256 - 2**60 = 256
    trees = np.full((1, 400, 400), TreeState.EXISTING, np.uint8)
    trees[0, [200, 300], 3] = TreeState.BURNING
    query = (0, 2.0**60 + 256.0, 3.0, 2.0**60)
    assert brute_closest(state_of(trees), *query) == (True, 200, 3)  # equally far (float), lowest index
    for found, row, col in each_pairing(state_of(trees), np.array([0]), np.array([query[1]]), np.array([3.0]), 2.0**60):
        assert (found[0], row[0], col[0]) == (True, 200, 3)


@pytest.mark.parametrize("half", [1, 4, 9, 17])
@pytest.mark.parametrize("edge", [(-1, 0), (1, 0), (0, -1), (0, 1)], ids=["top", "bottom", "left", "right"])
def test_closest_burning_reaches_each_edge_of_its_box_at_every_alignment(half, edge):
    """World w of 48 burns only along one edge of the box around its query, which sweeps row w (col w for
    the left and right edges) with the other coordinate 23.

    The nearest burning cell is the edge's midpoint, exactly half_box_cells away, found while that edge
    lies on the grid. The sweep moves the edge across every offset from the block edges of the block index.
    """
    cells, (d_row, d_col) = 48, edge
    sweep, fixed = np.arange(cells), np.full(cells, 23)
    q_row, q_col = (sweep, fixed) if d_row else (fixed, sweep)
    r, c = np.meshgrid(np.arange(cells), np.arange(cells), indexing="ij")
    off_row, off_col = r - q_row[:, None, None], c - q_col[:, None, None]
    along = np.abs(off_col) <= half if d_row else np.abs(off_row) <= half
    on_edge = along & ((off_row == d_row * half) if d_row else (off_col == d_col * half))
    state = state_of(np.where(on_edge, TreeState.BURNING, TreeState.EXISTING))
    middle_row, middle_col = q_row + d_row * half, q_col + d_col * half
    on_grid = (middle_row >= 0) & (middle_row < cells) & (middle_col >= 0) & (middle_col < cells)
    for found, row, col in each_pairing(state, sweep, q_row.astype(float), q_col.astype(float), float(half)):
        assert found.tolist() == on_grid.tolist()
        assert row.tolist() == np.where(on_grid, middle_row, -1).tolist()
        assert col.tolist() == np.where(on_grid, middle_col, -1).tolist()


@st.composite
def large_fires(draw):
    """Up to 3 worlds of up to 64 x 64 cells where a drawn share of the cells burns (sparse to nearly all)."""
    batch, cells = draw(st.integers(1, 3)), draw(st.integers(9, 64))
    share = draw(st.sampled_from([0.01, 0.05, 0.2, 0.6, 0.95]))
    rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    trees = rng.choice(np.array([TreeState.NONE, TreeState.EXISTING, TreeState.BURNT, TreeState.WET], np.uint8),
                       (batch, cells, cells))
    trees[rng.random(trees.shape) < share] = TreeState.BURNING
    state = state_of(trees)
    order = rng.permutation(len(state.burning))
    return FireState(trees=state.trees, burning=state.burning[order], age=state.age, quiet=state.quiet, out=state.out,
                     ignited=state.ignited, burnt_out=state.burnt_out)


@settings(max_examples=100, deadline=None)
@given(large_fires(), st.data())
def test_closest_burning_matches_brute_force_on_large_fronts(state, data):
    """Thousands of burning cells and up to 40 queries: enough pairs for the block index to be chosen."""
    cells = state.cells
    spot = st.floats(-12.0, cells + 12.0)
    box = st.one_of(st.floats(0.0, cells / 2.0), st.integers(0, cells).map(float), st.just(float(cells) * 3))
    count = data.draw(st.integers(1, 40))
    world = np.array(data.draw(st.lists(st.integers(0, state.batch - 1), min_size=count, max_size=count)))
    rows, cols = (np.array(data.draw(st.lists(spot, min_size=count, max_size=count))) for _ in range(2))
    half = np.array(data.draw(st.lists(box, min_size=count, max_size=count)))
    half_box = data.draw(st.one_of(st.just(half), box))
    half = np.broadcast_to(half_box, (count,))
    expected = []
    for w, qr, qc, h in zip(world, rows, cols, half):
        r, c = np.nonzero(state.trees[w] == TreeState.BURNING)  # row-major: argmin takes the lowest flat index
        dr, dc = r - qr, c - qc
        distance = np.where((np.abs(dr) <= h) & (np.abs(dc) <= h), dr * dr + dc * dc, np.inf)
        hit = int(np.argmin(distance)) if len(distance) and np.isfinite(distance.min()) else None
        expected.append((True, r[hit], c[hit]) if hit is not None else (False, -1, -1))
    for found, row, col in each_pairing(state, world, rows, cols, half_box):
        assert list(zip(found.tolist(), row.tolist(), col.tolist())) == expected


@settings(max_examples=150, deadline=None)
@given(fires(), st.lists(st.tuples(st.integers(0, 2), coordinate(), coordinate(), st.integers(0, 3)), max_size=6),
       st.one_of(st.sampled_from([0.0, 0.5, 1.0, 1.5, 3.0]), st.floats(0.0, 4.0)))
def test_douse_matches_brute_force(state, points, radius):
    points = [(w % state.batch, r, c, o) for w, r, c, o in points]
    before = state.trees.copy()
    expected_trees, extinguished, prepared = before.copy(), np.zeros(4, int), np.zeros(4, int)
    for w, r, c in zip(*np.nonzero((before == TreeState.EXISTING) | (before == TreeState.BURNING))):
        owners = [o for pw, pr, pc, o in points if pw == w and (r - pr) ** 2 + (c - pc) ** 2 <= radius * radius]
        if owners:
            expected_trees[w, r, c] = TreeState.WET
            (extinguished if before[w, r, c] == TreeState.BURNING else prepared)[min(owners)] += 1
    if points:
        state, got_extinguished, got_prepared = drop(state, points, radius)
    else:
        state, got_extinguished, got_prepared = douse(state, np.zeros(0, int), np.zeros(0), np.zeros(0), radius,
                                                      np.zeros(0, int), 4)
    np.testing.assert_array_equal(state.trees, expected_trees)
    assert got_extinguished.tolist() == extinguished.tolist() and got_prepared.tolist() == prepared.tolist()
    assert sorted(state.burning.tolist()) == np.flatnonzero(expected_trees == TreeState.BURNING).tolist()
