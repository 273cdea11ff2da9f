"""Layer 4, compiler: a scenario (file, dict or lock) into frozen, fingerprinted CompiledScenarios.

dispatch.py (compile, compile_all: a path, name or dict read, and sent to locks.py if it is a lock file, else to
scenario.py), scenario.py (CompiledScenario, validation, sweeps and the semantic checks), locks.py (lock files,
checked field by field) and registry.py (the environments: catalogue entry, params, reward terms, simulator
factory; their packages are found by module name). Imports: base, lang, sim. The environments (layer 6)
register themselves here when the registry imports them by name; no module here imports them.
"""

from .dispatch import compile, compile_all, compile_loaded
from .locks import as_written, written
from .scenario import (LOCK_VERSION, MAX_SWEEP_EXPRESSION_CHARS, MAX_SWEEP_EXPRESSIONS, MAX_SWEEP_POINTS,
                       MAX_SWEEP_VALUES, CompiledScenario)

__all__ = ["CompiledScenario", "LOCK_VERSION", "MAX_SWEEP_EXPRESSION_CHARS", "MAX_SWEEP_EXPRESSIONS", "MAX_SWEEP_POINTS",
           "MAX_SWEEP_VALUES", "as_written", "compile", "compile_all", "compile_loaded", "written"]
