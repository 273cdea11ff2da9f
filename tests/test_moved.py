"""Old module paths (hivex_dsl._moved's one table): the same module object, a warning that names the new path,
no warning for the paths kept public, and ModuleNotFoundError for names that never existed."""

from __future__ import annotations

import importlib
import pkgutil
import sys
import warnings

import pytest

import hivex_dsl
from hivex_dsl import _moved

OLD = sorted(_moved.MOVED)


def _import_fresh(name: str, monkeypatch) -> tuple[object, list[str]]:
    """``import name`` as a first import would run it, with the DeprecationWarnings it gives."""
    monkeypatch.delitem(sys.modules, name, raising=False)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        module = importlib.import_module(name)
    return module, [str(w.message) for w in caught if issubclass(w.category, DeprecationWarning)]


@pytest.mark.parametrize("old", OLD)
def test_an_old_path_is_the_moved_module_itself(old, monkeypatch):
    new = f"hivex_dsl.{_moved.MOVED[old]}"
    module, _ = _import_fresh(f"hivex_dsl.{old}", monkeypatch)
    assert module is importlib.import_module(new)
    assert module.__name__ == module.__spec__.name == new  # the module keeps its own name and spec


@pytest.mark.parametrize("old", OLD)
def test_an_old_path_warns_naming_the_new_one_unless_it_stays_public(old, monkeypatch):
    new = f"hivex_dsl.{_moved.MOVED[old]}"
    _, messages = _import_fresh(f"hivex_dsl.{old}", monkeypatch)
    if old in _moved.PUBLIC:
        assert messages == []
    else:
        assert messages == [f"hivex_dsl.{old} moved to {new}; import it from there"]


def test_the_warning_points_at_the_importing_line(monkeypatch):
    old = next(name for name in OLD if name not in _moved.PUBLIC)
    monkeypatch.delitem(sys.modules, f"hivex_dsl.{old}", raising=False)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        importlib.import_module(f"hivex_dsl.{old}")
    assert [w.filename for w in caught if issubclass(w.category, DeprecationWarning)] == [__file__]


def test_a_submodule_of_a_moved_package_is_aliased_too(monkeypatch):
    packages = [old for old in OLD if hasattr(importlib.import_module(f"hivex_dsl.{_moved.MOVED[old]}"), "__path__")]
    for old in packages:
        new = importlib.import_module(f"hivex_dsl.{_moved.MOVED[old]}")
        child = min(info.name for info in pkgutil.iter_modules(new.__path__))
        module, messages = _import_fresh(f"hivex_dsl.{old}.{child}", monkeypatch)
        assert module is importlib.import_module(f"{new.__name__}.{child}")
        if old not in _moved.PUBLIC:
            assert messages[-1] == f"hivex_dsl.{old}.{child} moved to {new.__name__}.{child}; import it from there"


def test_an_old_top_level_path_is_an_attribute_of_the_package():
    for old in OLD:
        if "." not in old:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", DeprecationWarning)
                assert getattr(hivex_dsl, old) is importlib.import_module(f"hivex_dsl.{_moved.MOVED[old]}")


@pytest.mark.parametrize("name", ["hivex_dsl.no_such_module", *(f"hivex_dsl.{old}.no_such_module" for old in OLD)])
def test_an_unknown_name_is_still_not_found(name):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)
        with pytest.raises(ModuleNotFoundError) as caught:
            importlib.import_module(name)
    assert caught.value.name in (name, name.rsplit(".", 1)[0])  # the old name, or its module that is no package


def test_an_unknown_attribute_of_the_package_is_still_an_attribute_error():
    with pytest.raises(AttributeError, match="no_such_name"):
        hivex_dsl.no_such_name  # noqa: B018
