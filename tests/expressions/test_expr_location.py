"""An offset into an expression maps back to the line and column where the file wrote that character."""

from __future__ import annotations

import pytest

from hivex_dsl.loader import load_file
from hivex_dsl.spec.expr_location import expression_location

STYLES = {
    "plain": "expr: max(x_m, 2) + abs(y_m)\n",
    "plain_folded": "expr: max(x_m, 2) +\n  abs(y_m) *\n  3\n",
    "single": "expr: 'where(a == b, ''q'', c_1)'\n",
    "double": 'expr: "min(a,\\tb) + \\x41bc + q_2"\n',
    "double_folded": 'expr: "min(a, b)\n   + clip(c, 0, 1)"\n',
    "literal": "expr: |\n  where(x_m > 0,\n        y_m, 0)\nnext: 1\n",
    "folded": "expr: >-\n  team_mean(x_m)\n  - delta(y_m)\nnext: 1\n",
    "flow": "{other: 1, expr: 'sqrt(x_m) + 1'}\n",
}


@pytest.mark.parametrize("style", STYLES)
def test_every_character_maps_back_to_where_it_is_written(style, tmp_path):
    path = tmp_path / f"{style}.yaml"
    path.write_text(STYLES[style])
    loaded = load_file(path)
    value = loaded.data["expr"]
    start = loaded.locate(("expr",))
    lines = STYLES[style].split("\n")
    checked = 0
    for offset, char in enumerate(value):
        if not (char.isalnum() or char in "_(),"):
            continue
        where = expression_location(start, value, offset)
        written = lines[where.line - 1][where.col - 1]
        assert written == char or (style == "double" and written == "\\"), (offset, char, where)
        checked += 1
    assert checked >= 5


def test_a_value_the_scanner_cannot_follow_falls_back_to_the_scalar_itself(tmp_path):
    path = tmp_path / "x.yaml"
    path.write_text("expr: x_m\n")
    start = load_file(path).locate(("expr",))
    assert expression_location(start, "something else", 3) == start
