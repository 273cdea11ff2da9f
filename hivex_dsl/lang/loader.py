"""Safe YAML reading that keeps the line and column of every key and value.

PyYAML composes the text into nodes (which carry marks); we construct plain Python values
ourselves so that we can refuse what a scenario must never contain: object-constructing tags,
duplicate keys, non-string keys, alias-expansion bombs and absurdly deep or large documents.
JSON is YAML, so lock files are read by the same code.
"""

from __future__ import annotations

import os
import re
import stat
import sys
import unicodedata
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Union

import yaml

from ..base.errors import Location, Problem, ScenarioError, show
from .yaml11 import character_name, line_and_column, refusal, refused_character

PathKey = tuple[Union[str, int], ...]

MAX_FILE_BYTES = 1_000_000
MAX_NODES = 100_000
MAX_DEPTH = 64

_STANDARD_TAG_PREFIX = "tag:yaml.org,2002:"
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
class Document:
    """What a file read by this module holds, for its messages: ``noun`` ("scenario"), ``contents`` (what the
    top level must be) and whether a file with nothing in it (comments only) reads as ``None``."""

    noun: str
    contents: str
    may_be_empty: bool = False


SCENARIO = Document("scenario", "a mapping with at least 'hivex' and 'environment'")


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


def load_file(path: str | Path, document: Document = SCENARIO) -> Loaded:
    """Read a YAML (or JSON) file; every failure is a located :class:`ScenarioError`."""
    path = Path(path)
    source = str(path)
    raw = _read_bounded(path, source, document)
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        line_start = raw.rfind(b"\n", 0, exc.start) + 1
        line = raw[: exc.start].count(b"\n") + 1
        col = len(raw[line_start: exc.start].decode("utf-8", errors="replace")) + 1  # in characters, not bytes
        _fail(source, line, col, f"byte 0x{raw[exc.start]:02x} is not valid UTF-8: expected UTF-8 encoded YAML")
    return load_text(text, source, document)


def _read_bounded(path: Path, source: str, document: Document) -> bytes:
    """At most MAX_FILE_BYTES bytes of ``path``: a regular file's size is checked before reading it,
    and a stream (a pipe, /dev/stdin, /dev/zero) is read no further than one byte past the limit."""
    try:
        with open(path, "rb") as stream:
            info = os.fstat(stream.fileno())
            if stat.S_ISDIR(info.st_mode):
                raise IsADirectoryError
            if stat.S_ISREG(info.st_mode) and info.st_size > MAX_FILE_BYTES:
                _fail(source, 1, 1,
                      f"file is {info.st_size:,} bytes; a {document.noun} may be at most {MAX_FILE_BYTES:,} bytes")
            raw = stream.read(MAX_FILE_BYTES + 1)
    except FileNotFoundError:
        _fail(source, 1, 1, f"no such file: {path}")
    except IsADirectoryError:
        _fail(source, 1, 1, f"{path} is a directory, expected a YAML file")
    except OSError as exc:
        _fail(source, 1, 1, f"cannot read {path}: {exc.strerror or exc}")
    if len(raw) > MAX_FILE_BYTES:
        _fail(source, 1, 1, f"input is longer than {MAX_FILE_BYTES:,} bytes, the most a {document.noun} may be")
    return raw


def load_text(text: str, source: str = "<string>", document: Document = SCENARIO) -> Loaded:
    """Parse YAML text named ``source`` (used in error locations)."""
    try:
        reader = _Reader(text, source)
    except yaml.reader.ReaderError as exc:  # a character YAML never allows (PyYAML checks the whole text first)
        line, col = line_and_column(text, exc.position)
        _fail(source, line, col, refused_character(exc.character))
    documents: list[tuple[yaml.Mark, yaml.Node]] = []
    try:
        while reader.check_node():
            start = reader.peek_event().start_mark  # the document's '---', or its first token
            node = reader.get_node()
            if node is not None and not _is_empty(node):
                documents.append((start, node))
            if len(documents) > 1:
                break
    except yaml.MarkedYAMLError as exc:
        _fail(source, *_syntax_error(exc))
    except yaml.YAMLError as exc:  # pragma: no cover - PyYAML marks all parse errors it raises
        _fail(source, 1, 1, f"not valid YAML: {exc}")
    except RecursionError:  # pragma: no cover - _Reader bounds the nesting first
        _fail(source, 1, 1, f"document nests deeper than {MAX_DEPTH} levels; refusing to read it")
    finally:
        reader.dispose()
    if len(documents) > 1:
        start = documents[1][0]
        _fail(source, start.line + 1, start.column + 1,
              f"a file holds one {document.noun}; found a second YAML document")
    if not documents:
        if document.may_be_empty:
            return Loaded(source, None, {(): Location(source, 1, 1)})
        _fail(source, 1, 1, f"the file is empty: expected {document.contents}")
    builder = _Builder(source, reader.alias_marks, document)
    data = builder.build(documents[0][1], (), 0)
    return Loaded(source, data, builder.marks, builder.key_marks)


_OPENERS = {"while scanning a quoted scalar": "quoted string", "while parsing a flow mapping": "'{'",
            "while parsing a flow sequence": "'['"}
_CLOSERS = {"'{'": "'}'", "'['": "']'"}


def _syntax_error(exc: yaml.MarkedYAMLError) -> tuple[int, int, str]:
    """(line, col, message) of a PyYAML syntax error. An unclosed quote or bracket is located where it
    opens; a bracket whose trouble lies on its own line, where the trouble is."""
    problem, context = exc.problem_mark, exc.context_mark
    what = exc.problem or exc.context or "malformed input"
    opener = _OPENERS.get(exc.context)
    if opener and context is not None and problem is not None:
        at = f"at line {problem.line + 1}, column {problem.column + 1}"
        if opener == "quoted string" or "<stream end>" in what:
            return (context.line + 1, context.column + 1,
                    f"not valid YAML: the {opener} opened here is never closed: {what} {at}")
        if problem.line > context.line:
            return (context.line + 1, context.column + 1,
                    f"not valid YAML: the {opener} opened here is not closed in time: {what} {at} "
                    f"(a missing {_CLOSERS[opener]} or ',')")
        what = f"{what} (inside the {opener} at column {context.column + 1})"
    mark = problem or context
    line, col = (mark.line + 1, mark.column + 1) if mark else (1, 1)
    return line, col, f"not valid YAML: {what}"


def _fail(source: str, line: int, col: int, message: str):
    raise ScenarioError([Problem(Location(source, line, col), message)])


def _dotted(path: PathKey) -> str:
    return "".join(f"[{p}]" if isinstance(p, int) else (f".{p}" if i else p) for i, p in enumerate(path))


def _is_empty(node: yaml.Node) -> bool:
    """A document with nothing in it (just '---' and comments)."""
    return isinstance(node, yaml.ScalarNode) and node.tag == "tag:yaml.org,2002:null" and node.value == ""


def _tag(tag: str) -> str:
    """A tag as it is written in YAML: ``!!python/object`` rather than ``tag:yaml.org,2002:python/object``."""
    return "!!" + tag[len(_STANDARD_TAG_PREFIX):] if tag.startswith(_STANDARD_TAG_PREFIX) else tag


class _Reader(yaml.SafeLoader):
    """PyYAML's safe composer, bounded in depth, remembering where each alias is written.

    Also reads ``1e-3`` and ``1e+16`` (YAML 1.2 and JSON floats) as numbers, not strings.
    """

    def __init__(self, text: str, source: str):
        super().__init__(text)
        self.source = source
        self.depth = 0
        # (id of the parent node, index or id of the key node) -> where the alias was written
        self.alias_marks: dict[tuple[int, int], yaml.Mark] = {}

    def compose_node(self, parent, index):
        if self.check_event(yaml.AliasEvent):
            mark = self.peek_event().start_mark
            node = super().compose_node(parent, index)
            if parent is not None:
                self.alias_marks[(id(parent), index if isinstance(index, int) else id(index))] = mark
            return node
        if self.depth > MAX_DEPTH:
            mark = self.peek_event().start_mark
            _fail(self.source, mark.line + 1, mark.column + 1,
                  f"document nests deeper than {MAX_DEPTH} levels; refusing to read it")
        self.depth += 1
        try:
            return super().compose_node(parent, index)
        finally:
            self.depth -= 1


_Reader.add_implicit_resolver(
    "tag:yaml.org,2002:float",
    re.compile(r"^[-+]?[0-9][0-9_]*(?:\.[0-9_]*)?[eE][-+]?[0-9]+$"),
    list("-+0123456789"),
)
# a plain '=' is the string '=' (YAML 1.2), not YAML 1.1's 'default value' tag that no constructor knows
_Reader.yaml_implicit_resolvers = {
    first: [(tag, regexp) for tag, regexp in resolvers if tag != "tag:yaml.org,2002:value"]
    for first, resolvers in _Reader.yaml_implicit_resolvers.items()}


_KEY_KINDS = {"tag:yaml.org,2002:int": "an integer", "tag:yaml.org,2002:float": "a number",
              "tag:yaml.org,2002:bool": "a boolean", "tag:yaml.org,2002:null": "null",
              "tag:yaml.org,2002:timestamp": "a date"}


class _Builder:
    """Turns composed nodes into dicts, lists and scalars, recording marks."""

    def __init__(self, source: str, alias_marks: dict[tuple[int, int], yaml.Mark] | None = None,
                 document: Document = SCENARIO):
        self.source = source
        self.document = document
        self.marks: dict[PathKey, Location] = {}
        self.key_marks: dict[PathKey, Location] = {}
        self.alias_marks = alias_marks or {}
        self.sizes: dict[int, int] = {}  # id(node) -> size(node)
        self._scalars = yaml.SafeLoader("")

    def where(self, node: yaml.Node, mark: yaml.Mark | None = None) -> Location:
        mark = mark or node.start_mark
        return Location(self.source, mark.line + 1, mark.column + 1)

    def fail(self, node: yaml.Node, message: str, mark: yaml.Mark | None = None):
        raise ScenarioError([Problem(self.where(node, mark), message)])

    def size(self, node: yaml.Node) -> int:
        """How many values ``node`` expands to once aliases are copied out (capped at MAX_NODES + 1).

        Iterative, so aliases chained deeper than Python's recursion limit are fine; a recursive
        alias (a node inside itself) expands forever, so it counts as too many.
        """
        cap = MAX_NODES + 1
        if id(node) in self.sizes:
            return self.sizes[id(node)]
        totals = {id(node): 1}
        stack = [(node, iter(self.children(node)))]
        while stack:
            current, pending = stack[-1]
            child = next(pending, None) if totals[id(current)] < cap else None
            if child is None:
                stack.pop()
                done = self.sizes[id(current)] = min(totals.pop(id(current)), cap)
                if stack:
                    parent = id(stack[-1][0])
                    totals[parent] = min(totals[parent] + done, cap)
            elif id(child) in self.sizes:
                totals[id(current)] = min(totals[id(current)] + self.sizes[id(child)], cap)
            elif id(child) in totals:  # still open: the child contains its own ancestor
                totals[id(current)] = cap
            else:
                totals[id(child)] = 1
                stack.append((child, iter(self.children(child))))
        return self.sizes[id(node)]

    @staticmethod
    def children(node: yaml.Node) -> list[yaml.Node]:
        if isinstance(node, yaml.MappingNode):
            return [part for pair in node.value for part in pair]
        if isinstance(node, yaml.SequenceNode):
            return list(node.value)
        return []

    def build(self, node: yaml.Node, path: PathKey, depth: int, mark: yaml.Mark | None = None) -> Any:
        if depth > MAX_DEPTH:
            self.fail(node, f"document nests deeper than {MAX_DEPTH} levels (a recursive alias?); refusing to read it", mark)
        if self.size(node) > MAX_NODES and not any(self.size(c) > MAX_NODES for c in self.children(node)):
            # the smallest part of the document that is too big: where the aliases multiply
            self.fail(node, f"this value expands to more than {MAX_NODES:,} values (an alias bomb?); refusing to read it",
                      mark)
        if node.tag not in _PLAIN_TAGS:
            self.fail(node, f"YAML tag '{_tag(node.tag)}' is not allowed: a {self.document.noun} holds plain data only "
                            "(no tags that construct objects)", mark)
        fits = {yaml.MappingNode: ("tag:yaml.org,2002:map",), yaml.SequenceNode: ("tag:yaml.org,2002:seq",)}
        allowed = fits.get(type(node), tuple(_PLAIN_TAGS - {"tag:yaml.org,2002:map", "tag:yaml.org,2002:seq"}))
        if node.tag not in allowed:
            kind = {yaml.MappingNode: "a mapping", yaml.SequenceNode: "a list"}.get(type(node), "a single value")
            self.fail(node, f"YAML tag '{_tag(node.tag)}' cannot be put on {kind}", mark)
        self.marks.setdefault(path, self.where(node, mark))
        if isinstance(node, yaml.MappingNode):
            return self.build_mapping(node, path, depth)
        if isinstance(node, yaml.SequenceNode):
            return [self.build(item, path + (i,), depth + 1, self.alias_marks.get((id(node), i)))
                    for i, item in enumerate(node.value)]
        return self.build_scalar(node, path)

    def build_mapping(self, node: yaml.MappingNode, path: PathKey, depth: int) -> dict:
        result: dict[str, Any] = {}
        first_seen: dict[str, Location] = {}
        for key_node, value_node in node.value:
            if key_node.tag == "tag:yaml.org,2002:merge":
                self.fail(key_node, "merge keys ('<<') are not supported: write the keys out")
            if not isinstance(key_node, yaml.ScalarNode):
                kind = "a mapping" if isinstance(key_node, yaml.MappingNode) else "a list"
                self.fail(key_node, f"a key must be a plain name, got {kind}")
            if key_node.tag in _KEY_KINDS:
                self.fail(key_node, f"a key must be a name, got {key_node.value or 'null'} ({_KEY_KINDS[key_node.tag]}); "
                                    "quote it if it is meant as a name")
            if key_node.tag != "tag:yaml.org,2002:str":
                self.fail(key_node, f"a key must be a plain name, not a value tagged '{_tag(key_node.tag)}'")
            key = key_node.value
            hidden = next((c for c in key if c != " " and unicodedata.category(c) in ("Zs", "Cf")), None)  # look-alikes
            if hidden is not None:
                self.fail(key_node, f"the key {show(key)} holds {character_name(ord(hidden))}, which YAML does not "
                                    "read as a space: keys and indentation are written with plain characters and spaces")
            if key in first_seen:
                first = first_seen[key]
                place = f" in '{_dotted(path)}'" if path else ""
                self.fail(key_node, f"duplicate key '{key}'{place} (first written at line {first.line}); a key may appear once")
            first_seen[key] = self.where(key_node)
            self.key_marks[path + (key,)] = self.where(key_node)
            result[key] = self.build(value_node, path + (key,), depth + 1, self.alias_marks.get((id(node), id(key_node))))
        return result

    def build_scalar(self, node: yaml.ScalarNode, path: PathKey) -> Any:
        field = f"{_dotted(path)}: " if path else ""
        if node.tag == "tag:yaml.org,2002:timestamp":
            return node.value  # kept as written; no field takes a date, so validation names it
        try:
            value = self._scalars.construct_object(node, deep=False)
        except (yaml.YAMLError, ValueError, TypeError, KeyError, IndexError, OverflowError):
            # only an explicit tag (``!!int 0.5``) or an absurdly long number gets here
            kind = {"tag:yaml.org,2002:int": "an integer", "tag:yaml.org,2002:float": "a number",
                    "tag:yaml.org,2002:bool": "true or false"}.get(node.tag, f"'{_tag(node.tag)}'")
            digits = sum(c.isdigit() for c in node.value)
            limit = sys.get_int_max_str_digits()
            if node.tag == "tag:yaml.org,2002:int" and limit and digits > limit:
                self.fail(node, f"{field}a {digits:,}-digit integer is too long to read: expected a number "
                                f"of at most {limit:,} digits")
            self.fail(node, f"{field}{show(node.value)} cannot be read as {kind}")
        reason = refusal(node.tag, node.value, value) if node.style is None else None
        if reason:
            self.fail(node, field + reason)
        return value
