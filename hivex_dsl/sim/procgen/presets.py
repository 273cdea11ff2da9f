"""Generator presets: data-only YAML under generators/, validated into pydantic specs."""

from __future__ import annotations

from typing import TypeVar

from pydantic import BaseModel

from ...base.resources import data_dir
from ...lang.loader import load_file
from ...lang.spec.validate import validate_loaded

M = TypeVar("M", bound=BaseModel)


def load_preset(file_name: str, model: type[M]) -> M:
    """generators/<file_name> validated as ``model``; problems are located ScenarioErrors."""
    return validate_loaded(model, load_file(data_dir("generators") / file_name))
