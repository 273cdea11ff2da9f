"""Pydantic models of the scenario language (no NumPy here)."""
