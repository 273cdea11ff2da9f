"""PettingZoo and Gymnasium views of the batched runtime."""


def sb3_doc() -> str:
    """The docstring of :mod:`hivex_dsl.adapters.sb3` without importing SB3 (for the docs)."""
    import ast
    from pathlib import Path

    return ast.get_docstring(ast.parse((Path(__file__).parent / "sb3.py").read_text())) or ""
