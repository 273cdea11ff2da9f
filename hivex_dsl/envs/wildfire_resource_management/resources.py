"""The nine watchtowers, their neighbour table and the bookkeeping of the resources they share.

Towers sit on a 3 x 3 grid, index ``i = 3 * row + col`` with ``x = (col - 1) * s`` and
``y = (row - 1) * s`` (row 0 is the south edge, col 0 the west edge):

    6 7 8      north (+y)
    3 4 5
    0 1 2      south (-y)

Each tower's three neighbours are the other towers ordered by distance, ties broken by the lower
tower index; neighbour 1 is the nearest. On the grid only the centre tower has a tie (four
towers at distance s); the rule keeps 1, 3, 5 and drops 7. The paper's process figure
(hivex-environments' docs/images/WRM_process.jpg, numbered as here) draws tower 2's three
neighbours as 1, 4 and 5 and tower 0's as 1, 3 and 4: a corner's two edges and the centre, as
the rule gives. So every tower but the centre counts the centre among its neighbours.

Resources are integers in tenths (no float drift). Agent ``i`` owns 10 tenths: ``budget[i]``
unallocated plus ``allocation[i, k]`` given to target ``k`` (0 itself, 1-3 its neighbours), so
``budget + allocation.sum(-1) == 10`` always. An action component 1 (add) moves a tenth from the
budget to its target, 2 (subtract) moves one back; one that cannot happen (no budget left, nothing
allocated to that target) does nothing and is counted as impossible.
"""

from __future__ import annotations

import numpy as np

GRID = 3
TOWERS = GRID * GRID
NEIGHBOURS_PER_TOWER = 3
TARGETS_PER_AGENT = 1 + NEIGHBOURS_PER_TOWER
TENTHS = 10  # one agent's whole resource, 1.0
NOOP, ADD, SUBTRACT = 0, 1, 2


def grid_offsets() -> np.ndarray:
    """(9, 2) int64 tower positions in units of the spacing: (col - 1, row - 1) of tower 3 * row + col."""
    row, col = np.divmod(np.arange(TOWERS), GRID)
    return np.stack([col - 1, row - 1], axis=-1)


def neighbour_table(offsets: np.ndarray, count: int = NEIGHBOURS_PER_TOWER) -> np.ndarray:
    """(N, count) int64: for each tower the ``count`` other towers nearest to it, ties to the lower index.

    ``offsets`` (N, 2) are integer grid positions, so squared distances compare exactly.
    """
    gap = offsets[:, None, :] - offsets[None, :, :]
    squared = (gap * gap).sum(axis=-1)
    towers = len(offsets)
    index = np.broadcast_to(np.arange(towers), (towers, towers))
    squared = np.where(np.eye(towers, dtype=bool), np.iinfo(np.int64).max, squared)
    order = np.lexsort((index, squared), axis=-1)  # last key sorts first: distance, then index
    return order[:, :count]


NEIGHBOURS = neighbour_table(grid_offsets())
TARGETS = np.concatenate([np.arange(TOWERS)[:, None], NEIGHBOURS], axis=1)  # (9, 4): self, n1, n2, n3
# (36, 9) one-hot: row a * 4 + k marks the tower agent a's target k is; support = allocation @ this
GIVES_TO = np.eye(TOWERS, dtype=np.int32)[TARGETS.reshape(-1)]
IN_DEGREE = np.bincount(NEIGHBOURS.reshape(-1), minlength=TOWERS)  # how many towers may support each one
MAX_SUPPORT_TENTHS = int(TENTHS * (1 + IN_DEGREE.max()))  # the most any tower can receive (the centre: 9.0)
for _array in (NEIGHBOURS, TARGETS, GIVES_TO, IN_DEGREE):
    _array.flags.writeable = False


def neighbour_rows() -> list[str]:
    """The neighbour table as lines for the docs: 'tower 0 (x -s, y -s): 1, 3, 4'."""
    sign = {-1: "-s", 0: "0", 1: "+s"}
    return [f"tower {i} (x {sign[int(x)]}, y {sign[int(y)]}): {', '.join(str(int(n)) for n in NEIGHBOURS[i])}"
            for i, (x, y) in enumerate(grid_offsets())]


def initial_resources(batch: int, agents: int, self_tenths: int) -> tuple[np.ndarray, np.ndarray]:
    """(allocation (B, A, 4) int16, budget (B, A) int16) at reset: ``self_tenths`` on the own tower, the rest free."""
    allocation = np.zeros((batch, agents, TARGETS_PER_AGENT), np.int16)
    allocation[..., 0] = self_tenths
    return allocation, np.full((batch, agents), TENTHS - self_tenths, np.int16)


def apply_in_order(allocation: np.ndarray, budget: np.ndarray, actions: np.ndarray
                   ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`apply_actions` written out target by target: the rule itself (it builds the step's table)."""
    allocation, budget = allocation.copy(), budget.copy()
    impossible = np.zeros(budget.shape, np.int16)
    for k in range(TARGETS_PER_AGENT):
        wish = actions[..., k]
        add = (wish == ADD) & (budget > 0)
        subtract = (wish == SUBTRACT) & (allocation[..., k] > 0)
        moved = add.astype(np.int16) - subtract
        allocation[..., k] += moved
        budget -= moved
        impossible += (wish != NOOP) & ~add & ~subtract
    return allocation, budget, impossible


# An agent's step depends only on its wishes, which targets hold something (a subtraction there succeeds)
# and its budget up to TARGETS_PER_AGENT (with that many tenths free every add succeeds): a key of
# BUDGET_LEVELS * 2^4 * 3^4 cases, whose moves (4,), budget change and impossible count are tabled.
BUDGET_LEVELS = TARGETS_PER_AGENT + 1
WISH_KEY = 3 ** np.arange(TARGETS_PER_AGENT)[::-1]  # wishes (4,) in {0, 1, 2} -> 0..80
HELD_KEY = 3**TARGETS_PER_AGENT * 2 ** np.arange(TARGETS_PER_AGENT)  # which targets hold something
BUDGET_KEY = 3**TARGETS_PER_AGENT * 2**TARGETS_PER_AGENT
BUDGET_KEYS = np.minimum(np.arange(TENTHS + 1), TARGETS_PER_AGENT) * BUDGET_KEY  # by budget 0..10
BUDGET_KEYS.flags.writeable = False


def _action_tables() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(moves (N, 4) int16, budget change (N,) int16, impossible (N,) int16) of every key case."""
    key = np.arange(BUDGET_LEVELS * BUDGET_KEY)
    level, rest = np.divmod(key, BUDGET_KEY)
    held, wish = np.divmod(rest, 3**TARGETS_PER_AGENT)
    digits = np.arange(TARGETS_PER_AGENT)
    allocation = ((held[:, None] >> digits) & 1).astype(np.int16)
    actions = wish[:, None] // WISH_KEY % 3
    after, budget, impossible = apply_in_order(allocation, level.astype(np.int16), actions)
    tables = (after - allocation, level.astype(np.int16) - budget, impossible)
    for table in tables:
        table.flags.writeable = False
    return tables


MOVES, SPENDS, IMPOSSIBLE = _action_tables()


def apply_actions(allocation: np.ndarray, budget: np.ndarray, actions: np.ndarray
                  ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """One step of add/subtract actions (B, A, 4) in {0, 1, 2}, applied target by target in order
    (self, neighbour 1, 2, 3), so a tenth freed by a subtraction can be added to a later target.

    Returns (allocation (B, A, 4) int16, budget (B, A) int16, impossible (B, A) int16 count of
    components that asked for an add without budget or a subtraction from an empty allocation).
    Looks each agent's case up in the tables :func:`apply_in_order` filled.
    """
    key = np.asarray(actions) @ WISH_KEY
    key += (allocation > 0) @ HELD_KEY
    key += BUDGET_KEYS.take(budget)
    return allocation + MOVES.take(key, axis=0), budget - SPENDS.take(key), IMPOSSIBLE.take(key)


def total_support(allocation: np.ndarray) -> np.ndarray:
    """(B, 9) int32 tenths each tower receives from every agent (itself included); ``allocation`` (B, 9, 4)."""
    return allocation.reshape(len(allocation), -1).astype(np.int32) @ GIVES_TO
