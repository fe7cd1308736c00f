"""Every public result is its own record: ``to_dict()`` and ``from_dict()`` from its fields.

A result class derives from :class:`Record`; the classes its fields hold (designs,
evaluations, solver answers) are registered with :func:`register_record`. Both are
written and read by one codec, from the dataclass fields and their type hints, so
no class keeps a hand-written JSON form that could drift from its fields:

- a registered object is ``{"type": class name, field: value, ...}`` (the fields
  its constructor takes, plus the cached figures a class lists in
  ``_record_derived``, which are saved so that a reloaded result computes nothing;
  a field marked :data:`NOT_SAVED`, such as a callable computing one of those
  figures, is left out and reloads as its default);
  a class with a checked form of its own (a case: the case file's tables, read
  back through the case-file checks) defines ``_record_save()`` and the class
  method ``_record_load(saved, where)`` instead (and ``_record_fields_saved()``, the
  names of the fields it saves and the schema of the others, where it saves fields:
  a study whose samples are drawn again on reading);
- a float that is NaN or infinite is ``{"float": "nan" | "inf" | "-inf"}`` (strict
  JSON has no such numbers), a numpy array ``{"dtype", "shape", "data"}``, a tuple
  a list;
- the top level adds ``"version"`` (:data:`RECORD_VERSION`).

Reading is strict, as reading a case file is: every field must be present and of
its declared type, no unknown field is accepted, the constructors check what they
check for a user's input, and the fields named in :data:`FIELD_RULES` (residual
errors, speeds, option, model) must lie in their ranges. A bad value raises
:class:`RecordError` naming the field's path, the value and what is allowed.
"""

from __future__ import annotations

import dataclasses
import functools
import json
import math
import types
import typing
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import Any, ClassVar, TypeVar

import numpy as np

from sso._files import read_input_bytes
from sso._kinematics.hooke import MODELS
from sso._limits import MAX_RESULT_FILE_BYTES
from sso._validation import shown

RECORD_VERSION = 1
"""Version of the saved form; :meth:`Record.from_dict` reads this version only."""

_REGISTERED: dict[str, type] = {}

Registered = TypeVar("Registered", bound=type)
R = TypeVar("R", bound="Record")
T = TypeVar("T")


def _non_negative(value: Any) -> bool:
    return isinstance(value, float) and math.isfinite(value) and value >= 0.0


def _positive(value: Any) -> bool:
    return isinstance(value, float) and math.isfinite(value) and value > 0.0


FieldRule = tuple[Callable[[Any], bool], str]
NON_NEGATIVE: FieldRule = (_non_negative, "a finite number >= 0")


class RecordError(ValueError):
    """A saved result that cannot be read back: the message names the field at fault."""


def register_record(cls: Registered) -> Registered:
    """Register a dataclass that results hold, so the codec can write and read it.

    Raises
    ------
    TypeError
        If ``cls`` is not a dataclass, or another class of that name is registered.
    """
    if not dataclasses.is_dataclass(cls):
        raise TypeError(f"{cls.__name__} is not a dataclass; only dataclasses are records")
    known = _REGISTERED.get(cls.__name__)
    if known is not None and known.__qualname__ + known.__module__ != (cls.__qualname__
                                                                         + cls.__module__):
        raise TypeError(f"two record classes are named {cls.__name__}: "
                        f"{known.__module__} and {cls.__module__}")
    _REGISTERED[cls.__name__] = cls
    return cls


def registered(name: str) -> type:
    """The registered class called ``name``.

    Raises
    ------
    RecordError
        If no record class has that name.
    """
    try:
        return record_classes()[name]
    except KeyError:
        raise RecordError(f"type = {shown(name)} is no sso result type") from None


def built(cls: type[T], **fields: Any) -> T:
    """An instance of the dataclass ``cls`` from ``fields``, made by its own constructor.

    Raises
    ------
    TypeError
        If a field is unknown, or one without a default is missing.
    """
    return cls(**fields)


def built_from(cls: type[T], fields: dict[str, Any]) -> T:
    """:func:`built` from the dict ``fields`` (a record's fields written as a dict display,
    as the result of a single solve is).

    Raises
    ------
    TypeError
        If a field is unknown, or one without a default is missing.
    """
    return cls(**fields)


def rebuilt(instance: T, **changes: Any) -> T:
    """The dataclass ``instance`` with ``changes``: :func:`dataclasses.replace`.

    Raises
    ------
    TypeError
        If a change names no field.
    """
    return dataclasses.replace(typing.cast(Any, instance), **changes)  # type: ignore[no-any-return]


class Record:
    """Base of every public result: ``to_dict``, ``from_dict`` and equality by content.

    Subclasses are dataclasses declared with ``eq=False`` (equality is the
    saved form's, so results holding arrays or NaN compare as their records do)
    and ``repr=False`` where they use :class:`sso._display.Readable`.
    """

    _record_derived: ClassVar[tuple[str, ...]] = ()
    """Cached properties saved with the record, so a reloaded result recomputes nothing."""
    _record_rules: ClassVar[dict[str, FieldRule]] = {}
    """Ranges of this class's fields beyond :data:`FIELD_RULES` (e.g. ``fun`` an RE)."""

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        # the class is not a dataclass yet; it is registered on first use
        _PENDING[cls.__name__] = cls

    def to_dict(self) -> dict[str, Any]:
        """The saved form: JSON-ready, with ``"type"`` and ``"version"``."""
        return {"version": RECORD_VERSION, **encode(self)}

    @classmethod
    def from_dict(cls: type[R], data: Any) -> R:
        """The result that :meth:`to_dict` saved, equal to the one saved.

        Raises
        ------
        RecordError
            If ``data`` is not a saved result of this class and version, or a field
            is missing, unknown, of the wrong type or out of range (the message
            names it).
        """
        if not isinstance(data, Mapping):
            raise RecordError(f"a saved result is a JSON object, not {type(data).__name__}")
        version = data.get("version")
        if type(version) is not int or version != RECORD_VERSION:
            raise RecordError(f"version = {shown(version)}; this sso reads version "
                              f"{RECORD_VERSION}")
        fields = {key: value for key, value in data.items() if key != "version"}
        result = decode(fields, cls, "")
        return typing.cast(R, result)

    def __eq__(self, other: object) -> bool:
        if type(other) is not type(self):
            return NotImplemented
        return self.to_dict() == other.to_dict()

    __hash__ = None  # type: ignore[assignment]


_PENDING: dict[str, type] = {}


def record_classes() -> dict[str, type]:
    """Every record class imported so far, by name."""
    for name, cls in list(_PENDING.items()):
        if dataclasses.is_dataclass(cls):
            register_record(cls)
            del _PENDING[name]
    return dict(_REGISTERED)


def read_json_object(path: str | Path) -> dict[str, Any]:
    """The JSON object in the file ``path`` (a saved result), read safely.

    Raises
    ------
    RecordError
        If the file is unreadable, not UTF-8 JSON, nested too deeply, holds a
        number that cannot be read, or is not a JSON object.
    """
    try:
        data = read_input_bytes(path, MAX_RESULT_FILE_BYTES)
    except ValueError as error:
        raise RecordError(f"{path}: cannot read the result file: {error}") from None
    try:
        saved = json.loads(data.decode("utf-8"))
    except (UnicodeDecodeError, json.JSONDecodeError) as error:
        raise RecordError(f"{path}: not a JSON result file: {error}") from None
    except ValueError as error:  # int() of a number with more than 4300 digits
        raise RecordError(f"{path}: a number cannot be read: {error}") from None
    except RecursionError:
        raise RecordError(f"{path}: arrays or objects are nested too deeply to read") from None
    if not isinstance(saved, dict):
        raise RecordError(f"{path}: not a saved result (a JSON object is expected)")
    return saved


def encode(value: Any) -> Any:
    """The JSON-ready form of ``value`` (see the module notes)."""
    if value is None or isinstance(value, (bool, str)):
        return value
    if isinstance(value, (int, np.integer)) and not isinstance(value, np.bool_):
        return int(value)
    if isinstance(value, np.bool_):
        return bool(value)
    if isinstance(value, (float, np.floating)):
        number = float(value)
        if math.isfinite(number):
            return number
        return {"float": "nan" if math.isnan(number) else "inf" if number > 0 else "-inf"}
    if isinstance(value, np.ndarray):
        return {"dtype": value.dtype.str, "shape": list(value.shape),
                "data": [encode(item) for item in value.ravel().tolist()]}
    if isinstance(value, (tuple, list)) or (isinstance(value, Sequence)
                                            and not isinstance(value, (str, bytes))):
        return [encode(item) for item in value]
    if isinstance(value, Mapping):
        return {str(key): encode(item) for key, item in value.items()}
    if isinstance(value, Path):
        return str(value)
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        cls = type(value)
        if record_classes().get(cls.__name__) is not cls:
            raise TypeError(f"{cls.__name__} is not a registered record class")
        saved: dict[str, Any] = {"type": cls.__name__}
        if hasattr(cls, "_record_save"):  # a class with a checked form of its own
            own: dict[str, Any] = getattr(value, "_record_save")()  # noqa: B009 - mypy
            return {**saved, **own}
        for field in _init_fields(cls):
            saved[field.name] = encode(getattr(value, field.name))
        for name in getattr(cls, "_record_derived", ()):
            saved[name] = encode(getattr(value, name))
        return saved
    raise TypeError(f"cannot save a {type(value).__name__} in a record")


def decode(value: Any, declared: Any, path: str) -> Any:
    """``value`` (JSON) read back as ``declared`` (a type hint), checked strictly.

    Raises
    ------
    RecordError
        Naming ``path`` (the field) when the value does not fit.
    """
    where = path or "result"
    if declared is Any or declared is object:
        return _decode_any(value)
    origin = typing.get_origin(declared)
    if origin in (typing.Union, types.UnionType):
        return _decode_union(value, typing.get_args(declared), path)
    if origin is typing.Literal:
        if value not in typing.get_args(declared):
            raise RecordError(f"{where} = {shown(value)}; allowed: "
                              f"{', '.join(map(repr, typing.get_args(declared)))}")
        return value
    if origin in (tuple, list, Sequence):
        if origin is Sequence:  # any sequence reads back as a tuple
            return tuple(_decode_sequence(value, declared, list, where))
        return _decode_sequence(value, declared, origin, where)
    if origin in (dict, Mapping) or declared is dict:
        return _decode_mapping(value, declared, where)
    if declared is float:
        return _decode_float(value, where)
    if declared is bool:
        if type(value) is not bool:
            raise RecordError(f"{where} = {shown(value)}; allowed: true or false")
        return value
    if declared is int:
        if type(value) is not int:
            raise RecordError(f"{where} = {shown(value)}; allowed: an integer")
        return value
    if declared is str:
        if type(value) is not str:
            raise RecordError(f"{where} = {shown(value)}; allowed: a string")
        return value
    if declared is type(None):
        if value is not None:
            raise RecordError(f"{where} = {shown(value)}; allowed: null")
        return None
    if declared is np.ndarray:
        return _decode_array(value, where)
    if declared is Path:
        if type(value) is not str:
            raise RecordError(f"{where} = {shown(value)}; allowed: a path (a string)")
        return Path(value)
    if isinstance(declared, type):
        return _decode_object(value, declared, path)
    raise TypeError(f"{where}: the codec cannot read the type {declared!r}")


def _decode_any(value: Any) -> Any:
    if isinstance(value, dict):
        if set(value) == {"float"} and value["float"] in _NON_FINITE:
            return _NON_FINITE[value["float"]]
        return {key: _decode_any(item) for key, item in value.items()}
    if isinstance(value, list):
        return [_decode_any(item) for item in value]
    return value


_NON_FINITE = {"nan": math.nan, "inf": math.inf, "-inf": -math.inf}


def _decode_union(value: Any, options: tuple[Any, ...], path: str) -> Any:
    if value is None and type(None) in options:
        return None
    chosen = [option for option in options if option is not type(None)]
    if len(chosen) == 1:
        return decode(value, chosen[0], path)
    errors = []
    for option in chosen:
        try:
            return decode(value, option, path)
        except RecordError as error:
            errors.append(str(error))
    raise RecordError("; or ".join(errors))


def _decode_sequence(value: Any, declared: Any, origin: Any, where: str) -> Any:
    if not isinstance(value, list):
        raise RecordError(f"{where} = {shown(value)}; allowed: a list")
    arguments = typing.get_args(declared)
    if origin is list or (len(arguments) == 2 and arguments[1] is Ellipsis):
        item_type = arguments[0] if arguments else Any
        items = [decode(item, item_type, f"{where}[{index}]") for index, item in enumerate(value)]
    else:
        if len(value) != len(arguments):
            raise RecordError(f"{where} has {len(value)} entries; allowed: {len(arguments)}")
        items = [decode(item, item_type, f"{where}[{index}]")
                 for index, (item, item_type) in enumerate(zip(value, arguments, strict=True))]
    return items if origin is list else tuple(items)


def _decode_mapping(value: Any, declared: Any, where: str) -> dict[Any, Any]:
    if not isinstance(value, dict):
        raise RecordError(f"{where} = {shown(value)}; allowed: an object")
    arguments = typing.get_args(declared) or (str, Any)
    key_type, item_type = arguments
    decoded = {}
    for key, item in value.items():
        if key_type is int:
            try:
                read_key: Any = int(key)
            except ValueError:
                raise RecordError(f"{where} has the key {shown(key)}; allowed: integers") from None
        else:
            read_key = key
        decoded[read_key] = decode(item, item_type, f"{where}.{key}")
    return decoded


def _decode_float(value: Any, where: str) -> float:
    if isinstance(value, dict) and set(value) == {"float"} and value["float"] in _NON_FINITE:
        return _NON_FINITE[value["float"]]
    if type(value) not in (int, float):
        raise RecordError(f"{where} = {shown(value)}; allowed: a number")
    try:
        return float(value)
    except OverflowError:
        raise RecordError(f"{where} = {shown(value)}; allowed: a number a float can hold") from None


def _decode_array(value: Any, where: str) -> np.ndarray:
    if not isinstance(value, dict) or set(value) != {"dtype", "shape", "data"}:
        raise RecordError(f"{where} = {shown(value)}; allowed: an array "
                          '{"dtype", "shape", "data"}')
    try:
        dtype = np.dtype(value["dtype"])
    except TypeError:
        raise RecordError(f"{where}.dtype = {shown(value['dtype'])} is no array type") from None
    if dtype.kind not in "biuf":
        raise RecordError(f"{where}.dtype = {shown(value['dtype'])}; allowed: booleans, "
                          "integers or floats")
    shape = decode(value["shape"], tuple[int, ...], f"{where}.shape")
    item_type = {"b": bool, "f": float}.get(dtype.kind, int)
    data = decode(value["data"], list[item_type], f"{where}.data")  # type: ignore[valid-type]
    if any(size < 0 for size in shape) or math.prod(shape) != len(data):
        raise RecordError(f"{where}: shape {list(shape)} does not hold {len(data)} values")
    try:
        return np.asarray(data, dtype=dtype).reshape(shape)
    except (OverflowError, ValueError):
        raise RecordError(f"{where}: a value does not fit the dtype {dtype.str}") from None


def _decode_object(value: Any, declared: type, path: str) -> Any:
    where = path or "result"
    if not isinstance(value, dict):
        raise RecordError(f"{where} = {shown(value)}; allowed: an object")
    name = value.get("type")
    cls = registered(name) if isinstance(name, str) else None
    if cls is None:
        raise RecordError(f"{where}.type = {shown(name)}; allowed: a result type's name")
    if not _is_protocol(declared) and not issubclass(cls, declared):
        raise RecordError(f"{where}.type = {shown(name)}; allowed: {declared.__name__}")
    if hasattr(cls, "_record_load"):
        try:
            return cls._record_load({key: item for key, item in value.items() if key != "type"},
                                    where)
        except (ValueError, TypeError, ArithmeticError, IndexError, KeyError,
                RecursionError) as error:
            raise RecordError(f"{where} ({cls.__name__}): {error}") from None
    hints = _hints(cls)
    fields = _init_fields(cls)
    derived = tuple(getattr(cls, "_record_derived", ()))
    check_field_names(cls, value, {field.name for field in fields} | set(derived) | {"type"},
                      path)
    arguments = {field.name: decode(value[field.name], hints[field.name],
                                    _join(path, field.name)) for field in fields}
    rules = {**FIELD_RULES, **getattr(cls, "_record_rules", {})}
    for field_name, field_value in arguments.items():
        check_field(_join(path, field_name), field_name, field_value, arguments, rules)
    try:
        made = cls(**arguments)
    except (ValueError, TypeError, ArithmeticError, IndexError, KeyError) as error:
        raise RecordError(f"{where} ({cls.__name__}): {error}") from None
    for name_derived in derived:
        cached = decode(value[name_derived], _derived_hint(cls, name_derived),
                        _join(path, name_derived))
        made.__dict__[name_derived] = cached
    return made


def check_field_names(cls: type, value: Mapping[str, Any], expected: set[str],
                      path: str) -> None:
    """Refuse a saved object of ``cls`` that lacks a name of ``expected`` or has another.

    Raises
    ------
    RecordError
        Naming the first unknown field (and the allowed ones), else the first missing.
    """
    unknown = sorted(set(value) - expected)
    if unknown:
        raise RecordError(f"{_join(path, unknown[0])} is not a field of {cls.__name__}; "
                          f"allowed: {', '.join(sorted(expected - {'type'}))}")
    missing = sorted(expected - set(value))
    if missing:
        raise RecordError(f"{_join(path, missing[0])} is missing (a field of {cls.__name__})")


def _join(path: str, name: str) -> str:
    return f"{path}.{name}" if path else name


def _is_protocol(declared: type) -> bool:
    return bool(getattr(declared, "_is_protocol", False))


NOT_SAVED = {"saved": False}
"""``dataclasses.field(metadata=NOT_SAVED)``: a field the record does not hold (a
callable that computes a derived figure); it must have a default, which a reloaded
result gets, and the figure it computes must be listed in ``_record_derived``."""


def _init_fields(cls: type) -> tuple[dataclasses.Field[Any], ...]:
    return tuple(field for field in dataclasses.fields(cls)
                 if field.init and field.metadata.get("saved", True))


@functools.cache
def _hints(cls: type) -> dict[str, Any]:
    return typing.get_type_hints(cls, localns=record_classes())


def _derived_hint(cls: type, name: str) -> Any:
    attribute = getattr(cls, name)
    function = getattr(attribute, "func", None) or getattr(attribute, "fget", None)
    return typing.get_type_hints(function, localns=record_classes())["return"]


FIELD_RULES: dict[str, FieldRule] = {
    "option": (lambda value: value in (1, 2, 3), "1, 2 or 3"),
    "model": (lambda value: value in MODELS, " or ".join(MODELS)),
    "input_speed_rpm": (_positive, "a finite number > 0"),
    "speed_min_rpm": NON_NEGATIVE,
    "speed_max_rpm": NON_NEGATIVE,
    "residual_error": NON_NEGATIVE,
    "fluctuation": NON_NEGATIVE,
    "fluctuation_rpm": NON_NEGATIVE,
    "minimum_residual_error": NON_NEGATIVE,
    
    "starts": (lambda value: value >= 1, "an integer >= 1"),
    "samples": (lambda value: value >= 0, "an integer >= 0"),
}
"""Ranges of the fields that every result reads the same way, by field name."""


def check_field(path: str, name: str, value: Any, fields: Mapping[str, Any],
                rules: Mapping[str, FieldRule] = FIELD_RULES) -> None:
    """Check one decoded field against its rule and the solver rule.

    A field's rule is the one ``rules`` names it by, else every field whose name
    ends in ``_re`` is a residual error (a finite number >= 0). The solver rule:
    an answer that says it succeeded has a finite objective.

    Raises
    ------
    RecordError
        Naming the field, its value and the allowed range.
    """
    rule = rules.get(name, NON_NEGATIVE if name.endswith("_re") else None)
    if rule is not None and not isinstance(value, (tuple, list, dict, np.ndarray)):
        accepts, allowed = rule
        if not accepts(value):
            raise RecordError(f"{path} = {shown(value)}; allowed: {allowed}")
    if (name == "fun" and fields.get("success") is True and isinstance(value, float)
            and not math.isfinite(value)):
        raise RecordError(f"{path} = {shown(value)} with success = true; allowed: a finite "
                          "number (a solver that succeeded has a finite objective)")


INTEGER_FIELDS = ("option", "starts", "samples")


def check_values(data: Any, path: str = "") -> None:
    """Check every field of an untyped saved tree (a column's result document) that
    :func:`check_field` has a rule for, wherever it is nested.

    JSON holds a non-finite number as null there: null is "not available", except
    as the ``fun`` of an answer that says it succeeded.

    Raises
    ------
    RecordError
        Naming the first field at fault, its value and the allowed range.
    """
    if isinstance(data, list):
        for index, item in enumerate(data):
            check_values(item, f"{path}[{index}]")
        return
    if not isinstance(data, dict):
        return
    for name, value in data.items():
        where = _join(path, str(name))
        if isinstance(value, (dict, list)):
            check_values(value, where)
            continue
        if name == "fun" and value is None and data.get("success") is True:
            raise RecordError(f"{where} = null with success = true; allowed: a finite number "
                              "(a solver that succeeded has a finite objective)")
        if value is None or isinstance(value, (bool, str)):
            continue
        if isinstance(value, int) and name not in INTEGER_FIELDS:
            value = _decode_float(value, where)
        check_field(where, str(name), value, data)


JsonSchema = dict[str, Any]
SCHEMA_DRAFT = "https://json-schema.org/draft/2020-12/schema"
_ARRAY_SCHEMA: JsonSchema = {
    "type": "object", "required": ["dtype", "shape", "data"], "additionalProperties": False,
    "description": "a numpy array: its dtype (numpy's name), its shape and its values in "
                   "C order",
    "properties": {"dtype": {"type": "string"},
                   "shape": {"type": "array", "items": {"type": "integer", "minimum": 0}},
                   "data": {"type": "array"}}}
_NON_FINITE_SCHEMA: JsonSchema = {
    "type": "object", "required": ["float"], "additionalProperties": False,
    "description": "a number that strict JSON cannot hold",
    "properties": {"float": {"enum": sorted(_NON_FINITE)}}}


def json_schema(results: tuple[type, ...]) -> JsonSchema:
    """The JSON Schema (draft 2020-12) of the saved form of ``results`` (record classes).

    Built from the same fields and type hints as the codec, so it cannot hold a
    second copy of them. ``type`` picks the class; :meth:`Record.from_dict` stays
    the primary check (it also checks ranges and each constructor's rules).
    """
    definitions: dict[str, JsonSchema] = {"array": _ARRAY_SCHEMA, "non_finite": _NON_FINITE_SCHEMA}
    pending = list(results)
    while pending:
        cls = pending.pop()
        if cls.__name__ in definitions:
            continue
        properties: dict[str, JsonSchema] = {"type": {"const": cls.__name__}}
        if hasattr(cls, "_record_fields_saved"):  # a form of its own, of named fields
            names, extra = cls._record_fields_saved()
            hints = _hints(cls)
            properties.update({name: _type_schema(hints[name], pending) for name in names})
            properties.update(extra)
            if cls in results:
                properties["version"] = {"const": RECORD_VERSION}
            definitions[cls.__name__] = {"type": "object", "additionalProperties": False,
                                         "required": ["type", *names, *extra],
                                         "properties": properties}
            continue
        if hasattr(cls, "_record_save"):
            definitions[cls.__name__] = {
                "type": "object", "required": ["type"], "properties": properties,
                "description": f"{cls.__name__} in a form of its own, checked on reading by "
                               "its own rules (a case: as a case file)"}
            continue
        if cls in results:
            properties["version"] = {"const": RECORD_VERSION}
        hints = _hints(cls)
        names = [field.name for field in _init_fields(cls)]
        for name in names:
            properties[name] = _type_schema(hints[name], pending)
        for name in getattr(cls, "_record_derived", ()):
            names.append(name)
            properties[name] = _type_schema(_derived_hint(cls, name), pending)
        definitions[cls.__name__] = {"type": "object", "required": ["type", *names],
                                     "additionalProperties": False, "properties": properties}
    names = sorted(cls.__name__ for cls in results)
    return {
        "$schema": SCHEMA_DRAFT,
        "title": "sso result (result.json)",
        "description": "A result saved by sso.write_report or the sso command; read it "
                       "back with the from_dict() of the class that 'type' names.",
        "type": "object",
        "required": ["version", "type"],
        "properties": {"version": {"const": RECORD_VERSION}, "type": {"enum": names}},
        "allOf": [{"if": {"properties": {"type": {"const": name}}},
                   "then": {"$ref": f"#/$defs/{name}"}} for name in names],
        "$defs": dict(sorted(definitions.items())),
    }


def _type_schema(declared: Any, pending: list[type]) -> JsonSchema:
    origin = typing.get_origin(declared)
    if declared is Any or declared is object:
        return {}
    if origin in (typing.Union, types.UnionType):
        return {"anyOf": [_type_schema(option, pending) for option in typing.get_args(declared)]}
    if origin in (tuple, list, Sequence):
        arguments = typing.get_args(declared)
        if origin is not tuple or (len(arguments) == 2 and arguments[1] is Ellipsis):
            return {"type": "array", "items": _type_schema(arguments[0] if arguments else Any,
                                                           pending)}
        items = [_type_schema(argument, pending) for argument in arguments]
        unique = [item for index, item in enumerate(items) if item not in items[:index]]
        return {"type": "array", "minItems": len(items), "maxItems": len(items),
                "items": unique[0] if len(unique) == 1 else {"anyOf": unique}}
    if origin in (dict, Mapping) or declared is dict:
        arguments = typing.get_args(declared) or (str, Any)
        return {"type": "object", "additionalProperties": _type_schema(arguments[1], pending)}
    number = {"anyOf": [{"type": "number"}, {"$ref": "#/$defs/non_finite"}]}
    simple: dict[Any, JsonSchema] = {
        float: number, int: {"type": "integer"}, bool: {"type": "boolean"},
        str: {"type": "string"}, type(None): {"type": "null"}, Path: {"type": "string"},
        np.ndarray: {"$ref": "#/$defs/array"}}
    if declared in simple:
        return dict(simple[declared])
    if isinstance(declared, type) and _is_protocol(declared):
        return {"type": "object", "required": ["type"],
                "description": f"any result part that is a {declared.__name__}"}
    if isinstance(declared, type) and dataclasses.is_dataclass(declared):
        pending.append(declared)
        return {"$ref": f"#/$defs/{declared.__name__}"}
    raise TypeError(f"no JSON Schema for the type {declared!r}")
