"""Where in a YAML file a character of an expression was written.

An expression error carries a 0-based offset into the string YAML gave us; the file may have
written that string plain, quoted (with escapes and folded lines) or as a block scalar (``|``,
``>``). We re-read the scalar from its first character and map each character of the value back
to a (line, column):

- plain and block scalars hold their characters verbatim; only line breaks and indentation change
  (a folded ``>`` joins lines with spaces but keeps the breaks around more-indented lines, a
  literal ``|`` keeps every break, both drop the indentation), so the value is aligned with the
  source: every other character of the value must be the next one written, and whitespace stands
  for the written whitespace or line break it came from;
- quoted scalars are re-read with their escapes and folding, and what we rebuilt must be the value.

When the value cannot be followed (a style or file we do not follow), :func:`traced_location` says
so with None and :func:`expression_location` answers the scalar's own location, never a wrong column.
"""

from __future__ import annotations

import os
from functools import lru_cache
from pathlib import Path
from typing import Optional

from ...base.errors import Location

Positions = list[tuple[int, int]]  # (0-based line, 0-based column) of each character of the value
_BLANKS = " \t\r"  # a CRLF file's lines end in "\r", which YAML reads as part of the line break


def expression_location(start: Location, value: str, offset: int) -> Location:
    """The location of ``value[offset]`` given where the scalar holding ``value`` starts; ``start`` itself
    when the scalar cannot be followed."""
    return traced_location(start, value, offset) or start


def traced_location(start: Location, value: str, offset: int) -> Optional[Location]:
    """The location of ``value[offset]`` (clamped to the value's last written character) given where the
    scalar holding ``value`` starts; ``start`` when there is no file to read (a scenario given as a dict);
    None when the file is there but its scalar cannot be followed character by character."""
    lines = _lines(start.path)
    if lines is None:
        return start
    if not 1 <= start.line <= len(lines) or not 1 <= start.col <= len(lines[start.line - 1]):
        return None
    try:
        positions = _positions(lines, start.line - 1, start.col - 1, value)
    except IndexError:
        return None
    if not positions:
        return None
    line, col = positions[min(max(offset, 0), len(positions) - 1)]
    return Location(start.path, line + 1, col + 1)


def _lines(path: str) -> tuple[str, ...] | None:
    """The lines of the file ``path`` as it is now (a file edited since it was last read is read again)."""
    try:
        info = os.stat(path)
    except (OSError, ValueError):
        return None
    return _read_lines(path, info.st_mtime_ns, info.st_size)


@lru_cache(maxsize=8)
def _read_lines(path: str, mtime_ns: int, size: int) -> tuple[str, ...] | None:
    try:
        return tuple(Path(path).read_text("utf-8").split("\n"))
    except (OSError, UnicodeDecodeError, ValueError):
        return None


def _positions(lines: tuple[str, ...], row: int, col: int, value: str) -> Optional[Positions]:
    """Where each character of ``value`` (less its trailing whitespace) is written, for the scalar whose first
    character is ``lines[row][col]``; None when the source does not hold that value."""
    first = lines[row][col]
    if first in "|>":  # a block scalar: its content starts on the line after the header
        return _aligned(lines, row + 1, 0, value.rstrip())
    if first in "'\"":
        text, positions = _quoted(lines, row, col + 1, first)
        kept = value.rstrip("\n")  # a final escaped line break is not a character the scan sees
        return positions[: len(kept)] if kept and text.startswith(kept) else None
    return _aligned(lines, row, col, value.rstrip())


def _aligned(lines: tuple[str, ...], row: int, col: int, value: str) -> Optional[Positions]:
    """Positions of the characters of ``value`` written verbatim from ``lines[row][col]`` on, where only
    whitespace may differ: each non-blank character of the value is the next non-blank one written (blanks
    and line breaks before it are indentation or folding), and each blank or line break of the value
    stands for the next blank or line break written. None when the source does not hold the value."""
    positions: Positions = []
    for char in value:
        if char not in " \t\n":
            while row < len(lines) and (col >= len(lines[row]) or lines[row][col] in _BLANKS):
                row, col = (row + 1, 0) if col >= len(lines[row]) else (row, col + 1)
            if row >= len(lines) or lines[row][col] != char:
                return None
        elif row >= len(lines) or (col < len(lines[row]) and lines[row][col] not in _BLANKS):
            return None
        positions.append((row, col))
        row, col = (row + 1, 0) if col >= len(lines[row]) else (row, col + 1)
    return positions


_ESCAPES = {"n": "\n", "t": "\t", "r": "\r", "0": "\0", '"': '"', "\\": "\\", "/": "/", " ": " ", "a": "\a",
            "b": "\b", "e": "\x1b", "f": "\f", "v": "\v", "N": "\x85", "_": "\xa0", "L": "\u2028", "P": "\u2029"}
_HEX = {"x": 2, "u": 4, "U": 8}


def _quoted(lines: tuple[str, ...], row: int, col: int, quote: str) -> tuple[str, Positions]:
    """A single- or double-quoted scalar from just after its opening quote."""
    chars: list[str] = []
    positions: Positions = []
    line, i = row, col
    while True:
        text = lines[line]
        if i >= len(text):  # a line break inside quotes: folded (trailing and leading blanks go)
            while chars and chars[-1] in " \t":
                chars.pop()
                positions.pop()
            line, breaks = _fold(lines, line)
            i = len(lines[line]) - len(lines[line].lstrip(" \t"))
            chars.extend(breaks)
            positions.extend([(line, i)] * len(breaks))
            continue
        c = text[i]
        if c == quote:
            if quote == "'" and text[i + 1: i + 2] == "'":
                chars.append("'")
                positions.append((line, i))
                i += 2
                continue
            return "".join(chars), positions
        if quote == '"' and c == "\\":
            code = text[i + 1] if i + 1 < len(text) else "\n"
            if code in _HEX:
                chars.append(chr(int(text[i + 2: i + 2 + _HEX[code]], 16)))
                positions.append((line, i))
                i += 2 + _HEX[code]
                continue
            if code in _ESCAPES:
                chars.append(_ESCAPES[code])
                positions.append((line, i))
                i += 2
                continue
            line, i = line + 1, len(lines[line + 1]) - len(lines[line + 1].lstrip(" \t"))  # escaped line break
            continue
        chars.append(c)
        positions.append((line, i))
        i += 1


def _fold(lines: tuple[str, ...], line: int) -> tuple[int, str]:
    """The line after the break that ends ``lines[line]`` inside quotes, past blank lines, and what the break
    reads as: a space, or one line break per blank line."""
    line += 1
    blank = 0
    while not lines[line].strip(" \t\r"):
        line, blank = line + 1, blank + 1
    return line, "\n" * blank or " "
