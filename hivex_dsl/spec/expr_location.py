"""Where in a YAML file a character of an expression was written.

An expression error carries a 0-based offset into the string YAML gave us; the file may have
written that string plain, quoted (with escapes and folded lines) or as a block scalar (``|``,
``>``). We re-read the scalar from its first character and map each character of the value back
to a (line, column), then check that what we rebuilt is the value: if not (a style we do not
follow), the scalar's own location is the answer, never a wrong column.
"""

from __future__ import annotations

from functools import lru_cache
from pathlib import Path

from ..errors import Location

Positions = list[tuple[int, int]]  # (0-based line, 0-based column) of each character of the value


def expression_location(start: Location, value: str, offset: int) -> Location:
    """The location of ``value[offset]`` given where the scalar holding ``value`` starts."""
    lines = _lines(start.path)
    if lines is None or not 1 <= start.line <= len(lines):
        return start
    try:
        text, positions = _scan(lines, start.line - 1, start.col - 1)
    except IndexError:
        return start
    kept = value.rstrip("\n")  # a block scalar's final line break is not a character the scan sees
    if not kept or not positions or not text.startswith(kept):
        return start
    line, col = positions[min(max(offset, 0), len(kept) - 1)]
    return Location(start.path, line + 1, col + 1)


@lru_cache(maxsize=8)
def _lines(path: str) -> tuple[str, ...] | None:
    try:
        return tuple(Path(path).read_text("utf-8").split("\n"))
    except (OSError, UnicodeDecodeError, ValueError):
        return None


def _scan(lines: tuple[str, ...], row: int, col: int) -> tuple[str, Positions]:
    first = lines[row][col]
    if first in "|>":
        return _block(lines, row, literal=first == "|")
    if first == "'":
        return _quoted(lines, row, col + 1, "'")
    if first == '"':
        return _quoted(lines, row, col + 1, '"')
    return _plain(lines, row, col)


def _plain(lines: tuple[str, ...], row: int, col: int) -> tuple[str, Positions]:
    """A plain scalar: its first line from ``col``, continuation lines folded into single spaces."""
    chars: list[str] = []
    positions: Positions = []
    indent = len(lines[row]) - len(lines[row].lstrip())
    line, start = row, col
    while line < len(lines):
        segment = lines[line][start:]
        cut = segment.find(" #")
        segment = (segment if cut < 0 else segment[:cut]).rstrip()
        if line > row:
            stripped = segment.lstrip()
            if not stripped or len(segment) - len(stripped) + start <= indent or ":" in stripped:
                break
            start += len(segment) - len(stripped)
            segment = stripped
            chars.append(" ")
            positions.append(positions[-1] if positions else (line, start))
        chars.extend(segment)
        positions.extend((line, start + i) for i in range(len(segment)))
        line, start = line + 1, 0
    return "".join(chars), positions


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
        if i >= len(text):  # a line break inside quotes folds into a space (leading blanks of the next line go)
            while chars and chars[-1] in " \t":
                chars.pop()
                positions.pop()
            line += 1
            i = len(lines[line]) - len(lines[line].lstrip(" \t"))
            chars.append(" ")
            positions.append((line, i))
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


def _block(lines: tuple[str, ...], row: int, literal: bool) -> tuple[str, Positions]:
    """A literal (``|``) or folded (``>``) block scalar: the lines after its header, less their indentation."""
    body = [n for n in range(row + 1, len(lines)) if lines[n].strip()]
    if not body:
        return "", []
    indent = len(lines[body[0]]) - len(lines[body[0]].lstrip(" "))
    chars: list[str] = []
    positions: Positions = []
    previous = None
    for n in range(row + 1, len(lines)):
        text = lines[n]
        if text.strip() and len(text) - len(text.lstrip(" ")) < indent:
            break
        if previous is not None:
            chars.append("\n" if literal or not text.strip() or not lines[previous].strip() else " ")
            positions.append((previous, len(lines[previous])))
        content = text[indent:]
        chars.extend(content)
        positions.extend((n, indent + i) for i in range(len(content)))
        previous = n
    return "".join(chars), positions
