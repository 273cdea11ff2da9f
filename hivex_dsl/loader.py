"""Safe YAML reading that keeps the line and column of every key and value.

PyYAML composes the text into nodes (which carry marks); we construct plain Python values
ourselves so that we can refuse what a scenario must never contain: object-constructing tags,
duplicate keys, non-string keys, alias-expansion bombs and absurdly deep or large documents.
JSON is YAML, so lock files are read by the same code.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Union

import yaml

from .errors import Location, Problem, ScenarioError

PathKey = tuple[Union[str, int], ...]

MAX_FILE_BYTES = 1_000_000
MAX_NODES = 100_000
MAX_DEPTH = 64

_PLAIN_TAGS = {
    "tag:yaml.org,2002:str",
    "tag:yaml.org,2002:int",
    "tag:yaml.org,2002:float",
    "tag:yaml.org,2002:bool",
    "tag:yaml.org,2002:null",
    "tag:yaml.org,2002:timestamp",
    "tag:yaml.org,2002:seq",
    "tag:yaml.org,2002:map",
}


@dataclass(frozen=True)
class Loaded:
    """A document as plain Python values plus where each part of it was written.

    ``marks[path]`` is the location of the value at ``path`` (a tuple of keys and indices);
    ``key_marks[path]`` is the location of the mapping key that introduced it.
    """

    source: str
    data: Any
    marks: dict[PathKey, Location] = field(default_factory=dict)
    key_marks: dict[PathKey, Location] = field(default_factory=dict)

    def locate(self, path: PathKey, *, key: bool = False) -> Location:
        """The location of ``path``, or of its nearest written ancestor."""
        path = tuple(path)
        if key and path in self.key_marks:
            return self.key_marks[path]
        while path:
            if path in self.marks:
                return self.marks[path]
            path = path[:-1]
        return self.marks.get((), Location(self.source, 1, 1))


def load_file(path: str | Path) -> Loaded:
    """Read a YAML (or JSON) file; every failure is a located :class:`ScenarioError`."""
    path = Path(path)
    source = str(path)
    try:
        raw = path.read_bytes()
    except FileNotFoundError:
        _fail(source, 1, 1, f"no such file: {path}")
    except IsADirectoryError:
        _fail(source, 1, 1, f"{path} is a directory, expected a YAML file")
    except OSError as exc:
        _fail(source, 1, 1, f"cannot read {path}: {exc.strerror}")
    if len(raw) > MAX_FILE_BYTES:
        _fail(source, 1, 1, f"file is {len(raw)} bytes; a scenario may be at most {MAX_FILE_BYTES} bytes")
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        line = raw[: exc.start].count(b"\n") + 1
        col = exc.start - (raw.rfind(b"\n", 0, exc.start) + 1) + 1
        _fail(source, line, col, "not a text file: expected UTF-8 encoded YAML")
    return load_text(text, source)


def load_text(text: str, source: str = "<string>") -> Loaded:
    """Parse YAML text named ``source`` (used in error locations)."""
    try:
        documents = list(yaml.compose_all(text, Loader=yaml.SafeLoader))
    except yaml.MarkedYAMLError as exc:
        mark = exc.problem_mark or exc.context_mark
        line, col = (mark.line + 1, mark.column + 1) if mark else (1, 1)
        what = exc.problem or exc.context or "malformed input"
        _fail(source, line, col, f"not valid YAML: {what}")
    except yaml.YAMLError as exc:  # pragma: no cover - PyYAML marks all parse errors it raises
        _fail(source, 1, 1, f"not valid YAML: {exc}")
    documents = [d for d in documents if d is not None]
    if not documents:
        _fail(source, 1, 1, "the file is empty: expected a mapping with at least 'hivex' and 'environment'")
    if len(documents) > 1:
        start = documents[1].start_mark
        _fail(source, start.line + 1, start.column + 1, "a file holds one scenario; found a second YAML document")
    builder = _Builder(source)
    data = builder.build(documents[0], (), 0)
    return Loaded(source, data, builder.marks, builder.key_marks)


def _fail(source: str, line: int, col: int, message: str):
    raise ScenarioError([Problem(Location(source, line, col), message)])


class _Builder:
    """Turns composed nodes into dicts, lists and scalars, recording marks."""

    def __init__(self, source: str):
        self.source = source
        self.marks: dict[PathKey, Location] = {}
        self.key_marks: dict[PathKey, Location] = {}
        self.visited = 0
        self._scalars = yaml.SafeLoader("")

    def where(self, node: yaml.Node) -> Location:
        return Location(self.source, node.start_mark.line + 1, node.start_mark.column + 1)

    def fail(self, node: yaml.Node, message: str):
        raise ScenarioError([Problem(self.where(node), message)])

    def build(self, node: yaml.Node, path: PathKey, depth: int) -> Any:
        self.visited += 1
        if self.visited > MAX_NODES:
            self.fail(node, f"document expands to more than {MAX_NODES} values (an alias bomb?); refusing to read it")
        if depth > MAX_DEPTH:
            self.fail(node, f"document nests deeper than {MAX_DEPTH} levels (a recursive alias?); refusing to read it")
        if node.tag not in _PLAIN_TAGS:
            self.fail(node, f"YAML tag '{node.tag}' is not allowed: scenarios hold plain data only (no tags that construct objects)")
        self.marks.setdefault(path, self.where(node))
        if isinstance(node, yaml.MappingNode):
            return self.build_mapping(node, path, depth)
        if isinstance(node, yaml.SequenceNode):
            return [self.build(item, path + (i,), depth + 1) for i, item in enumerate(node.value)]
        return self.build_scalar(node)

    def build_mapping(self, node: yaml.MappingNode, path: PathKey, depth: int) -> dict:
        result: dict[str, Any] = {}
        first_seen: dict[str, Location] = {}
        for key_node, value_node in node.value:
            if key_node.tag == "tag:yaml.org,2002:merge":
                self.fail(key_node, "merge keys ('<<') are not supported: write the keys out")
            if not isinstance(key_node, yaml.ScalarNode) or key_node.tag not in _PLAIN_TAGS:
                self.fail(key_node, "a key must be a plain name, not a list, mapping or tagged value")
            key = key_node.value
            if key in first_seen:
                first = first_seen[key]
                self.fail(key_node, f"duplicate key '{key}' (first written at line {first.line}); a key may appear once")
            first_seen[key] = self.where(key_node)
            self.key_marks[path + (key,)] = self.where(key_node)
            result[key] = self.build(value_node, path + (key,), depth + 1)
        return result

    def build_scalar(self, node: yaml.ScalarNode) -> Any:
        if node.tag == "tag:yaml.org,2002:timestamp":
            return node.value  # kept as written; no field takes a date, so validation names it
        return self._scalars.construct_object(node, deep=False)
