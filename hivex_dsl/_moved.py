"""Old import paths of the modules that moved into the layer folders (issue 37): one table, one finder.

:data:`MOVED` maps each old path (below ``hivex_dsl``) to its new one; a package's old path covers
everything under it (``hivex_dsl.spec.scenario`` is ``hivex_dsl.lang.spec.scenario``). :class:`MovedFinder`,
first on ``sys.meta_path``, answers only those old paths: ``import hivex_dsl.<old>`` gives the module at
its new path -- the same module object, so ``hivex_dsl.errors.ScenarioError is
hivex_dsl.base.errors.ScenarioError`` -- with a DeprecationWarning that names the new path. The paths in
:data:`PUBLIC` (``hivex_dsl.testing``) are public for good and give no warning. A name that never existed
still raises ModuleNotFoundError.
"""

from __future__ import annotations

import importlib
import importlib.abc
import importlib.machinery
import sys
import warnings
from types import ModuleType

PACKAGE = "hivex_dsl"

# old path -> new path, both below hivex_dsl
MOVED: dict[str, str] = {
    # base/
    "errors": "base.errors",
    "numeric": "base.numeric",
    "resources": "base.resources",
    # lang/
    "yaml11": "lang.yaml11",
    "loader": "lang.loader",
    "blame": "lang.blame",
    "spec": "lang.spec",
    "expr": "lang.expr",
    # sim/
    "spaces": "sim.spaces",
    "action_arrays": "sim.action_arrays",
    "batching": "sim.batching",
    "statistics": "sim.statistics",
    "reward": "sim.reward",
    "fire": "sim.fire",
    "procgen": "sim.procgen",
    "render": "sim.render",
    # compiler/
    "registry": "compiler.registry",
    "locks": "compiler.locks",
    # runtime/
    "global_state": "runtime.global_state",
    "seeding": "runtime.seeding",
    # evaluation/
    "rollout": "evaluation.rollout",
    "policies": "evaluation.policies",
    "report": "evaluation.report",
    "audit": "evaluation.audit",
    "published": "evaluation.published",
    "fidelity": "evaluation.fidelity",
    "bench": "evaluation.bench",
    "bench_expressions": "evaluation.bench_expressions",
    "progress": "evaluation.progress",
    "testing": "evaluation.testing",
    # cli/
    "audit_command": "cli.audit_command",
    "argtypes": "cli.argtypes",
    "points": "cli.points",
    "train.commands": "cli.train_commands",
}

# old paths that stay public without a warning
PUBLIC: frozenset[str] = frozenset({"testing"})


def new_name(fullname: str) -> str | None:
    """Where the module ``fullname`` (e.g. ``hivex_dsl.spec.scenario``) lives now, or None if it did not move."""
    if not fullname.startswith(PACKAGE + "."):
        return None
    rest = fullname[len(PACKAGE) + 1:]
    old = max((old for old in MOVED if rest == old or rest.startswith(old + ".")), key=len, default=None)
    return None if old is None else f"{PACKAGE}.{MOVED[old]}{rest[len(old):]}"


def is_public(fullname: str) -> bool:
    """Whether ``fullname`` is an old path kept public (no warning), e.g. ``hivex_dsl.testing``."""
    rest = fullname[len(PACKAGE) + 1:]
    return any(rest == old or rest.startswith(old + ".") for old in PUBLIC)


class MovedFinder(importlib.abc.MetaPathFinder):
    """Finds the old paths of :data:`MOVED` and nothing else."""

    def find_spec(self, fullname, path=None, target=None):
        new = new_name(fullname)
        if new is None:
            return None
        try:
            module = importlib.import_module(new)
        except ModuleNotFoundError as exc:
            if exc.name == new:  # no such module at the new path either: the old name is unknown
                return None
            raise
        if not is_public(fullname):
            warnings.warn(f"{fullname} moved to {new}; import it from there", DeprecationWarning,
                          stacklevel=_caller_level())
        return importlib.machinery.ModuleSpec(fullname, _AliasLoader(module),
                                              is_package=hasattr(module, "__path__"))


class _AliasLoader(importlib.abc.Loader):
    """Loads an old path as the module already imported at its new path, whose own ``__spec__`` it keeps."""

    def __init__(self, module: ModuleType):
        self.module = module
        self.spec = module.__spec__

    def create_module(self, spec):
        return self.module

    def exec_module(self, module):
        module.__spec__ = self.spec  # the import system set the alias's spec; the module keeps its own


def _caller_level() -> int:
    """The ``stacklevel`` of the frame that imports: the first outside the import machinery and this package's
    import hooks, so the warning points at the user's ``import`` line."""
    frame, level = sys._getframe(1), 1
    while frame is not None and _in_machinery(frame.f_code.co_filename):
        frame = frame.f_back
        if frame is not None and not _bootstrap(frame.f_code.co_filename):
            level += 1  # warnings.warn skips importlib's bootstrap frames itself: count only the others
    return level


def _bootstrap(filename: str) -> bool:
    return "importlib" in filename and "_bootstrap" in filename


def _in_machinery(filename: str) -> bool:
    return (filename.startswith("<frozen importlib") or filename == __file__ or filename == importlib.__file__
            or filename == _FACADE)


_FACADE = __file__.rsplit("_moved.py", 1)[0] + "__init__.py"


def install() -> None:
    """Put :class:`MovedFinder` first on ``sys.meta_path`` (once): it must answer before the path finder, which
    would otherwise load a moved package's submodules a second time under their old names."""
    if not any(isinstance(finder, MovedFinder) for finder in sys.meta_path):
        sys.meta_path.insert(0, MovedFinder())


def moved_attribute(name: str) -> ModuleType:
    """``hivex_dsl.<name>`` for an old top-level path (the package's ``__getattr__``): the module, imported as
    ``import hivex_dsl.<name>`` would (with its warning)."""
    if name not in MOVED:
        raise AttributeError(f"module {PACKAGE!r} has no attribute {name!r}")
    return importlib.import_module(f"{PACKAGE}.{name}")
