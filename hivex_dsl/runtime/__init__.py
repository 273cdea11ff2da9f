"""Layer 5, runtime: a compiled scenario run as a batch of worlds.

batched.py (BatchedEnv: reset, step, endings, statistics and the reward composer over B worlds x N agents),
seeding.py (the seed streams of the train/test split) and global_state.py (the centralised critic's state
of each world). Imports: base, lang, sim, compiler.
"""

from .batched import BatchedEnv, Simulator, Split, StepOutcome, Transition

__all__ = ["BatchedEnv", "Simulator", "Split", "StepOutcome", "Transition"]
