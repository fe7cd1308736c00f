"""The module paths of v0.1 still import for one release, with a DeprecationWarning."""

import importlib
import sys

import pytest

import sso
from sso._moved import MOVED


def _fresh_import(name):
    for loaded in [key for key in sys.modules if key == name or key.startswith(name + ".")]:
        del sys.modules[loaded]
    return importlib.import_module(name)


@pytest.mark.parametrize("old, new", [(old, new) for old, new in MOVED.items() if new])
def test_an_old_path_warns_and_hands_on_the_same_objects(old, new):
    with pytest.warns(DeprecationWarning, match=f"{old} is deprecated.*import from {new}"):
        module = _fresh_import(old)
    target = importlib.import_module(new)
    name = next(name for name in dir(target) if not name.startswith("_"))
    assert getattr(module, name) is getattr(target, name)


def test_the_readme_import_of_v01_still_gives_the_same_classes():
    sys.modules.pop("sso.mechanisms", None)
    with pytest.warns(DeprecationWarning, match="sso.mechanisms is deprecated") as caught:
        from sso.mechanisms import FourBar, slider_crank_method_difference
    assert caught[0].filename == __file__  # blames the import line, not importlib
    assert FourBar is sso.FourBar
    assert slider_crank_method_difference is sso.slider_crank_method_difference


def test_an_unknown_name_of_an_old_path_is_still_an_error():
    with pytest.warns(DeprecationWarning):
        module = _fresh_import("sso.series")
    with pytest.raises(AttributeError):
        module.NoSuchName  # noqa: B018


def test_the_old_tolerance_module_hands_on_the_renamed_study():
    with pytest.warns(DeprecationWarning, match="sso.batch.tolerance is deprecated"):
        module = _fresh_import("sso.batch.tolerance")
    assert module.tolerance is sso.tolerance_study
    assert sso.tolerance is sso.tolerance_study


def test_the_old_case_module_still_hands_on_the_shaft_series_case():
    from sso.cases.shaft_series import Case

    with pytest.warns(DeprecationWarning, match="sso.io.case is deprecated"):
        module = _fresh_import("sso.io.case")
    assert module.Case is Case
    assert module.load_case is importlib.import_module("sso.cases.schema").load_case
