"""The model of rewards/<env>.yaml: the paper's task x reward-term matrix, row for row."""

from __future__ import annotations

import re
from typing import Literal

from pydantic import Field, field_validator

from ...base.errors import did_you_mean
from .common import MAX_WEIGHT, SCHEMA_VERSION, StrictModel
from .expressions import TermsMapping

SNAKE = r"^[a-z][a-z0-9_]*$"
_PLAIN_NAME = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")


class TaskColumn(StrictModel):
    """One column of the matrix: a task with its paper index."""

    index: int = Field(ge=0, le=99, description="The paper's 0-based task index (the configs' `task:` value).")
    name: str = Field(pattern=SNAKE, max_length=60, description="Snake-case name used in scenarios.")
    title: str = Field(max_length=120, description="The task's title as the paper writes it.")
    description: str = Field("", max_length=2000, description="What the agents should learn.")
    ends_on: tuple[str, ...] = Field((), description=(
        "What ends an agent's episode in this task: event names of the environment or boolean expressions."))
    unpaid: tuple[str, ...] = Field((), description=(
        "Terms this task logs but does not pay: they keep their matrix weight for the statistics that mirror them "
        "(a logged total with the task's sign) and add nothing to the reward. Each must have a non-zero weight in "
        "this task's column. Empty for almost every task: a departure from the paper's table, with its evidence in "
        "the notes."))
    trivial_beats_ppo: str = Field("", max_length=3000, description=(
        "Where a trivial policy (all-zeros or random) earns more than the paper's published PPO in this task "
        "at some level: the evidence that this is not a reward bug (that the original shares it). The fidelity "
        "page shows it beside the grid; tests/test_fidelity.py requires it exactly where the stored audit "
        "finds a beaten cell."))

    @field_validator("ends_on", "unpaid", mode="before")
    @classmethod
    def _list_to_tuple(cls, value):
        return tuple(value) if isinstance(value, list) else value


class RewardTable(StrictModel):
    """Tasks as columns, reward terms as rows, each row one weight per task column.

    The model checks the shape; :func:`table_problems` checks it against the environment.
    """

    hivex: Literal[SCHEMA_VERSION] = Field(description="Version of the language.")
    environment: str = Field(description="The environment this table belongs to.")
    source: str = Field(max_length=500, description="Where in the paper the matrix comes from.")
    tasks: tuple[TaskColumn, ...] = Field(min_length=1, max_length=100, description="The columns, in paper order.")
    terms: TermsMapping = Field(None, description=(
        "Reward terms written as expressions over the environment's vocabulary (name -> {expr, ...}); "
        "each needs a row in the matrix like a registered term."))
    matrix: dict[str, tuple[float, ...]] = Field(description="term name -> one weight per task column.")
    notes: tuple[str, ...] = Field((), description="How this table reconciles or departs from the paper.")

    @field_validator("tasks", "notes", mode="before")
    @classmethod
    def _seq_to_tuple(cls, value):
        return tuple(value) if isinstance(value, list) else value

    @field_validator("matrix", mode="before")
    @classmethod
    def _rows_to_tuples(cls, value):
        if isinstance(value, dict):
            return {k: tuple(v) if isinstance(v, list) else v for k, v in value.items()}
        return value

    @property
    def task_names(self) -> tuple[str, ...]:
        return tuple(t.name for t in self.tasks)

    def column(self, task_index: int) -> dict[str, float]:
        """term -> weight of one task, in row order."""
        return {term: row[task_index] for term, row in self.matrix.items()}


def table_problems(table: RewardTable, environment: str, terms: tuple[str, ...],
                   events: tuple[str, ...], quantities: tuple[str, ...] = ()) -> list[tuple[tuple, str]]:
    """(path, message) for everything in ``table`` that does not fit the environment's code.

    ``terms`` are the registered terms; the table's own expression terms join them. An ``ends_on``
    entry that is neither an event nor a plain name (an expression) is compiled with each scenario.
    """
    problems: list[tuple[tuple, str]] = []
    for name in table.terms or {}:
        if name in terms:
            problems.append((("terms", name), f"terms.{name}: '{name}' is already a registered reward term"))
    terms = terms + tuple(name for name in table.terms or {} if name not in terms)
    if table.environment != environment:
        problems.append((("environment",), f"this table is for {environment!r}, not {table.environment!r}"))
    for position, task in enumerate(table.tasks):
        if task.index != position:
            problems.append((("tasks", position, "index"),
                             f"task '{task.name}' has index {task.index}; columns are numbered 0, 1, 2 ... in order"))
        if task.name in table.task_names[:position]:
            problems.append((("tasks", position, "name"), f"task name '{task.name}' is used twice"))
        for k, event in enumerate(task.ends_on):
            if event not in events and _PLAIN_NAME.match(event) and event not in quantities:
                listing = ", ".join(events) or "none"
                problems.append((("tasks", position, "ends_on", k),
                                 f"unknown event '{event}'{did_you_mean(event, events)}; {environment} has: {listing}"))
        for k, term in enumerate(task.unpaid):
            row = table.matrix.get(term, ())
            if len(row) <= position or row[position] == 0.0:
                problems.append((("tasks", position, "unpaid", k),
                                 f"unpaid term '{term}' has no non-zero weight in task '{task.name}': nothing to log"))
    for term, row in table.matrix.items():
        if term not in terms:
            problems.append((("matrix", term), f"unknown reward term '{term}'{did_you_mean(term, terms)}"))
        if len(row) != len(table.tasks):
            problems.append((("matrix", term), f"row '{term}' has {len(row)} weights for {len(table.tasks)} task columns"))
        if any(abs(w) > MAX_WEIGHT for w in row):
            problems.append((("matrix", term), f"row '{term}' has a weight beyond +/-{MAX_WEIGHT:g}"))
    missing = [t for t in terms if t not in table.matrix]
    if missing:
        problems.append((("matrix",), f"no row for reward term(s) {', '.join(missing)}; add a row (zeros are fine)"))
    return problems
