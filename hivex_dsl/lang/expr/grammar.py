"""The expression language as data: every operator and function with its unit and interval rule.

The checker takes arities from here and :func:`describe_grammar` hands the same table to the docs,
so the language page and the compiler cannot disagree.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass


@dataclass(frozen=True)
class Entry:
    """One operator or function: how it is written, its units, its range, what it does."""

    name: str
    signature: str
    units: str
    interval: str
    description: str
    arity: int = 0  # functions only


_SAME = "operands of the same unit (a plain number adapts to the other side)"

OPERATORS: tuple[Entry, ...] = (
    Entry("+", "a + b", _SAME, "[a.low + b.low, a.high + b.high]", "Sum."),
    Entry("-", "a - b", _SAME, "[a.low - b.high, a.high - b.low]", "Difference."),
    Entry("*", "a * b", "units multiply (m * m is m^2)", "extremes of the four corner products", "Product."),
    Entry("/", "a / b", "units divide (m / s is m/s)", "corner quotients; refused if b's range contains 0",
          "Quotient."),
    Entry("**", "a ** n", "exponents multiply by n; a fractional n needs whole results",
          "monotone pieces; refused for 0 in a with n < 0 or a negative a with a fractional n",
          "Power by a constant number n (written literally, e.g. x ** 2 or x ** -1); the same bits on every "
          "processor (hivex_dsl.base.portable)."),
    Entry("-x", "-a", "unit of a", "[-a.high, -a.low]", "Negation."),
    Entry("< <= > >= == !=", "a < b", _SAME + "; booleans only with == and !=", "boolean",
          "Comparison, giving a boolean; chains like 0 < x < 5 mean (0 < x) and (x < 5)."),
    Entry("and", "p and q", "booleans", "boolean", "True where both are true."),
    Entry("or", "p or q", "booleans", "boolean", "True where either is true."),
    Entry("not", "not p", "boolean", "boolean", "True where p is false."),
)

FUNCTIONS: dict[str, Entry] = {entry.name: entry for entry in (
    Entry("where", "where(cond, a, b)", "cond boolean; a and b of the same unit (or both boolean)",
          "hull of a's range where cond holds and b's where it does not (conditions comparing a quantity "
          "with a number narrow it)", "a where cond holds, else b (both are computed).", 3),
    Entry("min", "min(a, b)", _SAME, "[min of lows, min of highs]", "Element-wise minimum.", 2),
    Entry("max", "max(a, b)", _SAME, "[max of lows, max of highs]", "Element-wise maximum.", 2),
    Entry("abs", "abs(x)", "unit of x", "[0 or the nearer end, the farther end]", "Absolute value.", 1),
    Entry("clip", "clip(x, lo, hi)", _SAME, "min(max(x, lo), hi) at both ends",
          "x limited to [lo, hi], computed as min(max(x, lo), hi).", 3),
    Entry("exp", "exp(x)", "x dimensionless; result dimensionless",
          "[exp(low), exp(high)]; refused if x can exceed 690 (overflow)",
          "Exponential, the same bits on every processor (hivex_dsl.base.portable).", 1),
    Entry("log", "log(x)", "x dimensionless; result dimensionless",
          "[log(low), log(high)]; refused unless x > 0 everywhere",
          "Natural logarithm, the same bits on every processor (hivex_dsl.base.portable).", 1),
    Entry("sqrt", "sqrt(x)", "exponents halve (m^2 gives m; m is refused)",
          "[sqrt(low), sqrt(high)]; refused if x can be negative", "Square root.", 1),
    Entry("prev", "prev(x)", "unit of x", "range of x",
          "x computed from the quantities one physics step before (whatever the decision_period).", 1),
    Entry("delta", "delta(x)", "unit of x", "[x.low - x.high, x.high - x.low]",
          "x - prev(x): the change of x over the physics step.", 1),
    Entry("team_mean", "team_mean(x)", "unit of x; x per agent, result per world", "range of x",
          "Mean of x over the agents of each world.", 1),
    Entry("team_min", "team_min(x)", "unit of x; x per agent, result per world", "range of x",
          "Smallest x among the agents of each world.", 1),
    Entry("team_max", "team_max(x)", "unit of x; x per agent, result per world", "range of x",
          "Largest x among the agents of each world.", 1),
    Entry("team_sum", "team_sum(x)", "unit of x; x per agent, result per world",
          "[agents * low, agents * high] (ends at 0 kept)", "Sum of x over the agents of each world.", 1),
)}

SYNTAX: tuple[tuple[str, str], ...] = (
    ("number", "1, 0.5, .5, 2e-3; a plain number adapts to the unit of the other side of + - "
               "comparisons min max clip and where, and is dimensionless in * and /"),
    ("number with a unit", "500{m}, 2.5{m/s}, 1{1/s}: units are products and quotients of symbols "
                           "with integer exponents (kg*m/s^2)"),
    ("name", "a quantity of the environment's vocabulary, read after the step"),
    ("call", "one of the functions below, with positional arguments only"),
    ("precedence", "loosest first: or, and, not, comparisons (chainable), + -, * /, unary -, **, "
                   "calls and parentheses; ** is right-associative and -x ** 2 is -(x ** 2)"),
    ("refused", "strings, attribute access, subscripts, keyword arguments, lambdas, imports, "
                "names with double underscores and every other Python construct"),
)

RULES: tuple[str, ...] = (
    "A per-world value combined with a per-agent one applies to every agent of its world.",
    "A team_* reduction needs a per-agent argument and gives a per-world value.",
    "Booleans are not numbers: turn a condition into a number with where(cond, 1, 0).",
    "Every expression's range is inferred from the vocabulary's ranges; an operation that could "
    "divide by zero, take the log or square root of a negative, or overflow (beyond 1e300) is refused, "
    "and so is a scenario whose weighted terms' ranges allow an agent's episode return beyond 1e15.",
    "Operations run exactly as written, left to right, with no reassociation.",
    "Both branches of where are computed: guard a divisor with max(x, small), not with where.",
    "Ranges treat every occurrence of a quantity as independent: x * x may be negative for a "
    "signed x, x ** 2 may not; x - x spans the width of x's range in both directions.",
)


def describe_grammar() -> dict[str, list]:
    """The language as plain data for the docs: syntax forms, operators, functions and general rules.

    ``syntax``: [{"form", "text"}]; ``operators`` and ``functions``: [{"name", "signature",
    "units", "interval", "description"}]; ``rules``: [str].
    """
    return {
        "syntax": [{"form": form, "text": text} for form, text in SYNTAX],
        "operators": [_public(entry) for entry in OPERATORS],
        "functions": [_public(entry) for entry in FUNCTIONS.values()],
        "rules": list(RULES),
    }


def _public(entry: Entry) -> dict:
    row = asdict(entry)
    del row["arity"]
    return row
