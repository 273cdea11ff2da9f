"""What YAML 1.1 (PyYAML) reads differently from what a user most likely meant, and how to say so.

PyYAML follows YAML 1.1, whose plain scalars have readings that YAML 1.2, JSON and Python do
not share: ``0123`` is octal 83, ``1:30`` is base 60 (90), ``yes``/``no``/``on``/``off`` are
booleans and ``1_000_`` is an integer. A scenario must never be rewritten behind its author's
back, so the loader refuses those spellings and asks for the plain form. Spellings every
reading agrees on stay accepted: ``0x1F`` and ``0b101`` (Python's meaning), ``1_000``
(digits grouped as Python groups them), ``true``/``false``, ``~``/``null``, ``.inf``/``.nan``
(which number fields then refuse as not finite).
"""

from __future__ import annotations

import re
import unicodedata
from typing import Any, Optional

_INT = "tag:yaml.org,2002:int"
_FLOAT = "tag:yaml.org,2002:float"
_BOOL = "tag:yaml.org,2002:bool"
_YAML_1_1_BOOLEANS = {word: value for value in (True, False)
                      for base in (("yes", "on") if value else ("no", "off"))
                      for word in (base, base.capitalize(), base.upper())}
_LEADING_ZERO = re.compile(r"^[-+]?0_*[0-9]")


def refusal(tag: str, text: str, reading: Any) -> Optional[str]:
    """Why the plain scalar ``text``, which PyYAML read as ``reading`` with ``tag``, is refused (or None)."""
    if tag == _BOOL and text in _YAML_1_1_BOOLEANS:
        word = "true" if reading else "false"
        return (f"{text} is read by YAML 1.1 as the boolean {word}; write {word}, "
                f"or quote it ('{text}') if it is meant as text")
    if tag not in (_INT, _FLOAT):
        return None
    if ":" in text:
        return (f"{text} is read by YAML 1.1 as a base-60 number ({_plain(reading)}); write {_plain(reading)}, "
                f"or quote it ('{text}') if it is meant as text")
    if tag == _INT and _LEADING_ZERO.match(text):
        decimal = ("-" if text.startswith("-") else "") + (text.lstrip("+-").replace("_", "").lstrip("0") or "0")
        other = f", or {decimal} if that is what was meant" if decimal != str(reading) else ""
        return (f"{text} has a leading zero, which YAML 1.1 reads as the octal number {reading}; "
                f"write the plain decimal form {reading}{other}")
    if "_" in text and not _python_reads(tag, text):
        return f"{text} is read by YAML 1.1 as {_plain(reading)}; write the plain form {_plain(reading)}"
    return None


def _python_reads(tag: str, text: str) -> bool:
    """Whether Python reads the same digits (underscores only between digits)."""
    try:
        int(text, 0) if tag == _INT else float(text)
    except ValueError:
        return False
    return True


def _plain(value: Any) -> str:
    if isinstance(value, float) and value.is_integer() and abs(value) < 1e16:
        return repr(value)
    return str(value)


# --- characters YAML refuses -----------------------------------------------------------------------

_C0_NAMES = (
    "NULL", "START OF HEADING", "START OF TEXT", "END OF TEXT", "END OF TRANSMISSION", "ENQUIRY",
    "ACKNOWLEDGE", "BELL", "BACKSPACE", "CHARACTER TABULATION", "LINE FEED", "LINE TABULATION",
    "FORM FEED", "CARRIAGE RETURN", "SHIFT OUT", "SHIFT IN", "DATA LINK ESCAPE", "DEVICE CONTROL ONE",
    "DEVICE CONTROL TWO", "DEVICE CONTROL THREE", "DEVICE CONTROL FOUR", "NEGATIVE ACKNOWLEDGE",
    "SYNCHRONOUS IDLE", "END OF TRANSMISSION BLOCK", "CANCEL", "END OF MEDIUM", "SUBSTITUTE", "ESCAPE",
    "INFORMATION SEPARATOR FOUR", "INFORMATION SEPARATOR THREE", "INFORMATION SEPARATOR TWO",
    "INFORMATION SEPARATOR ONE",
)


def character_name(code: int) -> str:
    """``U+000C FORM FEED``: the code point and its Unicode name (control characters have none in unicodedata)."""
    if code < 0x20:
        name = _C0_NAMES[code]
    elif code == 0x7F:
        name = "DELETE"
    elif 0x80 <= code <= 0x9F:
        name = "(a C1 control character)"
    elif 0xD800 <= code <= 0xDFFF:
        name = "(a lone surrogate)"
    else:
        name = unicodedata.name(chr(code), "(a noncharacter)")
    return f"U+{code:04X} {name}"


def refused_character(code: int) -> str:
    """The message for a character PyYAML's reader refuses."""
    escape = f"\\x{code:02x}" if code < 0x100 else (f"\\u{code:04x}" if code < 0x10000 else f"\\U{code:08x}")
    return (f"{character_name(code)} is not allowed in YAML: expected printable text "
            f"(inside double quotes the escape \"{escape}\" writes it)")


def line_and_column(text: str, position: int) -> tuple[int, int]:
    """1-based line and column of ``text[position]``, counting line breaks as PyYAML's marks do."""
    line, start, i = 1, 0, 0
    while i < position:
        ch = text[i]
        if ch in "\n\x85\u2028\u2029" or (ch == "\r" and text[i + 1: i + 2] != "\n"):
            line, start = line + 1, i + 1
        i += 1
    return line, position - start + 1
