"""The library x environment table of docs/ecosystem.md, read from the tests that prove its cells.

A test proves a cell when it carries ``@pytest.mark.ecosystem("<library>")`` and is parametrized by environment
(``@pytest.mark.parametrize("env_id", ENV_IDS)`` or ``"environment"``): each environment it runs on is a cell of that
library's row. The tests are read statically (Python's ``ast``), so `hivex docs` imports no test library; a marked
test whose environments this reader cannot work out is an error, never a guess. The parametrize values it reads: a
list or tuple of environment ids (or of tuples, the environment one of their fields), a module-level name bound to
one of those, a dict literal (its keys), ``list(...)``/``tuple(...)`` of one of those, and
``registry.environments()`` (every environment). tests/test_ecosystem.py checks this reading against pytest's own
collection, so a removed or narrowed test removes its claim.
"""

from __future__ import annotations

import ast
from dataclasses import dataclass
from pathlib import Path

from ..compiler import registry

MARKER = "ecosystem"
ENV_PARAMETERS = ("env_id", "environment")


@dataclass(frozen=True)
class Library:
    """A row of the table: its title and a note on where its tests run."""

    title: str
    note: str = ""


# The rows, in order; a marker naming any other library is an error.
LIBRARIES: dict[str, Library] = {
    "pettingzoo": Library("PettingZoo API suite"),
    "gymnasium": Library("Gymnasium vector env checks"),
    "supersuit": Library("SuperSuit"),
    "sb3": Library("Stable-Baselines3"),
    "rllib": Library("RLlib", "tested in a venv of its own by `make rllib`: ray[rllib] pins an older Gymnasium"),
    "torchrl": Library("TorchRL"),
    "benchmarl": Library("BenchMARL"),
    "cleanrl": Library("CleanRL-style example"),
}


class EcosystemScanError(ValueError):
    """A marked test the reader cannot turn into cells (or a marker naming no known library)."""


@dataclass(frozen=True)
class Proof:
    """One marked test: its pytest node id (relative to the tests' parent folder), libraries and environments."""

    nodeid: str
    libraries: tuple[str, ...]
    environments: tuple[str, ...]


def _dotted(node: ast.AST) -> str:
    """``pytest.mark.ecosystem`` for the attribute chain of that name ('' for anything else)."""
    parts = []
    while isinstance(node, ast.Attribute):
        parts.append(node.attr)
        node = node.value
    return ".".join([node.id, *reversed(parts)]) if isinstance(node, ast.Name) else ""


def _marks(function: ast.AST, name: str) -> list[ast.Call]:
    """The decorators ``@pytest.mark.<name>(...)`` of a function."""
    return [d for d in getattr(function, "decorator_list", ())
            if isinstance(d, ast.Call) and _dotted(d.func) == f"pytest.mark.{name}"]


class _Reader:
    """Reads one test module: its module-level names and each marked test's libraries and environments."""

    def __init__(self, path: Path, root: Path):
        self.path, self.rel = path, path.relative_to(root).as_posix()
        self.tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
        self.names = {target.id: node.value for node in self.tree.body if isinstance(node, ast.Assign)
                      for target in node.targets if isinstance(target, ast.Name)}

    def fail(self, node: ast.AST, why: str) -> EcosystemScanError:
        """An error pointing at ``node``'s line."""
        return EcosystemScanError(f"{self.rel}:{getattr(node, 'lineno', '?')}: {why}")

    def values(self, node: ast.AST) -> list:
        """The parametrize values ``node`` stands for: str constants, or tuples of them."""
        if isinstance(node, (ast.List, ast.Tuple)):
            return [self.constant(element) for element in node.elts]
        if isinstance(node, ast.Dict):
            return [self.constant(key) for key in node.keys]
        if isinstance(node, ast.Name) and node.id in self.names:
            return self.values(self.names[node.id])
        if isinstance(node, ast.Call) and not node.keywords:
            if _dotted(node.func) in ("list", "tuple") and len(node.args) == 1:
                return self.values(node.args[0])
            if _dotted(node.func) == "registry.environments" and not node.args:
                return list(registry.environments())
        raise self.fail(node, f"cannot read the environments of {ast.unparse(node)!r} statically")

    def constant(self, node: ast.AST):
        """A str constant, or a tuple of constants (a list of them too: parametrize's argnames)."""
        if isinstance(node, ast.Constant):
            return node.value
        if isinstance(node, (ast.Tuple, ast.List)):
            return tuple(self.constant(element) for element in node.elts)
        raise self.fail(node, f"{ast.unparse(node)!r} is no constant")

    def environments(self, function: ast.AST) -> tuple[str, ...]:
        """The environments a marked test is parametrized by (an error if it is parametrized by none)."""
        for call in _marks(function, "parametrize"):
            names = self.constant(call.args[0]) if call.args else ()
            names = [n.strip() for n in names.split(",")] if isinstance(names, str) else list(names)
            position = next((names.index(p) for p in ENV_PARAMETERS if p in names), None)
            if position is None:
                continue
            values = self.values(call.args[1])
            found = tuple(v if len(names) == 1 else v[position] for v in values)
            unknown = sorted(set(found) - set(registry.environments()))
            if unknown:
                raise self.fail(call, f"{unknown} are no environments")
            return found
        raise self.fail(function, f"{function.name} is marked {MARKER} but not parametrized by "
                                  f"{' or '.join(ENV_PARAMETERS)}")

    def libraries(self, function: ast.AST) -> tuple[str, ...]:
        """The libraries named by a test's ecosystem markers."""
        named = tuple(self.constant(arg) for call in _marks(function, MARKER) for arg in call.args)
        unknown = [n for n in named if n not in LIBRARIES]
        if unknown or any(call.keywords or not call.args for call in _marks(function, MARKER)):
            raise self.fail(function, f"{MARKER} markers name one of {list(LIBRARIES)}, not {unknown or 'nothing'}")
        return named

    def proofs(self) -> list[Proof]:
        """Every marked test function of the module (top level or in a class), in file order."""
        found = []
        for owner, function in self._functions():
            if _marks(function, MARKER):
                nodeid = "::".join([self.rel, *([owner] if owner else []), function.name])
                found.append(Proof(nodeid, self.libraries(function), self.environments(function)))
        return found

    def _functions(self):
        for node in self.tree.body:
            if isinstance(node, ast.ClassDef):
                yield from ((node.name, f) for f in node.body if isinstance(f, ast.FunctionDef))
            elif isinstance(node, ast.FunctionDef):
                yield None, node


def read_proofs(tests: Path) -> list[Proof]:
    """Every test under ``tests`` marked ``ecosystem``; node ids are relative to ``tests``' parent (pytest's)."""
    tests = Path(tests)
    proofs = []
    for path in sorted(tests.rglob("test_*.py")):
        if MARKER in path.read_text(encoding="utf-8"):
            proofs.extend(_Reader(path, tests.parent).proofs())
    return proofs


def cells(proofs: list[Proof]) -> dict[tuple[str, str], list[str]]:
    """(library, environment) -> the node ids of the tests that prove it."""
    out: dict[tuple[str, str], list[str]] = {}
    for proof in proofs:
        for library in proof.libraries:
            for environment in dict.fromkeys(proof.environments):
                out.setdefault((library, environment), []).append(proof.nodeid)
    return out


def _spans(numbers: list[int]) -> str:
    """``[1, 2, 3, 5]`` -> ``"1–3, 5"`` (an en dash); ``[]`` -> ``"-"`` (no test proves the cell)."""
    runs: list[list[int]] = []
    for n in numbers:
        if runs and n == runs[-1][-1] + 1:
            runs[-1].append(n)
        else:
            runs.append([n])
    return ", ".join(f"{r[0]}" if len(r) == 1 else f"{r[0]}–{r[-1]}" for r in runs) or "-"


def matrix_context(tests: Path | None) -> dict:
    """The table for the template: columns (environments), rows (libraries, each cell the numbers of its tests or
    '-'), and the tests numbered row by row; ``None`` when there are no tests to read (an install without the
    checkout)."""
    if tests is None or not Path(tests).is_dir():
        return {"matrix": None}
    order = list(LIBRARIES)
    proofs = sorted(read_proofs(Path(tests)), key=lambda p: min(order.index(name) for name in p.libraries))
    numbers = {proof.nodeid: i for i, proof in enumerate(proofs, start=1)}
    proven = cells(proofs)
    environments = list(registry.environments())
    rows = [{"title": library.title, "note": library.note,
             "cells": [_spans(sorted(numbers[n] for n in proven.get((key, env), ()))) for env in environments]}
            for key, library in LIBRARIES.items()]
    columns = [{"title": registry.get(env).info.abbreviation, "env": env} for env in environments]
    return {"matrix": {"columns": columns, "rows": rows,
                       "tests": [{"number": numbers[p.nodeid], "nodeid": p.nodeid} for p in proofs]}}
