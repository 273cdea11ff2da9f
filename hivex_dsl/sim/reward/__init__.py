"""Reward terms with contracts, and the weighted composer shared by every environment."""

from .composer import RewardComposer
from .terms import RewardTerm, TermContract, TermRegistry

__all__ = ["RewardComposer", "RewardTerm", "TermContract", "TermRegistry"]
