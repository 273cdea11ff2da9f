"""The original HIVEX release's own records read as data."""
