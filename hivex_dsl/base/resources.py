"""Where the declarative content (scenarios/, rewards/, generators/) lives.

In a wheel it is package data under ``hivex_dsl/_data``; in a source checkout (including an
editable install) it is the top of the repository, next to the package.
"""

from __future__ import annotations

from pathlib import Path

_PACKAGE = Path(__file__).resolve().parent.parent  # hivex_dsl/ (this file is hivex_dsl/base/resources.py)
_KINDS = ("scenarios", "rewards", "generators")


def data_dir(kind: str) -> Path:
    """The directory holding one kind of bundled content."""
    if kind not in _KINDS:
        raise ValueError(f"unknown kind of bundled content {kind!r}; expected one of {_KINDS}")
    for candidate in (_PACKAGE / "_data" / kind, _PACKAGE.parent / kind):
        if candidate.is_dir():
            return candidate
    raise FileNotFoundError(f"bundled {kind}/ not found next to {_PACKAGE}; is the installation complete?")


def bundled_scenarios() -> list[Path]:
    """Every bundled scenario file, sorted."""
    return sorted(data_dir("scenarios").glob("*/*.yaml"))


def resolve_scenario_path(text: str) -> Path:
    """A user's path as given if it exists, else the bundled scenario it names.

    Accepted bundled forms: ``scenarios/<env>/<name>.yaml``, ``<env>/<name>.yaml`` and ``<env>/<name>``.
    """
    path = Path(text)
    if path.exists():
        return path
    parts = path.parts[1:] if path.parts[:1] == ("scenarios",) else path.parts
    if len(parts) == 2:
        candidate = data_dir("scenarios").joinpath(*parts)
        for option in (candidate, candidate.with_suffix(".yaml")):
            if option.is_file():
                return option
    return path
