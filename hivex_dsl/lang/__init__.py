"""Layer 2, lang: the scenario language's primitives, what a scenario file is before any environment runs it.

yaml11.py (YAML 1.1 scalars read as the language means them), loader.py (files and text into located data,
with size and depth limits), blame.py (which written value causes a cross-field problem), spec/ (the pydantic
models of scenarios, reward tables and the catalogue) and expr/ (the expression language: grammar, units,
intervals, checker and plans). Imports: base.
"""
