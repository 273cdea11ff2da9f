"""``hivex_dsl.testing``, the public path of :mod:`hivex_dsl.evaluation.testing`: hypothesis strategies for
property-testing reward terms (needs ``hypothesis``: ``pip install "hivex-dsl[testing]"``).

    from hivex_dsl.testing import term_inputs
"""

from __future__ import annotations

from .evaluation.testing import TermInputs, actions, compiled_scenarios, scenarios, term_inputs

__all__ = ["TermInputs", "actions", "compiled_scenarios", "scenarios", "term_inputs"]
