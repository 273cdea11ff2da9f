"""Tokenizer and parser of the expression language: source text to a tree of a few node types.

A hand-written recursive-descent parser rather than Python's ``ast``: the language is a small,
strict subset, every token keeps its 0-based character offset (``ast`` counts UTF-8 bytes per
line), and each Python construct we refuse (attribute access, subscripts, strings, keywords
such as ``lambda`` or ``import``, keyword arguments, dunder names) gets its own message at the
offending token. Precedence, loosest first, as in Python::

    or  <  and  <  not  <  comparisons (chainable)  <  + -  <  * /  <  unary -  <  **  <  atoms

``**`` is right-associative and binds tighter than a unary minus on its left (``-x**2`` is
``-(x**2)``); its exponent may carry a unary minus (``x**-1``). A number may carry a unit in
braces, ``500{m}`` or ``2.5{m/s}``; a plain number adapts to the unit of the other side.
"""

from __future__ import annotations

import keyword
import re
from dataclasses import dataclass

from .errors import ExpressionError

MAX_DEPTH = 120  # the deepest tree accepted: checking and evaluation recurse once per level
MAX_NESTING = 50  # the most parentheses, calls and prefix operators open at once: parsing recurses
_COMPARISONS = ("<", "<=", ">", ">=", "==", "!=")
_TOKEN = re.compile(
    r"(?P<space>\s+)"
    r"|(?P<num>(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?(?:\s*\{[^{}]*\})?)"
    r"|(?P<name>[A-Za-z_][A-Za-z0-9_]*)"
    r"|(?P<op>\*\*|<=|>=|==|!=|&&|\|\||[-+*/<>(),=!&|^%.\[\]{}'\"])"
)
_REFUSED = {
    ".": "attribute access ('.') is not allowed",
    "[": "subscripts ('[...]') are not allowed",
    "]": "subscripts ('[...]') are not allowed",
    "{": "'{' is not part of the expression language",
    "}": "'}' is not part of the expression language",
    "&&": "use 'and' to combine conditions",
    "&": "use 'and' to combine conditions",
    "||": "use 'or' to combine conditions",
    "|": "use 'or' to combine conditions",
    "!": "use 'not' to negate a condition",
    "^": "use '**' for powers",
    "%": "'%' is not part of the expression language",
}
_KEYWORD_HINTS = {
    "if": "; use where(cond, a, b)",
    "else": "; use where(cond, a, b)",
    "True": "; compare instead, e.g. x > 0",
    "False": "; compare instead, e.g. x > 0",
}


@dataclass(frozen=True)
class Token:
    kind: str  # "num", "name", "op" or "end"
    text: str
    offset: int


@dataclass(frozen=True)
class Node:
    """A node of the tree; ``offset``/``length`` span its source text."""

    offset: int
    length: int


@dataclass(frozen=True)
class Number(Node):
    value: float
    unit: str | None = None  # written as 500{m}; None for a plain number, which adapts


@dataclass(frozen=True)
class Name(Node):
    name: str


@dataclass(frozen=True)
class Call(Node):
    function: Token
    args: tuple[Node, ...]


@dataclass(frozen=True)
class Unary(Node):
    op: Token  # '-' or 'not'
    operand: Node


@dataclass(frozen=True)
class Binary(Node):
    op: Token  # + - * / ** and or
    left: Node
    right: Node


@dataclass(frozen=True)
class Compare(Node):
    ops: tuple[Token, ...]
    operands: tuple[Node, ...]


def written_number(node: Node) -> float | None:
    """The value of a number written out, ``2`` or ``-2``; None for anything else."""
    if isinstance(node, Number):
        return node.value
    if isinstance(node, Unary) and node.op.text == "-" and isinstance(node.operand, Number):
        return -node.operand.value
    return None


def calls_of(node: Node, names: tuple[str, ...]) -> list[Call]:
    """The calls of the functions ``names`` in the tree ``node``, outermost first, left to right."""
    found: list[Call] = []
    pending = [node]
    while pending:
        current = pending.pop()
        if isinstance(current, Call) and current.function.text in names:
            found.append(current)
        children = (current.args if isinstance(current, Call) else (current.operand,) if isinstance(current, Unary)
                    else (current.left, current.right) if isinstance(current, Binary)
                    else current.operands if isinstance(current, Compare) else ())
        pending.extend(reversed(children))
    return found


def tokenize(source: str) -> list[Token]:
    """The tokens of ``source``, ending in an ``end`` token; ExpressionError at the first bad character."""
    tokens: list[Token] = []
    position = 0
    while position < len(source):
        match = _TOKEN.match(source, position)
        if match is None:
            raise ExpressionError(f"unexpected character {source[position]!r}", position, 1)
        kind, text = match.lastgroup, match.group()
        if kind == "num" and _word_end(source, match.end()) > match.end():
            end = _word_end(source, match.end())
            raise ExpressionError(f"malformed number {source[position:end]!r}", position, end - position)
        if kind == "op" and text in "'\"":
            end = source.find(text, position + 1)
            length = (end + 1 if end >= 0 else len(source)) - position
            raise ExpressionError("strings are not allowed", position, length)
        if kind == "op" and text in _REFUSED:
            length = _word_end(source, position + 1) - position if text == "." else len(text)
            raise ExpressionError(_REFUSED[text], position, length)
        if kind == "name":
            _check_name(text, position)
        if kind != "space":
            tokens.append(Token(kind, text, position))
        position = match.end()
    tokens.append(Token("end", "", len(source)))
    return tokens


def _word_end(source: str, position: int) -> int:
    while position < len(source) and (source[position].isalnum() or source[position] == "_"):
        position += 1
    return position


def _check_name(text: str, position: int) -> None:
    if "__" in text:
        raise ExpressionError(f"names with double underscores are not allowed ({text!r})", position, len(text))
    if keyword.iskeyword(text) and text not in ("and", "or", "not"):
        hint = _KEYWORD_HINTS.get(text, "")
        raise ExpressionError(f"{text!r} is not part of the expression language{hint}", position, len(text))


def parse(source: str) -> Node:
    """The tree of ``source``; ExpressionError with the offset and length of the offending token."""
    tokens = tokenize(source)
    if tokens[0].kind == "end":
        raise ExpressionError("empty expression", 0, len(source))
    parser = _Parser(tokens)
    tree = parser.expression()
    end = parser.peek()
    if end.kind != "end":
        raise ExpressionError(f"unexpected {_shown(end)} after a complete expression", end.offset, len(end.text))
    return tree


def _shown(token: Token) -> str:
    return "end of expression" if token.kind == "end" else repr(token.text)


def _span(first: Node | Token, last: Node | Token) -> tuple[int, int]:
    end = last.offset + (last.length if isinstance(last, Node) else len(last.text))
    return first.offset, end - first.offset


class _Parser:
    def __init__(self, tokens: list[Token]):
        self.tokens = tokens
        self.index = 0
        self.depth: dict[int, int] = {}  # id(node) -> depth below it
        self.open = 0  # parentheses, calls and prefix operators being parsed

    def nested(self, token: Token, parse):
        """``parse()`` one level deeper; refused beyond MAX_NESTING levels, before Python's recursion limit."""
        if self.open >= MAX_NESTING:
            raise ExpressionError(f"expression nested too deeply (more than {MAX_NESTING} levels)",
                                  token.offset, len(token.text))
        self.open += 1
        try:
            return parse()
        finally:
            self.open -= 1

    def peek(self) -> Token:
        return self.tokens[self.index]

    def take(self) -> Token:
        token = self.tokens[self.index]
        self.index += 1
        return token

    def made(self, node: Node, *children: Node, at: Token | Node | None = None) -> Node:
        depth = 1 + max((self.depth.get(id(c), 0) for c in children), default=0)
        if depth > MAX_DEPTH:
            where = at if at is not None else node
            length = where.length if isinstance(where, Node) else len(where.text)
            raise ExpressionError(f"expression nested too deeply (more than {MAX_DEPTH} levels)", where.offset, length)
        self.depth[id(node)] = depth
        return node

    def expression(self) -> Node:
        return self.binary_chain(("or",), self.conjunction)

    def conjunction(self) -> Node:
        return self.binary_chain(("and",), self.negation)

    def negation(self) -> Node:
        if self.peek().text == "not" and self.peek().kind == "name":
            op = self.take()
            operand = self.nested(op, self.negation)
            return self.made(Unary(*_span(op, operand), op, operand), operand, at=op)
        return self.comparison()

    def comparison(self) -> Node:
        operands, ops = [self.sum()], []
        while self.peek().kind == "op" and self.peek().text in _COMPARISONS + ("=",):
            op = self.take()
            if op.text == "=":
                raise ExpressionError("use '==' to compare", op.offset, 1)
            ops.append(op)
            operands.append(self.sum())
        if not ops:
            return operands[0]
        return self.made(Compare(*_span(operands[0], operands[-1]), tuple(ops), tuple(operands)), *operands, at=ops[-1])

    def sum(self) -> Node:
        return self.binary_chain(("+", "-"), self.product)

    def product(self) -> Node:
        return self.binary_chain(("*", "/"), self.unary)

    def binary_chain(self, ops: tuple[str, ...], operand) -> Node:
        left = operand()
        while self.peek().text in ops and self.peek().kind in ("op", "name"):
            op = self.take()
            right = operand()
            left = self.made(Binary(*_span(left, right), op, left, right), left, right, at=op)
        return left

    def unary(self) -> Node:
        if self.peek().text == "-" and self.peek().kind == "op":
            op = self.take()
            operand = self.nested(op, self.unary)
            return self.made(Unary(*_span(op, operand), op, operand), operand, at=op)
        if self.peek().text == "+" and self.peek().kind == "op":
            raise ExpressionError("unary '+' is not part of the expression language", self.peek().offset, 1)
        return self.power()

    def power(self) -> Node:
        base = self.atom()
        if self.peek().text == "**" and self.peek().kind == "op":
            op = self.take()
            exponent = self.nested(op, self.unary)
            return self.made(Binary(*_span(base, exponent), op, base, exponent), base, exponent, at=op)
        return base

    def atom(self) -> Node:
        token = self.take()
        if token.kind == "num":
            digits, _, unit = token.text.partition("{")
            return Number(token.offset, len(token.text), float(digits), unit[:-1].strip() if unit else None)
        if token.kind == "name" and token.text not in ("and", "or", "not"):
            if self.peek().text == "(" and self.peek().kind == "op":
                return self.nested(token, lambda: self.call(token))
            return Name(token.offset, len(token.text), token.text)
        if token.text == "(" and token.kind == "op":
            inner = self.nested(token, self.expression)
            self.close(token)
            return inner
        raise ExpressionError(f"expected a number, a name or '(', got {_shown(token)}", token.offset, len(token.text))

    def call(self, function: Token) -> Node:
        opening = self.take()
        args: list[Node] = []
        if self.peek().text != ")":
            while True:
                if self.peek().kind == "name" and self.tokens[self.index + 1].text == "=":
                    keyword_ = self.peek()
                    raise ExpressionError("keyword arguments are not allowed", keyword_.offset, len(keyword_.text))
                args.append(self.expression())
                if self.peek().text != ",":
                    break
                self.take()
        closing = self.close(opening)
        return self.made(Call(*_span(function, closing), function, tuple(args)), *args, at=function)

    def close(self, opening: Token) -> Token:
        token = self.take()
        if token.text == ")" and token.kind == "op":
            return token
        if token.kind == "end":
            raise ExpressionError("unclosed '('", opening.offset, 1)
        raise ExpressionError(f"expected ')' or an operator, got {_shown(token)}", token.offset, len(token.text))
