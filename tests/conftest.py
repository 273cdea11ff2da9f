"""Shared fixtures; hypothesis runs derandomized in CI so a red build is reproducible."""

from __future__ import annotations

import os

import pytest
from hypothesis import settings

settings.register_profile("ci", derandomize=True, deadline=None, print_blob=True)
settings.register_profile("dev", deadline=None)
settings.load_profile("ci" if os.environ.get("CI") else "dev")


@pytest.fixture
def wfc_dict():
    """A minimal valid Wind Farm Control scenario as a plain dict."""
    return {"hivex": 1, "environment": "wind_farm_control"}
