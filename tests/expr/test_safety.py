"""Nothing in the expression package can hand text to Python: no eval, exec, compile or imports
by name anywhere in its source, and hostile sources are refused by the parser itself."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

import hivex_dsl.lang.expr
from hivex_dsl.lang.expr import ExpressionError, compile_expression

from .conftest import VOCABULARY

_FORBIDDEN_BUILTINS = {"eval", "exec", "compile", "__import__", "getattr", "setattr", "globals", "locals", "vars"}
_FORBIDDEN_METHODS = {"eval", "exec", "import_module", "literal_eval", "__import__"}  # re.compile is fine


def test_the_package_never_calls_eval_exec_compile_or_getattr():
    for path in Path(hivex_dsl.lang.expr.__file__).parent.glob("*.py"):
        for node in ast.walk(ast.parse(path.read_text(), str(path))):
            if isinstance(node, ast.Call) and isinstance(node.func, ast.Name):
                assert node.func.id not in _FORBIDDEN_BUILTINS, f"{path.name}:{node.lineno} calls {node.func.id}"
            if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute):
                assert node.func.attr not in _FORBIDDEN_METHODS, f"{path.name}:{node.lineno} calls {node.func.attr}"


@pytest.mark.parametrize("source", [
    "__import__('os').system('true')",
    "water.__class__.__mro__",
    "().__class__",
    "[x for x in ()]",
    "(lambda: 1)()",
    "exec('1')",
    "eval",
    "open('/etc/passwd')",
    "water; import os",
    "globals()",
    "f'{water}'",
    "water if water else water",
    "(water := 1)",
    "*water",
    "water @ water",
    "~water",
    "`water`",
    "water\x00",
])
def test_hostile_sources_are_refused_by_the_parser(source):
    with pytest.raises(ExpressionError):
        compile_expression(source, VOCABULARY)
