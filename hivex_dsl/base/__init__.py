"""Layer 1, base: what every layer may use, and which imports no other layer.

errors.py (the exceptions, located problems and their wording), numeric.py (float64 operands as 0-d
arrays for the hot paths) and resources.py (where the bundled scenarios/, rewards/ and generators/ live).
Imports: the standard library and NumPy only.
"""
