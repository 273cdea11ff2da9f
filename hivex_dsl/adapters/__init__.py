"""PettingZoo and Gymnasium views of the batched runtime."""


def module_doc(name: str) -> str:
    """The docstring of the adapter module ``name`` (``"sb3"``, ``"benchmarl"``...) without importing it, nor the
    library it needs (for the docs)."""
    import ast
    from pathlib import Path

    return ast.get_docstring(ast.parse((Path(__file__).parent / f"{name}.py").read_text())) or ""
