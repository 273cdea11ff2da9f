"""The context of docs/adding_an_environment.md: the contract (runtime/contract.py's Protocols and the registry
entry's fields) and the example environment of the tests, file by file."""

from __future__ import annotations

import ast
import dataclasses
import re
from pathlib import Path
from typing import Any

from ..compiler import registry
from ..runtime import contract

PAGE = "adding_an_environment.md"
EXAMPLE = Path("example_env") / "bee_foraging"  # under the checkout's tests/
# every file of the walk-through in full, in the order the page takes them; the other scenarios in the table only
SHOWN_IN_FULL = ("params.py", "simulator.py", "terms.py", "scripted.py", "vocabulary.py", "rewards.yaml",
                 "scenarios/main.yaml", "__init__.py")


ROLE = re.compile(r":\w+:`(~?)([\w.]+)`")  # reST's :class:`~a.b.C` -> `C`, :mod:`a.b` -> `a.b`


def markdown(text: str) -> str:
    """A docstring's reST on one line as Markdown: roles and double backquotes as code spans."""
    text = ROLE.sub(lambda m: f"`{m.group(2).rsplit('.', 1)[-1] if m.group(1) else m.group(2)}`", text)
    return " ".join(text.replace("``", "`").split())


def _first_paragraph(text: str) -> str:
    return markdown(text.strip().split("\n\n")[0])


def entry_fields() -> list[dict[str, Any]]:
    """Each field of EnvironmentEntry: its name, whether an environment must give it, and what it is."""
    rows = []
    for item in dataclasses.fields(registry.EnvironmentEntry):
        required = item.default is dataclasses.MISSING and item.default_factory is dataclasses.MISSING
        rows.append({"name": item.name, "required": required, "doc": item.metadata.get("doc", "")})
    return rows


def protocols() -> list[dict[str, Any]]:
    """The simulator's Protocols, the required one first, each with its members."""
    return [{"name": protocol.__name__, "required": protocol in contract.REQUIRED,
             "doc": _first_paragraph(protocol.__doc__ or ""),
             "members": [{"name": name, "signature": signature.replace("'", "").replace('"', ""),
                          "doc": markdown(doc)}
                         for name, signature, doc in contract.members(protocol)]}
            for protocol in contract.REQUIRED + contract.OPTIONAL]


def example_files(folder: Path) -> list[dict[str, Any]]:
    """The example's files: path in the folder, lines, what it holds (a module's docstring, a YAML file's first
    comment) and, for the few shown in full, the text."""
    rows = []
    for path in sorted(p for p in folder.rglob("*") if p.is_file() and "__pycache__" not in p.parts):
        name = path.relative_to(folder).as_posix()
        text = path.read_text(encoding="utf-8")
        if path.suffix == ".py":
            about = _first_paragraph(ast.get_docstring(ast.parse(text)) or "")
        else:
            about = next((line.lstrip("# ").strip() for line in text.splitlines() if line.startswith("#")), "")
        rows.append({"name": name, "lines": len(text.splitlines()), "about": about,
                     "language": "python" if path.suffix == ".py" else "yaml",
                     "text": text if name in SHOWN_IN_FULL else None})
    return rows


def walk_through(files: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """The files shown in full, in the order of :data:`SHOWN_IN_FULL`."""
    by_name = {f["name"]: f for f in files}
    return [by_name[name] for name in SHOWN_IN_FULL if name in by_name]


def adding_context(tests: Path) -> dict[str, Any]:
    """Everything the page shows; ``tests`` is the checkout's tests/ folder, which holds the example."""
    folder = Path(tests) / EXAMPLE
    files = example_files(folder)
    return {"fields": entry_fields(), "protocols": protocols(), "files": files, "shown": walk_through(files),
            "example": EXAMPLE.as_posix(), "package": registry.ENVIRONMENTS_PACKAGE,
            "group": registry.ENTRY_POINT_GROUP, "variable": registry.ENVIRONMENTS_VARIABLE}


def has_example(tests: Path | None) -> bool:
    return tests is not None and (Path(tests) / EXAMPLE / "__init__.py").is_file()
