"""Layer 6, envs: the five HIVEX environments, one package per environment id (the registry finds any package here,
see docs/adding_an_environment.md), and island.py (the wildfire island
Aerial Wildfire Suppression and Wildfire Resource Management share).

Each package holds its simulator, reward terms, params, statistics, scripted policy, render, global state
and expression vocabulary, and registers itself with :mod:`hivex_dsl.compiler.registry` on import (the
registry imports it by module name). Imports: base, lang, sim, compiler, runtime.
"""
