"""One package per environment; each registers itself with :mod:`hivex_dsl.registry` on import."""
