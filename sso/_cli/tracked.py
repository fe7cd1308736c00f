"""Find which field of a malformed result document a renderer tripped over.

A ``result.json`` that sso wrote renders; one edited by hand may hold a string
where a number belongs, a list where a table belongs, and so on. Rather than a
second schema of every field the reports read, the failed rendering is repeated
on a copy that records each field read, and the last one read is named.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from typing import Any

RENDERING_ERRORS = (KeyError, TypeError, ValueError, AttributeError, IndexError,
                    ArithmeticError, RecursionError)
"""What a renderer raises on a document of the wrong shape."""


class _Log:
    last = ""


class _TrackedDict(dict[Any, Any]):
    def __init__(self, data: Any = (), path: str = "", log: _Log | None = None) -> None:
        super().__init__(data)
        self._path = path
        self._log = log or _Log()

    def _wrap(self, key: Any, value: Any) -> Any:
        path = f"{self._path}.{key}" if self._path else str(key)
        self._log.last = path
        return _tracked(value, path, self._log)

    def __getitem__(self, key: Any) -> Any:
        self._log.last = f"{self._path}.{key}" if self._path else str(key)
        return self._wrap(key, super().__getitem__(key))

    def get(self, key: Any, default: Any = None) -> Any:
        try:
            return self[key]
        except KeyError:
            return default

    def items(self) -> Any:
        return [(key, self._wrap(key, value)) for key, value in super().items()]

    def values(self) -> Any:
        return [self._wrap(key, value) for key, value in super().items()]


class _TrackedList(list[Any]):
    def __init__(self, data: Any = (), path: str = "", log: _Log | None = None) -> None:
        super().__init__(data)
        self._path = path
        self._log = log or _Log()

    def __getitem__(self, index: Any) -> Any:
        value = super().__getitem__(index)
        if isinstance(index, slice):
            return value
        self._log.last = f"{self._path}[{index}]"
        return _tracked(value, self._log.last, self._log)

    def __iter__(self) -> Iterator[Any]:
        for index, value in enumerate(super().__iter__()):
            self._log.last = f"{self._path}[{index}]"
            yield _tracked(value, self._log.last, self._log)


def _tracked(value: Any, path: str, log: _Log) -> Any:
    if isinstance(value, dict):
        return _TrackedDict(value, path, log)
    if isinstance(value, list):
        return _TrackedList(value, path, log)
    return value


def field_at_fault(render: Callable[[Any], Any], document: dict[str, Any]) -> str | None:
    """The field read last when ``render(document)`` fails, or None if it does not fail
    again on the recording copy (or fails elsewhere)."""
    log = _Log()
    try:
        render(_TrackedDict(document, "", log))
    except RENDERING_ERRORS:
        return log.last or None
    return None
