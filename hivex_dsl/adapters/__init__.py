"""Layer 7, adapters (with zoo/): PettingZoo and Gymnasium views of the batched runtime, and the RL libraries' own.

factory.py (``parallel_env``, ``vector_env``), pettingzoo.py and gymnasium.py (ParallelEnv and VectorEnv),
flat.py and joint.py (flat and joint-action views), human.py (the window), registration.py (Gymnasium ids and
PettingZoo's module convention), sb3.py, torchrl.py and benchmarl.py. Imports: base, lang, sim, compiler,
runtime; an environment only through the registry.
"""


def module_doc(name: str) -> str:
    """The docstring of the adapter module ``name`` (``"sb3"``, ``"benchmarl"``...) without importing it, nor the
    library it needs (for the docs)."""
    import ast
    from pathlib import Path

    return ast.get_docstring(ast.parse((Path(__file__).parent / f"{name}.py").read_text())) or ""
