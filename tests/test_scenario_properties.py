"""Property tests of the scenario language on Wind Farm Control.

(a) valid scenarios always compile, and every value written comes out unchanged;
(b) mutated scenarios (YAML text in a file) always fail with located ScenarioErrors, nothing else;
(c) a lock file compiles back to the same fingerprint, and an edited lock is refused.
"""

from __future__ import annotations

import itertools
import json
import math
import re

import annotated_types as at
import pytest
import yaml
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

import hivex_dsl
from hivex_dsl import ScenarioError
from hivex_dsl.envs.wind_farm_control.params import WindFarmControlParams
from hivex_dsl.sim.procgen.layouts import PATTERN_NAMES, layout_problem

ENV = "wind_farm_control"
# rewards/wind_farm_control.yaml: the columns (tasks) and their weights per term
TASKS = ("generate_energy", "avoid_damage")
COLUMNS = ({"generate_energy": 1.0, "avoid_damage": 0.0}, {"generate_energy": 0.0, "avoid_damage": 1.0})
TERMS = ("generate_energy", "avoid_damage")
MAX_WEIGHT = 1e6
MAX_SEED = 2**32 - 1
DEFAULT_SEEDS = {"train": 5000, "test": 6000}
DEFAULT_AGENTS, DEFAULT_EPISODE_LENGTH = 8, 5000
TOP_KEYS = ("hivex", "name", "description", "environment", "task", "pattern", "agents", "episode_length",
            "seeds", "weights", "params", "sweep")

FIELDS = WindFarmControlParams.model_fields
PARAM_NAMES = tuple(FIELDS)
DEFAULTS = {name: field.default for name, field in FIELDS.items()}

EXAMPLES = settings(max_examples=100, deadline=None, suppress_health_check=[HealthCheck.too_slow])


def bounds(name: str) -> tuple[float, bool, float, bool]:
    """(low, low inclusive, high, high inclusive) of a param, from its field metadata."""
    low = high = None
    for meta in FIELDS[name].metadata:
        if isinstance(meta, at.Ge):
            low = (meta.ge, True)
        elif isinstance(meta, at.Gt):
            low = (meta.gt, False)
        elif isinstance(meta, at.Le):
            high = (meta.le, True)
        elif isinstance(meta, at.Lt):
            high = (meta.lt, False)
    assert low and high, f"params.{name} must be bounded on both sides"
    return low[0], low[1], high[0], high[1]


def is_int_param(name: str) -> bool:
    return FIELDS[name].annotation is int


def param_values(name: str) -> st.SearchStrategy:
    low, low_in, high, high_in = bounds(name)
    if is_int_param(name):
        return st.integers(math.ceil(low) if low_in else math.floor(low) + 1,
                           math.floor(high) if high_in else math.ceil(high) - 1)
    return st.floats(low, high, exclude_min=not low_in, exclude_max=not high_in, allow_nan=False,
                     allow_infinity=False)


def out_of_range(name: str) -> st.SearchStrategy:
    low, low_in, high, high_in = bounds(name)
    if is_int_param(name):
        below = st.integers(max_value=math.ceil(low) - 1 if low_in else math.floor(low))
        above = st.integers(min_value=math.floor(high) + 1 if high_in else math.ceil(high))
    else:
        below = st.floats(max_value=low, exclude_max=low_in, allow_nan=False, allow_infinity=False)
        above = st.floats(min_value=high, exclude_min=high_in, allow_nan=False, allow_infinity=False)
    return st.one_of(below, above)


def seed_sets(excluded: set[int]) -> st.SearchStrategy:
    seed = st.integers(0, MAX_SEED).filter(lambda s: s not in excluded)
    return st.one_of(seed, st.lists(seed, min_size=1, max_size=5, unique=True))


def as_set(seeds) -> set[int]:
    return {seeds} if isinstance(seeds, int) else set(seeds)


# Names and descriptions start with a letter: PyYAML's dumper writes YAML 1.1, where a plain
# 1e5 is a string, while this loader (like YAML 1.2 and JSON) reads it as a number.
NAMES = st.from_regex(r"[A-Za-z][A-Za-z0-9_.\-\[\]=,]{0,30}", fullmatch=True)
DESCRIPTIONS = st.builds(lambda s: "About " + s, st.text(st.characters(blacklist_categories=("Cs", "Cc")), max_size=40))


@st.composite
def valid_scenarios(draw) -> dict:
    """A valid scenario: random subsets of the optional fields, every value in range."""
    d: dict = {"hivex": 1, "environment": ENV}
    if draw(st.booleans()):
        d["name"] = draw(NAMES)
    if draw(st.booleans()):
        d["description"] = draw(DESCRIPTIONS)
    if draw(st.booleans()):
        d["task"] = draw(st.one_of(st.sampled_from(TASKS), st.integers(0, len(TASKS) - 1)))
    pattern = draw(st.integers(0, len(PATTERN_NAMES) - 1))
    if draw(st.booleans()):
        d["pattern"] = draw(st.sampled_from([pattern, PATTERN_NAMES[pattern]]))
    else:
        pattern = 0
    chosen = draw(st.lists(st.sampled_from(PARAM_NAMES), unique=True, max_size=4))
    params = {}
    for name in chosen:
        if name in ("turbine_spacing_m", "farm_half_extent_m") and draw(st.booleans()):
            # bias the layout sizes towards ones where many turbine counts fit
            params[name] = draw(st.floats(bounds(name)[0], 10 * bounds(name)[0]))
        else:
            params[name] = draw(param_values(name))
    if params:
        d["params"] = params
    geometry = {**DEFAULTS, **params}
    fits = [n for n in range(1, 17)
            if layout_problem(pattern, n, geometry["turbine_spacing_m"], geometry["farm_half_extent_m"]) is None]
    assume(fits)
    if DEFAULT_AGENTS not in fits or draw(st.booleans()):
        d["agents"] = draw(st.sampled_from(fits))
    if draw(st.booleans()):
        d["episode_length"] = draw(st.integers(1, 1_000_000))
    if draw(st.booleans()):
        seeds = {}
        if draw(st.booleans()):
            seeds["train"] = draw(seed_sets({DEFAULT_SEEDS["test"]}))
        if draw(st.booleans()):
            seeds["test"] = draw(seed_sets(as_set(seeds.get("train", DEFAULT_SEEDS["train"]))))
        d["seeds"] = seeds
    if draw(st.booleans()):
        terms = draw(st.lists(st.sampled_from(TERMS), unique=True, max_size=2))
        d["weights"] = {t: draw(st.floats(-MAX_WEIGHT, MAX_WEIGHT, allow_nan=False)) for t in terms}
    keys = list(d)
    return {k: d[k] for k in draw(st.permutations(keys))}


def dump(data: dict) -> str:
    return yaml.safe_dump(data, sort_keys=False, allow_unicode=True)


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    """A function writing text to a fresh file, for use inside @given tests."""
    directory = tmp_path_factory.mktemp("scenarios")
    counter = itertools.count()

    def write(text: str, suffix: str = ".yaml"):
        path = directory / f"s{next(counter)}{suffix}"
        path.write_text(text, encoding="utf-8")
        return path

    return write


# --- (a) valid scenarios compile to exactly what was written -----------------------------------------


def check_compiled(compiled, d: dict) -> None:
    assert compiled.environment == ENV
    task = d.get("task", 0)
    task_index = TASKS.index(task) if isinstance(task, str) else task
    assert compiled.task_index == task_index and compiled.task_name == TASKS[task_index]
    pattern = d.get("pattern", 0)
    assert compiled.level == (PATTERN_NAMES.index(pattern) if isinstance(pattern, str) else pattern)
    assert compiled.agents == d.get("agents", DEFAULT_AGENTS)
    assert compiled.episode_length == d.get("episode_length", DEFAULT_EPISODE_LENGTH)
    assert compiled.spec.name == d.get("name", "scenario")
    assert compiled.spec.description == d.get("description", "")
    for split in ("train", "test"):
        written = d.get("seeds", {}).get(split, DEFAULT_SEEDS[split])
        got = getattr(compiled.seeds, split)
        if isinstance(written, int):
            assert type(got) is int and got == written
        else:
            assert list(got) == written
    assert dict(compiled.weights) == {**COLUMNS[task_index], **d.get("weights", {})}
    for name in PARAM_NAMES:
        value = getattr(compiled.params, name)
        written = d.get("params", {}).get(name, DEFAULTS[name])
        assert value == written and type(value) is (int if is_int_param(name) else float)


@EXAMPLES
@given(valid_scenarios())
def test_valid_scenarios_compile_to_what_was_written(files, d):
    original = json.loads(json.dumps(d))
    from_dict = hivex_dsl.compile(d)
    assert d == original  # the caller's dict is not changed
    check_compiled(from_dict, d)
    [from_text] = hivex_dsl.compile_all(files(dump(d)))
    check_compiled(from_text, d)
    assert from_text.fingerprint == from_dict.fingerprint


# --- (b) mutations fail with located ScenarioErrors ------------------------------------------------


def value_position(text: str, path: tuple[str, ...]) -> tuple[int, int]:
    """(line, col) of the block-style key at ``path`` in a safe_dump text, and of its value: by hand."""
    lines = text.split("\n")
    start, indent = 0, ""
    for depth, key in enumerate(path):
        pattern = re.compile(rf"^{indent}(?:{re.escape(key)}|'{re.escape(key)}'):(?: |$)")
        start = next(i for i in range(start, len(lines)) if pattern.match(lines[i]))
        if depth < len(path) - 1:
            start, indent = start + 1, indent + "  "
    line = lines[start]
    if line.endswith(":"):  # a block list or mapping starts on the next line
        following = lines[start + 1]
        return start + 2, len(following) - len(following.lstrip(" ")) + 1
    return start + 1, line.index(":", len(indent) + len(path[-1])) + 3


def key_position(text: str, path: tuple[str, ...]) -> tuple[int, int]:
    line, _ = value_position(text, path)
    return line, 2 * (len(path) - 1) + 1


def problems_of(path) -> tuple:
    """The problems of compiling ``path``: must be a ScenarioError and nothing else."""
    try:
        hivex_dsl.compile_all(path)
    except ScenarioError as exc:
        problems = exc.problems
    else:
        raise AssertionError("the mutated scenario compiled")
    assert problems and all(p.location.line >= 1 and p.location.col >= 1 for p in problems)
    assert all(p.location.path == str(path) for p in problems)
    assert all(len(p.message.splitlines()) == 1 for p in problems)
    return problems


LEVELS = {(): TOP_KEYS, ("seeds",): ("train", "test"), ("weights",): TERMS, ("params",): PARAM_NAMES}
UNKNOWN_KEYS = st.from_regex(r"[a-z][a-z0-9_]{0,15}", fullmatch=True)


@EXAMPLES
@given(valid_scenarios(), st.sampled_from(sorted(LEVELS)), UNKNOWN_KEYS, st.integers(0, 10**6))
def test_an_unknown_key_at_any_level_is_a_located_error(files, d, level, key, value):
    assume(key not in LEVELS[level] and key != "hivex_lock")
    if level:
        d.setdefault(level[0], {})[key] = value
    else:
        d[key] = value
    text = dump(d)
    problems = problems_of(files(text))
    line, col = key_position(text, level + (key,))
    assert any(p.location.line == line and p.location.col == col and f"'{key}'" in p.message for p in problems)


def numeric_fields() -> st.SearchStrategy:
    """(path, out-of-range value) for every bounded numeric field of a scenario."""
    return st.one_of(
        st.tuples(st.just(("agents",)), st.one_of(st.integers(max_value=0), st.integers(min_value=17))),
        st.tuples(st.just(("episode_length",)), st.one_of(st.integers(max_value=0), st.integers(min_value=1_000_001))),
        st.tuples(st.sampled_from([("seeds", "train"), ("seeds", "test")]),
                  st.one_of(st.integers(max_value=-1), st.integers(min_value=MAX_SEED + 1))),
        st.tuples(st.sampled_from([("weights", t) for t in TERMS]),
                  st.one_of(st.floats(max_value=-MAX_WEIGHT, exclude_max=True, allow_nan=False, allow_infinity=False),
                            st.floats(min_value=MAX_WEIGHT, exclude_min=True, allow_nan=False, allow_infinity=False))),
        *[st.tuples(st.just(("params", name)), out_of_range(name)) for name in PARAM_NAMES],
    )


def put(d: dict, path: tuple[str, ...], value) -> None:
    target = d
    for part in path[:-1]:
        target = target.setdefault(part, {})
    target[path[-1]] = value


def mutated(files, d: dict, path: tuple[str, ...], value) -> tuple[tuple, int, int, str]:
    """Write ``value`` at ``path``, compile the YAML text; (problems, line, col, dotted path) of that value."""
    put(d, path, value)
    text = dump(d)
    line, col = value_position(text, path)
    return problems_of(files(text)), line, col, ".".join(path)


@EXAMPLES
@given(valid_scenarios(), numeric_fields())
def test_a_numeric_field_out_of_its_bounds_is_a_located_error(files, d, field_value):
    problems, line, col, dotted = mutated(files, d, *field_value)
    assert any(p.location.line == line and p.location.col == col and p.message.startswith(f"{dotted}: ")
               and "out of range" in p.message for p in problems), problems


NOT_A_NUMBER = st.one_of(st.text(max_size=5).map(lambda s: "x" + s), st.booleans(), st.lists(st.integers(), max_size=2),
                         st.dictionaries(st.sampled_from("abc"), st.integers(), max_size=2))


def wrong_types() -> st.SearchStrategy:
    """(path, value of a type the field never takes)."""
    not_int = st.one_of(NOT_A_NUMBER, st.none(), st.floats(allow_nan=False, allow_infinity=False))
    return st.one_of(
        st.tuples(st.sampled_from([("agents",), ("episode_length",)]), not_int),
        st.tuples(st.sampled_from([("task",), ("pattern",)]),
                  st.one_of(st.booleans(), st.none(), st.floats(allow_nan=False), st.lists(st.integers(), max_size=2))),
        st.tuples(st.sampled_from([("name",), ("description",)]), st.one_of(st.integers(), st.booleans(), st.none())),
        st.tuples(st.sampled_from([("seeds", "train"), ("seeds", "test")]),
                  st.one_of(st.text(max_size=5).map(lambda s: "x" + s), st.booleans(), st.none(),
                            st.floats(allow_nan=False, allow_infinity=False))),
        st.tuples(st.sampled_from([("weights", t) for t in TERMS]), NOT_A_NUMBER),
        st.tuples(st.sampled_from([("params", n) for n in PARAM_NAMES]), st.one_of(NOT_A_NUMBER, st.none())),
        st.tuples(st.sampled_from([("seeds",), ("weights",), ("params",)]), st.one_of(st.integers(), st.text(max_size=3))),
    )


@EXAMPLES
@given(valid_scenarios(), wrong_types())
def test_a_value_of_the_wrong_type_is_a_located_error(files, d, field_value):
    problems, line, col, dotted = mutated(files, d, *field_value)
    assert any(p.location.line == line and p.location.col == col and p.message.startswith(f"{dotted}")
               for p in problems), problems


@EXAMPLES
@given(valid_scenarios(), st.data())
def test_a_misspelt_environment_is_a_located_error_with_a_suggestion(files, d, data):
    position = data.draw(st.integers(0, len(ENV) - 1))
    edit = data.draw(st.sampled_from(["drop", "replace", "insert", "swap"]))
    letter = data.draw(st.sampled_from("abcdefghijklmnopqrstuvwxyz_"))
    chars = list(ENV)
    if edit == "drop":
        del chars[position]
    elif edit == "replace":
        chars[position] = letter
    elif edit == "insert":
        chars.insert(position, letter)
    else:
        chars[position:position + 2] = chars[position:position + 2][::-1]
    misspelt = "".join(chars)
    assume(misspelt != ENV)
    d["environment"] = misspelt
    text = dump(d)
    problems = problems_of(files(text))
    line, col = value_position(text, ("environment",))
    assert any(p.location.line == line and p.location.col == col and f"'{misspelt}'" in p.message
               and f"did you mean '{ENV}'?" in p.message for p in problems), problems


# --- (c) lock files ---------------------------------------------------------------------------------


LOCK_EXAMPLES = settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
LAYOUT_FREE = tuple(n for n in PARAM_NAMES if n not in ("turbine_spacing_m", "farm_half_extent_m"))


@LOCK_EXAMPLES
@given(valid_scenarios(), st.sampled_from(LAYOUT_FREE), st.data())
def test_a_lock_compiles_to_the_same_fingerprint_and_an_edited_lock_is_refused(files, d, name, data):
    compiled = hivex_dsl.compile(d)
    lock = compiled.to_lock()
    [again] = hivex_dsl.compile_all(files(json.dumps(lock, indent=2), ".json"))
    assert again.fingerprint == compiled.fingerprint
    check_compiled(again, {**d, "name": compiled.name, "description": ""})  # a lock keeps no description

    old = lock["scenario"]["params"][name]
    new = data.draw(param_values(name).filter(lambda v: v != old))
    lock["scenario"]["params"][name] = new
    text = json.dumps(lock, indent=2)
    path = files(text, ".json")
    with pytest.raises(ScenarioError) as caught:
        hivex_dsl.compile_all(path)
    [problem] = caught.value.problems
    line_index = next(i for i, line in enumerate(text.split("\n")) if line.startswith('  "fingerprint": '))
    assert (problem.location.line, problem.location.col) == (line_index + 1, len('  "fingerprint": ') + 1)
    assert problem.message.startswith("fingerprint ") and "does not match" in problem.message
