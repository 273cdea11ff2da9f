"""Arbitrary text and arbitrary mutations of every bundled scenario: `hivex validate` and the Python API
either accept the input or raise the toolkit's own ScenarioError, whose every problem is located in
the file (a line and column that exist) with a one-line message. Never a traceback."""

from __future__ import annotations

import io
from contextlib import redirect_stderr, redirect_stdout
from pathlib import Path

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import hivex_dsl
from hivex_dsl import ScenarioError
from hivex_dsl.cli import main
from hivex_dsl.lang.loader import load_text
from hivex_dsl.base.resources import bundled_scenarios

SCENARIOS = sorted(bundled_scenarios())
# every character YAML refuses or treats specially, among the ones a scenario is made of
CONTROL = [chr(c) for c in range(0x20)] + ["\x7f", "\x85", "\x9b", "\ufeff", "\u2028", "\ufffe"]
SYNTAX = list(":{}[],'\"-#&*!|>%@`?~=\n\t ") + ["0x", "0b", "0o", "_", "1:30", "yes", "off", ".inf", "---", "<<"]
VALUES = st.one_of(st.integers(-10**6, 10**6).map(str), st.floats().map(str),
                   st.sampled_from(["0123", "1:30", "yes", "off", "~", "0x1F", "1_000_", "[1, 2]", "{}", "''", '"x',
                                    "[1, true]", "{a: 1", "!!python/object:os.system", "*x", "&x 1", "9" * 5000]))
PIECES = st.one_of(st.sampled_from(SYNTAX), VALUES, st.sampled_from(["hivex: 1", "environment: ", "sweep:",
                                                                      "params:", "agents: ", "seeds: ", "\n  "]),
                   st.text(max_size=4), st.characters(), st.sampled_from(CONTROL))
FUZZ = settings(max_examples=int(__import__("os").environ.get("FUZZ_N", 60)), deadline=None, suppress_health_check=[HealthCheck.too_slow,
                                                                        HealthCheck.function_scoped_fixture])


def _check_located(text: str, path: Path) -> None:
    """compile_all and `hivex validate` on ``path`` (holding ``text``): accepted, or located ScenarioErrors."""
    path.write_text(text, encoding="utf-8")
    lines = len(text.splitlines()) + 1  # splitlines breaks at least wherever YAML does
    try:
        hivex_dsl.compile_all(path)
    except ScenarioError as exc:
        assert exc.problems
        for problem in exc.problems:
            assert problem.location.path == str(path)
            assert 1 <= problem.location.line <= lines, problem
            assert problem.location.col >= 1, problem
            assert problem.message and len(problem.message.splitlines()) == 1, problem
    out, err = io.StringIO(), io.StringIO()
    with redirect_stdout(out), redirect_stderr(err):
        code = main(["validate", str(path)])
    assert code in (0, 2)
    reported = err.getvalue().splitlines()
    assert (code == 0) == (not reported)
    assert all(line.startswith(f"{path}:") for line in reported), reported


def _check_dict(text: str) -> None:
    """What the loader reads, handed to the Python API as a dict: accepted or a ScenarioError."""
    try:
        data = load_text(text).data
    except ScenarioError:
        return
    if isinstance(data, dict):
        try:
            hivex_dsl.compile_all(data)
        except ScenarioError as exc:
            assert all(p.location.path == "<dict>" and p.message for p in exc.problems)


@FUZZ
@given(st.lists(PIECES, max_size=40).map("".join))
def test_arbitrary_text_gives_located_scenario_errors_only(tmp_path_factory, text):
    path = tmp_path_factory.mktemp("fuzz") / "arbitrary.yaml"
    _check_located(text, path)
    _check_dict(text)


@st.composite
def mutations(draw):
    """A bundled scenario with a few edits: pieces inserted, spans deleted or duplicated, lines swapped."""
    source = draw(st.sampled_from(SCENARIOS))
    text = source.read_text(encoding="utf-8")
    for _ in range(draw(st.integers(1, 3))):
        at = draw(st.integers(0, len(text)))
        kind = draw(st.sampled_from(["value", "insert", "delete", "duplicate", "swap_lines"]))
        values = [i + 2 for i in range(len(text)) if text.startswith(": ", i)]
        if kind == "value" and values:  # a value replaced by another, up to the end of its line
            start = draw(st.sampled_from(values))
            end = text.find("\n", start) if "\n" in text[start:] else len(text)
            text = text[:start] + draw(VALUES) + text[end:]
        elif kind == "insert":
            text = text[:at] + draw(PIECES) + text[at:]
        elif kind == "delete":
            text = text[:at] + text[at + draw(st.integers(1, 12)):]
        elif kind == "duplicate":
            span = text[at: at + draw(st.integers(1, 40))]
            text = text[:at] + span + text[at:]
        else:
            lines = text.split("\n")
            i, j = draw(st.integers(0, len(lines) - 1)), draw(st.integers(0, len(lines) - 1))
            lines[i], lines[j] = lines[j], lines[i]
            text = "\n".join(lines)
    return source.name, text


@FUZZ
@given(mutations())
def test_mutated_bundled_scenarios_give_located_scenario_errors_only(tmp_path_factory, mutated):
    name, text = mutated
    path = tmp_path_factory.mktemp("mutated") / name
    _check_located(text, path)
    _check_dict(text)
