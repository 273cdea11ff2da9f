"""The one error of the expression language: a message and the span of source it blames."""

from __future__ import annotations

from ...base.errors import HivexError


class ExpressionError(HivexError, ValueError):
    """An expression that cannot be compiled.

    ``message``: one line saying what is wrong; ``offset``: 0-based character index of the
    offending token in the expression's source; ``length``: its number of characters (0 at the end).
    """

    def __init__(self, message: str, offset: int, length: int = 1):
        super().__init__(message)
        self.message = message
        self.offset = offset
        self.length = length

    def line_column(self, source: str) -> tuple[int, int]:
        """The 1-based line and column of the blamed span inside ``source`` (which may span lines)."""
        line = source.count("\n", 0, self.offset) + 1
        return line, self.offset - (source.rfind("\n", 0, self.offset) + 1) + 1

    def pointer(self, source: str) -> str:
        """``source`` and a caret line under the blamed span, for a terminal."""
        line_start = source.rfind("\n", 0, self.offset) + 1
        line_end = source.find("\n", self.offset)
        line = source[line_start : line_end if line_end >= 0 else len(source)]
        column = self.offset - line_start
        return f"{line}\n{' ' * column}{'^' * max(1, min(self.length, len(line) - column))}"
