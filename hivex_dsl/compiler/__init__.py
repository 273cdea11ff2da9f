"""Layer 4, compiler: a scenario (file, dict or lock) into frozen, fingerprinted CompiledScenarios.

registry.py (the environments: catalogue entry, params, reward terms, simulator factory; found by module
name), scenario.py (CompiledScenario, validation, sweeps and the semantic checks) and locks.py (lock files,
checked field by field). Imports: base, lang, sim; environments register themselves from above.
"""

from .scenario import (LOCK_VERSION, MAX_SWEEP_POINTS, MAX_SWEEP_VALUES, CompiledScenario, compile, compile_all,
                       compile_loaded)

__all__ = ["CompiledScenario", "LOCK_VERSION", "MAX_SWEEP_POINTS", "MAX_SWEEP_VALUES", "compile", "compile_all",
           "compile_loaded"]
