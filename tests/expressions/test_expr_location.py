"""An offset into an expression maps back to the line and column where the file wrote that character."""

from __future__ import annotations

import pytest

import hivex_dsl
from hivex_dsl import ScenarioError
from hivex_dsl.lang.loader import load_file
from hivex_dsl.sim.reward.expressions import UNTRACED
from hivex_dsl.lang.spec.expr_location import expression_location

STYLES = {
    "plain": "expr: max(x_m, 2) + abs(y_m)\n",
    "plain_folded": "expr: max(x_m, 2) +\n  abs(y_m) *\n  3\n",
    "single": "expr: 'where(a == b, ''q'', c_1)'\n",
    "double": 'expr: "min(a,\\tb) + \\x41bc + q_2"\n',
    "double_folded": 'expr: "min(a, b)\n   + clip(c, 0, 1)"\n',
    "literal": "expr: |\n  where(x_m > 0,\n        y_m, 0)\nnext: 1\n",
    "folded": "expr: >-\n  team_mean(x_m)\n  - delta(y_m)\nnext: 1\n",
    "flow": "{other: 1, expr: 'sqrt(x_m) + 1'}\n",
    # a folded block keeps the line breaks around more-indented lines (they are not joined with spaces)
    "folded_more_indented": "expr: >-\n  where(x_m > 0,\n        y_m,\n      0)\n\n  + z_m\nnext: 1\n",
    "folded_keep_comment": "expr: >+ # the header may carry a comment\n  a_m\n\n\n   - b_m\n  c_m\n\nnext: 1\n",
    "literal_indicator": "expr: |2-\n    where(x_m,\n  y_m)\n",
    "folded_crlf": "expr: >\r\n  abs(x_m)\r\n    + y_m\r\n  * 2\r\n",
    "double_blank_line": 'expr: "min(a, b)\n\n\n   + clip(c, 0, 1)"\n',
}


@pytest.mark.parametrize("style", STYLES)
def test_every_character_maps_back_to_where_it_is_written(style, tmp_path):
    path = tmp_path / f"{style}.yaml"
    path.write_bytes(STYLES[style].encode())
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


def test_a_scalar_that_cannot_be_followed_is_blamed_at_its_start_and_the_message_says_so(tmp_path):
    """An escaped line break followed by a blank line inside double quotes is not followed: the problem is
    reported where the value starts, with a note, never at a wrong column."""
    path = tmp_path / "untraced.yaml"
    path.write_text('hivex: 1\nenvironment: wind_farm_control\nterms:\n  t1:\n'
                    '    expr: "where(alignment > 0.5, 1, \\\n\n      2 * alignmnet)"\n')
    with pytest.raises(ScenarioError) as caught:
        hivex_dsl.compile(path)
    problem = caught.value.first
    assert (problem.location.line, problem.location.col) == (5, 11)
    assert problem.message == (f"terms.t1.expr: unknown quantity 'alignmnet'; did you mean 'alignment'? ({UNTRACED})")


def test_a_dict_scenario_has_no_file_to_follow_and_says_nothing_of_it():
    with pytest.raises(ScenarioError) as caught:
        hivex_dsl.compile({"hivex": 1, "environment": "wind_farm_control", "terms": {"t1": "2 * alignmnet"}})
    assert UNTRACED not in caught.value.first.message
