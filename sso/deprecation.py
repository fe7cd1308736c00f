"""Renamed public keywords keep working for one release, with a DeprecationWarning."""

from __future__ import annotations

import functools
import warnings
from collections.abc import Callable
from typing import Any, TypeVar

from sso.warning_origin import user_stacklevel

Function = TypeVar("Function", bound=Callable[..., Any])


def renamed_keywords(**new_by_old: str) -> Callable[[Function], Function]:
    """Accept each old keyword as its new name, warning once per call.

    Parameters
    ----------
    **new_by_old : str
        ``old_name="new_name"`` for each renamed keyword.

    Raises
    ------
    TypeError
        At call time, when both the old and the new name are given.
    """

    def decorate(function: Function) -> Function:
        @functools.wraps(function)
        def wrapper(*args: Any, **kwargs: Any) -> Any:
            for old, new in new_by_old.items():
                if old in kwargs:
                    if new in kwargs:
                        raise TypeError(f"{function.__name__}() got both {old}= and {new}=; "
                                        f"give only {new}= ({old}= is its deprecated name)")
                    warnings.warn(f"{function.__name__}({old}=...) is deprecated and will be "
                                  f"removed in the next release; use {new}=",
                                  DeprecationWarning, stacklevel=user_stacklevel())
                    kwargs[new] = kwargs.pop(old)
            return function(*args, **kwargs)

        return wrapper  # type: ignore[return-value]

    return decorate
