"""One package per environment; each registers itself with :mod:`hivex_dsl.compiler.registry` on import."""
