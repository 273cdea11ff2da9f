"""The package's layers (issue 37), read from the source with ``ast``: every import, at any depth (in functions and
``if TYPE_CHECKING:`` blocks too), relative ones resolved.

- a layer imports only itself and the layers below it;
- no private name (a leading underscore) is imported from another module;
- no modules import each other in a circle;
- the top of hivex_dsl/ holds only the package's own modules and one folder per layer.
"""

from __future__ import annotations

import ast
import re
from dataclasses import dataclass
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / "hivex_dsl"
NAME = PACKAGE.name

# bottom -> top; a layer may import itself and the layers below it. zoo/ belongs to the adapters layer; replay/ sits
# beside train/ (it plays a checkpoint and train never imports it).
LAYERS = {"base": 0, "lang": 1, "sim": 2, "compiler": 3, "runtime": 4, "envs": 5, "adapters": 6, "zoo": 6,
          "evaluation": 7, "train": 8, "replay": 8, "docsgen": 9, "cli": 10}
ABOVE_ALL = len(set(LAYERS.values()))  # the facade (hivex_dsl/__init__.py) and the public path testing.py
TOP_MODULES = {"__init__.py", "testing.py"}  # all that may sit loose at the top of hivex_dsl/
DATA_FOLDERS = {"data"}  # package data, no layer


@dataclass(frozen=True)
class Import:
    importer: str  # module name
    file: str  # path from the repository root
    line: int
    target: str  # the module imported (a submodule imported by name counts as that submodule)
    names: tuple[str, ...]  # names imported from target ((), for `import target` or a submodule by name)


def _module_name(path: Path) -> str:
    parts = path.relative_to(PACKAGE.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


MODULES = {_module_name(path): path for path in sorted(PACKAGE.rglob("*.py"))}


def _resolve(node: ast.ImportFrom, module: str, path: Path) -> str:
    if not node.level:
        return node.module or ""
    package = module.split(".") if path.name == "__init__.py" else module.split(".")[:-1]
    base = package[: len(package) - (node.level - 1)]
    return ".".join(base + ([node.module] if node.module else []))


def _imports() -> list[Import]:
    found = []
    for module, path in MODULES.items():
        where = str(path.relative_to(PACKAGE.parent))
        for node in ast.walk(ast.parse(path.read_text(), where)):
            if isinstance(node, ast.Import):
                found += [Import(module, where, node.lineno, alias.name, ()) for alias in node.names
                          if alias.name == NAME or alias.name.startswith(NAME + ".")]
            elif isinstance(node, ast.ImportFrom):
                source = _resolve(node, module, path)
                if source != NAME and not source.startswith(NAME + "."):
                    continue
                names = []
                for alias in node.names:
                    if f"{source}.{alias.name}" in MODULES:  # a submodule, imported by its name
                        found.append(Import(module, where, node.lineno, f"{source}.{alias.name}", ()))
                    else:
                        names.append(alias.name)
                if names:
                    found.append(Import(module, where, node.lineno, source, tuple(names)))
    return found


IMPORTS = _imports()


def layer_of(module: str) -> tuple[int, str]:
    """(rank, name) of the layer a module belongs to: its first folder under hivex_dsl/."""
    parts = module.split(".")
    if len(parts) == 1 or parts[1] not in LAYERS:
        return ABOVE_ALL, "the facade" if len(parts) == 1 else parts[1]
    return LAYERS[parts[1]], parts[1]


def test_the_modules_are_found():
    assert len(MODULES) > 100 and f"{NAME}.compiler.scenario" in MODULES and len(IMPORTS) > 500


def test_every_import_names_a_module_of_the_package():
    """An import inside the package names a real module."""
    unknown = [f"{i.file}:{i.line}: imports {i.target}, which is no module of the package"
               for i in IMPORTS if i.target not in MODULES]
    assert not unknown, "\n".join(unknown)


def test_no_layer_imports_a_layer_above_it():
    broken = []
    for i in IMPORTS:
        (rank, layer), (target_rank, target_layer) = layer_of(i.importer), layer_of(i.target)
        if target_rank > rank:
            broken.append(f"{i.file}:{i.line}: {layer} (layer {rank + 1}) imports {i.target} ({target_layer}, "
                          f"layer {target_rank + 1}): a layer may import only itself and the layers below it")
    assert not broken, "\n".join(broken)


def test_no_private_name_is_imported_from_another_module():
    """A name with a leading underscore is its module's own; a private module, its package's own."""
    broken = []
    for i in IMPORTS:
        private = [name for name in i.names if name.startswith("_")]
        last = i.target.rsplit(".", 1)[-1]
        if last.startswith("_") and not i.names and i.target.rsplit(".", 1)[0] != i.importer.rsplit(".", 1)[0] \
                and i.target.rsplit(".", 1)[0] != i.importer:
            private.append(i.target)
        broken += [f"{i.file}:{i.line}: imports the private {name} from {i.target}: a name with a leading "
                   f"underscore is private to its module; give it a public name if other modules need it"
                   for name in private]
    assert not broken, "\n".join(broken)


def _cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """One circle per group of modules that import each other (a DFS; each circle as the path that closes it)."""
    state: dict[str, int] = {}  # 1: on the DFS path, 2: done
    cycles, seen = [], set()
    for start in sorted(graph):
        if state.get(start):
            continue
        path, stack = [start], [iter(sorted(graph[start]))]
        state[start] = 1
        while stack:
            nxt = next(stack[-1], None)
            if nxt is None:
                state[path.pop()] = 2
                stack.pop()
            elif state.get(nxt) == 1:
                cycle = path[path.index(nxt):] + [nxt]
                if frozenset(cycle) not in seen:
                    seen.add(frozenset(cycle))
                    cycles.append(cycle)
            elif not state.get(nxt):
                state[nxt] = 1
                path.append(nxt)
                stack.append(iter(sorted(graph.get(nxt, ()))))
    return cycles


def test_the_cycle_finder_finds_a_circle():
    assert _cycles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [["a", "b", "c", "a"]]
    assert _cycles({"a": {"b"}, "b": set()}) == []


def test_no_modules_import_each_other_in_a_circle():
    graph: dict[str, set[str]] = {module: set() for module in MODULES}
    where: dict[tuple[str, str], Import] = {}
    for i in IMPORTS:
        if i.target in MODULES and i.target != i.importer:
            graph[i.importer].add(i.target)
            where.setdefault((i.importer, i.target), i)
    messages = []
    for cycle in _cycles(graph):
        steps = [where[a, b] for a, b in zip(cycle, cycle[1:])]
        messages.append("import circle: " + " -> ".join(cycle) + "\n" + "\n".join(
            f"  {s.file}:{s.line}: imports {s.target}" for s in steps))
    assert not messages, "\n".join(messages)


def test_the_top_of_the_package_holds_only_its_own_modules_and_one_folder_per_layer():
    loose = sorted(p.name for p in PACKAGE.glob("*.py") if p.name not in TOP_MODULES)
    assert not loose, (f"{loose} at the top of {NAME}/: a module belongs in the folder of its layer "
                       f"({', '.join(LAYERS)}); see docs/architecture.md")
    folders = {p.name for p in PACKAGE.iterdir() if p.is_dir() and p.name != "__pycache__"}
    assert folders == set(LAYERS) | DATA_FOLDERS, f"folders that are no layer: {sorted(folders - set(LAYERS))}"


@pytest.mark.parametrize("layer", sorted(LAYERS))
def test_each_layer_says_what_it_holds_and_what_it_may_import(layer):
    doc = ast.get_docstring(ast.parse((PACKAGE / layer / "__init__.py").read_text())) or ""
    rank = LAYERS[layer]
    named = "adapters" if layer == "zoo" else layer
    assert doc.startswith(f"Layer {rank + 1}, {named}"), f"{NAME}/{layer}/__init__.py: its docstring starts " \
                                                         f"with 'Layer {rank + 1}, {named}'"
    assert "Imports:" in doc, f"{NAME}/{layer}/__init__.py: its docstring says which layers it imports ('Imports:')"


@pytest.mark.parametrize("page, section", [("docs/architecture.md", "# Architecture"), ("README.md", "## Layout")])
def test_the_architecture_page_and_the_readme_list_the_layers_in_order(page, section):
    text = (PACKAGE.parent / page).read_text()
    block = re.search(r"```\n(.*?)```", text[text.index(section):], re.S).group(1)
    found = {layer: re.search(rf"(?<![\w/]){layer}/", block) for layer in LAYERS}
    missing = [layer for layer, match in found.items() if match is None]
    assert not missing, f"{page}: its tree does not name {missing}"
    assert sorted(LAYERS, key=lambda layer: found[layer].start()) == list(LAYERS), \
        f"{page}: its tree lists the layers out of order; bottom to top they are {', '.join(LAYERS)}"
