"""The grammar table handed to the docs describes exactly the functions the compiler accepts."""

from __future__ import annotations

import re

import numpy as np

from hivex_dsl.lang.expr import compile_expression, describe_grammar
from hivex_dsl.lang.expr.grammar import FUNCTIONS

from .conftest import AGENTS, VOCABULARY

SAMPLE_ARGUMENTS = {"cond": "dropped", "x": "water + 0.5", "a": "water", "b": "0.25", "lo": "0.25", "hi": "0.75"}


def call_of(signature: str) -> str:
    name, params = re.fullmatch(r"(\w+)\((.*)\)", signature).groups()
    return f"{name}({', '.join(SAMPLE_ARGUMENTS[p.strip()] for p in params.split(','))})"


def test_every_documented_function_compiles_as_its_signature_says(states):
    now, before = states
    for entry in FUNCTIONS.values():
        source = call_of(entry.signature)
        expression = compile_expression(source, VOCABULARY, agents=AGENTS)
        value = expression.evaluate(now, before)
        assert np.isfinite(value).all() and expression.low <= value.min() <= value.max() <= expression.high
        assert entry.arity == source.count(",") + 1


def test_the_description_is_plain_data_with_every_field_filled():
    grammar = describe_grammar()
    assert [row["name"] for row in grammar["functions"]] == list(FUNCTIONS)
    for row in grammar["functions"] + grammar["operators"]:
        assert set(row) == {"name", "signature", "units", "interval", "description"}
        assert all(isinstance(v, str) and v for v in row.values())
    assert grammar["rules"] and all(isinstance(rule, str) for rule in grammar["rules"])
    assert grammar["syntax"] and all(set(row) == {"form", "text"} for row in grammar["syntax"])
