"""The safe YAML loader: located marks, and refusal of what a scenario must never contain."""

from __future__ import annotations

import pytest

from hivex_dsl.base.errors import Location, ScenarioError
from hivex_dsl.lang.loader import MAX_DEPTH, load_file, load_text


def first_problem(text: str) -> str:
    """``LINE:COL: message`` of the first problem of loading ``text``."""
    with pytest.raises(ScenarioError) as caught:
        load_text(text, "s.yaml")
    problem = caught.value.problems[0]
    assert problem.location.path == "s.yaml"
    return f"{problem.location.line}:{problem.location.col}: {problem.message}"


# --- located marks ---------------------------------------------------------------------------------

NESTED = """\
hivex: 1
seeds:
  train: [11, 22,
          33]
  test:
    - 44
    -   55
params: {drag: 0.5}
"""


def test_values_and_keys_are_located_at_nested_keys_and_list_items():
    loaded = load_text(NESTED, "n.yaml")
    assert loaded.data == {"hivex": 1, "seeds": {"train": [11, 22, 33], "test": [44, 55]}, "params": {"drag": 0.5}}
    at = lambda line, col: Location("n.yaml", line, col)  # noqa: E731
    assert loaded.marks[("hivex",)] == at(1, 8)
    assert loaded.marks[("seeds",)] == at(3, 3)
    assert loaded.key_marks[("seeds",)] == at(2, 1)
    assert loaded.key_marks[("seeds", "train")] == at(3, 3)
    assert loaded.marks[("seeds", "train")] == at(3, 10)
    assert loaded.marks[("seeds", "train", 0)] == at(3, 11)
    assert loaded.marks[("seeds", "train", 1)] == at(3, 15)
    assert loaded.marks[("seeds", "train", 2)] == at(4, 11)
    assert loaded.key_marks[("seeds", "test")] == at(5, 3)
    assert loaded.marks[("seeds", "test", 0)] == at(6, 7)
    assert loaded.marks[("seeds", "test", 1)] == at(7, 9)
    assert loaded.key_marks[("params", "drag")] == at(8, 10)
    assert loaded.marks[("params", "drag")] == at(8, 16)


def test_locate_falls_back_to_the_nearest_written_ancestor():
    loaded = load_text(NESTED, "n.yaml")
    assert loaded.locate(("params", "wind_drift_m")) == Location("n.yaml", 8, 9)
    assert loaded.locate(("seeds", "train", 1), key=True) == Location("n.yaml", 3, 15)
    assert loaded.locate(("seeds", "train"), key=True) == Location("n.yaml", 3, 3)
    assert loaded.locate(("nowhere",)) == Location("n.yaml", 1, 1)


# --- duplicate and non-string keys ---------------------------------------------------------------


def test_duplicate_top_level_key():
    assert first_problem("agents: 1\nhivex: 1\nagents: 2\n") == \
        "3:1: duplicate key 'agents' (first written at line 1); a key may appear once"


def test_duplicate_nested_key_names_its_mapping():
    assert first_problem("params:\n  drag: 1\n  other: 2\n  drag: 3\n") == \
        "4:3: duplicate key 'drag' in 'params' (first written at line 2); a key may appear once"
    assert first_problem("seeds: {train: 1, train: 2}\n") == \
        "1:19: duplicate key 'train' in 'seeds' (first written at line 1); a key may appear once"


@pytest.mark.parametrize(("text", "expected"), [
    ("a: 1\n1: 2\n", "2:1: a key must be a name, got 1 (an integer); quote it if it is meant as a name"),
    ("a: 1\n2.5: 2\n", "2:1: a key must be a name, got 2.5 (a number); quote it if it is meant as a name"),
    ("a: 1\non: 2\n", "2:1: a key must be a name, got on (a boolean); quote it if it is meant as a name"),
    ("a: 1\n~: 2\n", "2:1: a key must be a name, got ~ (null); quote it if it is meant as a name"),
    ("a: 1\n[x, y]: 2\n", "2:1: a key must be a plain name, got a list"),
    ("a: 1\n? {x: 1}\n: 2\n", "2:3: a key must be a plain name, got a mapping"),
    ("a: 1\n!foo b: 2\n", "2:1: a key must be a plain name, not a value tagged '!foo'"),
])
def test_non_string_keys_are_refused(text, expected):
    assert first_problem(text) == expected


def test_quoted_keys_are_names():
    assert load_text("'1': a\n\"on\": b\n").data == {"1": "a", "on": "b"}


# --- tags ---------------------------------------------------------------------------------------


@pytest.mark.parametrize(("text", "expected"), [
    ("a: !!python/object/apply:os.system [ls]\n",
     "1:4: YAML tag '!!python/object/apply:os.system' is not allowed: a scenario holds plain data only "
     "(no tags that construct objects)"),
    ("a:\n  b: !!python/name:os.system ''\n",
     "2:6: YAML tag '!!python/name:os.system' is not allowed: a scenario holds plain data only "
     "(no tags that construct objects)"),
    ("a: [1, !foo 2]\n", "1:8: YAML tag '!foo' is not allowed: a scenario holds plain data only "
                         "(no tags that construct objects)"),
    ("a: !!set {x: null}\n", "1:4: YAML tag '!!set' is not allowed: a scenario holds plain data only "
                             "(no tags that construct objects)"),
    ("a: !!binary aGVsbG8=\n", "1:4: YAML tag '!!binary' is not allowed: a scenario holds plain data only "
                               "(no tags that construct objects)"),
    ("a: !!str [1]\n", "1:4: YAML tag '!!str' cannot be put on a list"),
    ("a: !!seq x\n", "1:4: YAML tag '!!seq' cannot be put on a single value"),
    ("a: !!int 0.5\n", "1:4: a: '0.5' cannot be read as an integer"),
    ("a: !!bool maybe\n", "1:4: a: 'maybe' cannot be read as true or false"),
])
def test_object_constructing_and_mismatched_tags_are_refused(text, expected):
    assert first_problem(text) == expected


def test_standard_tags_on_fitting_values_are_plain_data():
    assert load_text("a: !!str 1\nb: !!int '5'\nc: !!float '2'\nd: !!map {x: 1}\n").data == \
        {"a": "1", "b": 5, "c": 2.0, "d": {"x": 1}}


# --- aliases -------------------------------------------------------------------------------------


BOMB = "".join(
    ['a: &a ["lol", "lol", "lol", "lol", "lol", "lol", "lol", "lol", "lol", "lol"]\n']
    + [f"{c}: &{c} [{', '.join(['*' + p] * 10)}]\n" for p, c in zip("abcdefgh", "bcdefghi")]
)


def test_alias_bomb_is_refused_where_the_aliases_multiply():
    # a has 11 values, b 111, c 1111, d 11111, e 111111: e (line 5) is the first part over 100,000
    assert first_problem(BOMB) == \
        "5:4: this value expands to more than 100,000 values (an alias bomb?); refusing to read it"


def test_recursive_alias_is_refused():
    assert "(a recursive alias?)" in first_problem("a: &a [1, *a]\n")
    assert "(a recursive alias?)" in first_problem("a: &a {b: *a}\n")


def test_ordinary_anchors_and_aliases_still_work_and_are_located_where_written():
    text = "base: &b {drag: 0.5, list: [1, 2]}\ncopy: *b\nseed: &s 7\nagain: [*s, 8]\n"
    loaded = load_text(text, "a.yaml")
    assert loaded.data == {"base": {"drag": 0.5, "list": [1, 2]}, "copy": {"drag": 0.5, "list": [1, 2]},
                           "seed": 7, "again": [7, 8]}
    loaded.data["copy"]["list"].append(3)  # copies, not shared objects
    assert loaded.data["base"]["list"] == [1, 2]
    assert loaded.marks[("copy",)] == Location("a.yaml", 2, 7)  # the alias, not the anchor
    assert loaded.marks[("again", 0)] == Location("a.yaml", 4, 9)
    assert loaded.marks[("copy", "drag")] == Location("a.yaml", 1, 17)  # inside the anchored text


def test_merge_keys_are_refused():
    assert first_problem("base: &b {x: 1}\nother:\n  <<: *b\n") == \
        "3:3: merge keys ('<<') are not supported: write the keys out"


# --- depth, documents, encodings ----------------------------------------------------------------


def test_nesting_up_to_the_depth_bound_loads():
    levels = MAX_DEPTH + 1  # the top-level value and MAX_DEPTH levels below it
    data = load_text("[" * levels + "]" * levels).data
    for _ in range(levels - 1):
        data = data[0]
    assert data == []


def test_nesting_beyond_the_depth_bound_is_refused_at_the_first_level_too_deep():
    levels = MAX_DEPTH + 2
    assert first_problem("[" * levels + "]" * levels) == \
        f"1:{levels}: document nests deeper than {MAX_DEPTH} levels; refusing to read it"


def test_very_deep_nesting_is_a_located_error_not_a_recursion_error():
    text = "a:\n  " + "[" * 100_000 + "]" * 100_000 + "\n"
    assert first_problem(text).startswith(f"2:{MAX_DEPTH + 3}: document nests deeper than {MAX_DEPTH} levels")


def test_a_second_document_is_refused_at_its_start():
    assert first_problem("a: 1\n---\nb: 2\n") == "2:1: a file holds one scenario; found a second YAML document"
    assert first_problem("a: 1\n...\n---\nb: 2\n") == "3:1: a file holds one scenario; found a second YAML document"
    assert first_problem("a: 1\n--- [x]\n") == "2:1: a file holds one scenario; found a second YAML document"


def test_a_leading_marker_or_trailing_empty_document_is_one_document():
    assert load_text("---\na: 1\n").data == {"a": 1}
    assert load_text("a: 1\n---\n# nothing\n").data == {"a": 1}


def test_empty_and_comment_only_files():
    expected = "1:1: the file is empty: expected a mapping with at least 'hivex' and 'environment'"
    assert first_problem("") == expected
    assert first_problem("# just a comment\n\n   \n") == expected


def test_syntax_errors_are_located():
    assert first_problem("a: [1, 2\n") == ("1:4: not valid YAML: the '[' opened here is never closed: "
                                            "expected ',' or ']', but got '<stream end>' at line 2, column 1")
    assert first_problem("a:\n\tb: 1\n") == "2:1: not valid YAML: found character '\\t' that cannot start any token"


def test_exponent_floats_are_numbers_as_in_json_and_yaml_1_2():
    loaded = load_text("a: 1e-3\nb: 1e+16\nc: 2.5E3\nd: -1e5\ne: '1e5'\nf: 1e\ng: 1_000\n")
    assert loaded.data == {"a": 0.001, "b": 1e16, "c": 2500.0, "d": -100000.0, "e": "1e5", "f": "1e", "g": 1000}
    assert isinstance(loaded.data["b"], float)


def test_files(tmp_path):
    assert load_file(_write(tmp_path / "ok.yaml", "a: 'caf\u00e9'\n".encode())).data == {"a": "caf\u00e9"}
    with pytest.raises(ScenarioError) as caught:
        load_file(_write(tmp_path / "latin1.yaml", "a: 1\nb: 'caf\u00e9'\n".encode("latin-1")))
    assert str(caught.value) == f"{tmp_path / 'latin1.yaml'}:2:8: byte 0xe9 is not valid UTF-8: expected UTF-8 encoded YAML"
    with pytest.raises(ScenarioError) as caught:
        load_file(tmp_path / "missing.yaml")
    assert caught.value.problems[0].message == f"no such file: {tmp_path / 'missing.yaml'}"
    with pytest.raises(ScenarioError) as caught:
        load_file(tmp_path)
    assert caught.value.problems[0].message == f"{tmp_path} is a directory, expected a YAML file"


def test_json_is_read_by_the_same_loader():
    loaded = load_text('{\n  "a": [1, 2.5e-07, "x"],\n  "b": {"c": null}\n}\n', "l.json")
    assert loaded.data == {"a": [1, 2.5e-07, "x"], "b": {"c": None}}
    assert loaded.marks[("a", 1)] == Location("l.json", 2, 12)


def test_line_breaks_in_quoted_keys_do_not_break_one_line_messages():
    message = first_problem('"a\\nb": 1\n"a\\nb": 2\n')
    assert len(message.splitlines()) == 1 and "a\\nb" in message


def _write(path, data: bytes):
    path.write_bytes(data)
    return path


# --- YAML 1.1 readings: refused when they would rewrite what was written, kept when every reading agrees ---


@pytest.mark.parametrize("text, expected", [
    ("a: 0123\n", "1:4: a: 0123 has a leading zero, which YAML 1.1 reads as the octal number 83; "
                  "write the plain decimal form 83, or 123 if that is what was meant"),
    ("a: -0_7\n", "1:4: a: -0_7 has a leading zero, which YAML 1.1 reads as the octal number -7; "
                  "write the plain decimal form -7"),
    ("a: [1:30]\n", "1:5: a[0]: 1:30 is read by YAML 1.1 as a base-60 number (90); write 90, "
                    "or quote it ('1:30') if it is meant as text"),
    ("a: 1:30.5\n", "1:4: a: 1:30.5 is read by YAML 1.1 as a base-60 number (90.5); write 90.5, "
                    "or quote it ('1:30.5') if it is meant as text"),
    ("a: {b: On}\n", "1:8: a.b: On is read by YAML 1.1 as the boolean true; write true, "
                     "or quote it ('On') if it is meant as text"),
    ("a: NO\n", "1:4: a: NO is read by YAML 1.1 as the boolean false; write false, or quote it ('NO') if it is meant as text"),
    ("a: 1__0\n", "1:4: a: 1__0 is read by YAML 1.1 as 10; write the plain form 10"),
    ("a: 2_.5\n", "1:4: a: 2_.5 is read by YAML 1.1 as 2.5; write the plain form 2.5"),
])
def test_yaml_1_1_readings_are_refused_with_the_reading_and_the_plain_form(text, expected):
    assert first_problem(text) == expected


def test_spellings_every_reading_agrees_on_are_kept():
    loaded = load_text("a: 0x1F\nb: 0b101\nc: 1_000\nd: 0\ne: 0.5\nf: true\ng: FALSE\nh: ~\ni: .inf\nj: '0123'\n"
                       "k: \"1:30\"\nl: 'yes'\nm: =\nn: -0.0\n")
    assert loaded.data == {"a": 31, "b": 5, "c": 1000, "d": 0, "e": 0.5, "f": True, "g": False, "h": None,
                           "i": float("inf"), "j": "0123", "k": "1:30", "l": "yes", "m": "=", "n": -0.0}


@pytest.mark.parametrize("code", [c for c in range(0x20) if c not in (0x09, 0x0A, 0x0D)] + [0x7F, 0x80, 0x9F, 0xFFFE])
def test_every_control_character_is_refused_by_name_where_it_stands(code):
    message = first_problem(f"a: 1\nb: 'x{chr(code)}'\n")
    assert message.startswith(f"2:6: U+{code:04X} ")
    assert message.endswith(f"is not allowed in YAML: expected printable text "
                            f"(inside double quotes the escape \"\\x{code:02x}\" writes it)"
                            if code < 0x100 else f"(inside double quotes the escape \"\\u{code:04x}\" writes it)")


def test_escaped_control_characters_in_double_quotes_are_read():
    assert load_text('a: "x\\f\\x1b\\u0085"\n').data == {"a": "x\x0c\x1b\x85"}


def test_control_characters_are_named():
    from hivex_dsl.lang.yaml11 import character_name

    assert character_name(0x0C) == "U+000C FORM FEED"
    assert character_name(0x1B) == "U+001B ESCAPE"
    assert character_name(0x00) == "U+0000 NULL"
    assert character_name(0x7F) == "U+007F DELETE"
    assert character_name(0x9B) == "U+009B (a C1 control character)"
    assert character_name(0xFFFE) == "U+FFFE (a noncharacter)"


def test_a_too_long_integer_names_its_field():
    import sys

    limit = sys.get_int_max_str_digits()
    assert first_problem(f"a:\n  b: {'7' * (limit + 1)}\n") == (
        f"2:6: a.b: a {limit + 1:,}-digit integer is too long to read: expected a number of at most {limit:,} digits")


def test_unclosed_quotes_and_brackets_are_located_where_they_open():
    assert first_problem("a: 1\nb: 'x\nc: 2\n") == ("2:4: not valid YAML: the quoted string opened here is never closed: "
                                                    "found unexpected end of stream at line 4, column 1")
    assert first_problem("a: {x: 1\nb: 2\n") == ("1:4: not valid YAML: the '{' opened here is not closed in time: "
                                                 "expected ',' or '}', but got ':' at line 2, column 2 (a missing '}' or ',')")
    assert first_problem("a: {x: 1\n") == ("1:4: not valid YAML: the '{' opened here is never closed: "
                                          "expected ',' or '}', but got '<stream end>' at line 2, column 1")
    # closed on its own line: the trouble is where it stands
    assert first_problem("a: [1: 2: 3]\n") == "1:9: not valid YAML: expected ',' or ']', but got ':' (inside the '[' at column 4)"
