"""Where the fire starts under params.fire_start 'release': the release's InitiateFireEnvProbability, one block.

Read from the AWS release's IL (the reward table's note 'The release's fire start and burning queue'): candidates
are every tenth cell holding a tree, ranked driest first; the list of burning trees is replaced by each
candidate's 5 x 5 block in turn, the first's kept if it holds 15 trees or more, else the loop stops at the first
holding more than 15. This toolkit's 'running' rule adds blocks until their running count passes 15, so its fires
often start in two places or more. Worked by hand on a 30 x 30 grid.
"""

from __future__ import annotations

import numpy as np
import pytest

import hivex_dsl
from hivex_dsl.sim.fire import TreeState
from hivex_dsl.sim.procgen.forest import IgnitionSpec, ranked_ignition_mask, release_ignition_block

SPEC = IgnitionSpec()  # 5 x 5 blocks, more than 15 trees


@pytest.mark.parametrize("counts, chosen", [
    ([15, 20, 30], 0),  # the first block is kept at 15 trees or more
    ([14, 16, 30], 1),  # else the first holding more than 15
    ([14, 15, 16], 2),  # 15 is not more than 15
    ([3, 4, 5], 2),  # none does: the last block the loop tried
    ([0], 0),
])
def test_the_release_keeps_one_block(counts, chosen):
    assert release_ignition_block(np.array(counts), 15) == chosen


def block(exists: np.ndarray, centre: tuple[int, int], trees: int, own_tree: bool = True) -> None:
    """Plant ``trees`` trees in the 5 x 5 block around ``centre``, row-major, its own cell first or left bare."""
    rows, cols = np.meshgrid(np.arange(centre[0] - 2, centre[0] + 3), np.arange(centre[1] - 2, centre[1] + 3),
                             indexing="ij")
    cells = [(r, c) for r, c in zip(rows.ravel(), cols.ravel()) if (r, c) != centre]
    planted = ([centre] if own_tree else []) + cells[:trees - (1 if own_tree else 0)]
    for r, c in planted:
        exists[r, c] = True


def grid() -> tuple[np.ndarray, np.ndarray]:
    exists = np.zeros((30, 30), bool)
    block(exists, (10, 10), 24, own_tree=False)  # driest, but no tree on its own cell
    block(exists, (20, 20), 14)
    block(exists, (10, 20), 16)
    block(exists, (20, 10), 25)
    return exists, np.array([(10, 10), (20, 20), (10, 20), (20, 10)])


def burning_blocks(mask: np.ndarray) -> dict[tuple[int, int], int]:
    rows, cols = np.nonzero(mask)
    centres = zip(np.rint(rows / 10).astype(int) * 10, np.rint(cols / 10).astype(int) * 10)
    found: dict[tuple[int, int], int] = {}
    for centre in centres:
        found[centre] = found.get(centre, 0) + 1
    return found


def test_the_release_skips_a_bare_candidate_and_a_block_too_small():
    exists, ranked = grid()
    assert burning_blocks(ranked_ignition_mask(exists, SPEC, ranked, "release")) == {(10, 20): 16}
    assert burning_blocks(ranked_ignition_mask(exists, SPEC, ranked, "running")) == {(10, 10): 24}


def test_the_running_rule_lights_two_places_where_the_release_lights_one():
    exists, ranked = grid()
    mixed = ranked[1:3]  # 14 trees, then 16
    assert burning_blocks(ranked_ignition_mask(exists, SPEC, mixed, "running")) == {(20, 20): 14, (10, 20): 16}
    assert burning_blocks(ranked_ignition_mask(exists, SPEC, mixed, "release")) == {(10, 20): 16}


def test_no_candidate_with_a_tree_lights_nothing():
    exists, ranked = grid()
    assert not ranked_ignition_mask(exists, SPEC, ranked[:1], "release").any()


def test_the_islands_start_one_fire_in_one_block():
    scenario = {"hivex": 1, "environment": "aerial_wildfire_suppression", "task": "main", "params": {}}
    starts = {}
    for rule in ("running", "release"):
        compiled = hivex_dsl.compile({**scenario, "params": {"fire_start": rule}})
        state = compiled.entry.make_simulator(compiled).reset(np.random.default_rng(compiled.seeds.test), 8)
        starts[rule] = [burning_blocks(trees == TreeState.BURNING) for trees in state.fire.trees]
    assert all(len(blocks) == 1 and sum(blocks.values()) >= 15 for blocks in starts["release"])
    assert any(len(blocks) > 1 for blocks in starts["running"])  # level 1's sparse blocks: several places
