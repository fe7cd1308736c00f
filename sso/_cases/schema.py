"""Case files: one TOML file describes one design problem.

A case file is data only (``tomllib``; nothing in it is executed). Reading one
checks every key against the schema of its ``kind``:

* a TOML syntax error names the line;
* an unknown key or table is refused with the nearest valid key suggested;
* a wrong type or an out-of-range value names the key, the value and the allowed
  range (and the line where the key sits).

Adding a kind
-------------
The schema is a table of :class:`Key` entries per kind, registered with a function
that builds the kind's case object from the checked values. A new kind (a planar
mechanism, say) registers its own keys and builder with :func:`register_case_kind`
when its module is imported, and a shipped kind names that module in
:data:`KIND_MODULES` (a case file imports its own kind's module only); a new table
shared by every kind (a sweep, say) adds its keys to :data:`COMMON_KEYS`.
"""

from __future__ import annotations

import difflib
import re
import tomllib
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field, replace
from importlib import import_module
from pathlib import Path
from typing import Any

from sso._cases.units import (
    CONFIRM_LABEL,
    UNITS_TABLE,
    check_confirmed,
    confirmed_labels,
    unit_warnings,
)
from sso._files import read_input_bytes
from sso._limits import INPUT_MAGNITUDE_RANGE, MAX_JOINTS, OUTPUT_FORMATS
from sso._validation import finite_float, per_item_bounds, shown

DEFAULT_KIND = "shaft_series"
NAME_PATTERN = re.compile(r"[A-Za-z0-9][A-Za-z0-9._-]{0,99}")

MAX_TEXT_LENGTH = 10_000


class CaseError(ValueError):
    """A case file cannot be read or breaks the schema.

    Attributes
    ----------
    path : str
        The case file.
    line : int or None
        Line of the offending key, when it could be found.
    reason : str
        What is wrong, naming the key, the value and the allowed range.
    """

    def __init__(self, path: str, reason: str, line: int | None = None) -> None:
        self.path = path
        self.line = line
        self.reason = reason
        where = f"{path}, line {line}" if line is not None else path
        super().__init__(f"{where}: {reason}")


@dataclass(frozen=True)
class Key:
    """One key of the case-file schema.

    Attributes
    ----------
    table : str
        TOML table holding the key (``""`` for the top level).
    name : str
        Key name inside the table.
    parse : callable
        ``parse(label, value)`` returns the checked value or raises ValueError
        naming ``label``, the value and the allowed range.
    default : any
        Value when the key is absent; :data:`REQUIRED` if it must be given, or a
        callable ``default(values, path)`` for defaults that depend on other keys.
    unit : str
        Unit of the value (``""`` if none).
    allowed : str
        Allowed values in words, for errors and the README.
    """

    table: str
    name: str
    parse: Callable[[str, Any], Any]
    default: Any
    unit: str
    allowed: str

    @property
    def label(self) -> str:
        """Dotted name as a user writes it: ``solver.starts``."""
        return f"{self.table}.{self.name}" if self.table else self.name


REQUIRED = object()

# One ``(lower, upper)`` pair for every item, or one pair per item.
Bounds = tuple[float, float] | tuple[tuple[float, float], ...]


@dataclass(frozen=True)
class CaseKind:
    """Schema and builder of one ``kind`` of case.

    Attributes
    ----------
    keys : tuple of Key
        The kind's own keys (the common keys are added to every kind).
    optional_tables : frozenset of str
        Tables that may be left out even though they hold required keys.
    build : callable
        ``build(values, path)`` checks the keys against each other and returns the
        case object from the checked values keyed by dotted label; it raises
        ValueError naming the keys.
    """

    keys: tuple[Key, ...]
    optional_tables: frozenset[str]
    build: Callable[[dict[str, Any], str], Any]


# ---------------------------------------------------------------- value parsers

def _describe_range(lower: float, upper: float, lower_open: bool = False,
                    upper_open: bool = False, unit: str = "") -> str:
    left = "(" if lower_open else "["
    right = ")" if upper_open else "]"
    text = f"{left}{lower:g}, {upper:g}{right}"
    return f"{text} {unit}" if unit else text


def number(lower: float, upper: float, unit: str = "", lower_open: bool = False,
           upper_open: bool = False) -> Callable[[str, Any], float]:
    """Parser of one real number inside an interval.

    Whatever the interval, the number must be 0 or have a magnitude inside
    :data:`sso._limits.INPUT_MAGNITUDE_RANGE`, so that squares, products and
    ratios computed from it cannot overflow.
    """
    allowed = _describe_range(lower, upper, lower_open, upper_open, unit)
    smallest, largest = INPUT_MAGNITUDE_RANGE

    def parse(label: str, value: Any) -> float:
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise ValueError(f"{label} = {shown(value)} must be a number in {allowed}")
        result = finite_float(label, value)
        too_low = result <= lower if lower_open else result < lower
        too_high = result >= upper if upper_open else result > upper
        if too_low or too_high:
            raise ValueError(f"{label} = {result:g} is outside the allowed range {allowed}")
        if result != 0.0 and not smallest <= abs(result) <= largest:
            raise ValueError(f"{label} = {result:g} is outside the allowed range {allowed}: "
                             f"a number must be 0 or of magnitude {smallest:g} to {largest:g}")
        return result

    return parse


def whole_number(lower: int, upper: int) -> Callable[[str, Any], int]:
    """Parser of one integer inside ``[lower, upper]``."""

    def parse(label: str, value: Any) -> int:
        if isinstance(value, bool) or not isinstance(value, int):
            raise ValueError(f"{label} = {shown(value)} must be a whole number in "
                             f"[{lower}, {upper}]")
        if not lower <= value <= upper:
            raise ValueError(f"{label} = {value} is outside the allowed range [{lower}, {upper}]")
        return value

    return parse


def choice(allowed: tuple[str, ...]) -> Callable[[str, Any], str]:
    """Parser of one string out of ``allowed``."""

    def parse(label: str, value: Any) -> str:
        if value not in allowed:
            raise ValueError(f"{label} = {shown(value)} is not one of {_quoted(allowed)}")
        return str(value)

    return parse


def text(max_length: int = MAX_TEXT_LENGTH) -> Callable[[str, Any], str]:
    """Parser of free text (stored as given; escaped wherever it is rendered)."""

    def parse(label: str, value: Any) -> str:
        if not isinstance(value, str):
            raise ValueError(f"{label} = {shown(value)} must be a string of at most {max_length} "
                             "characters")
        if len(value) > max_length:
            raise ValueError(f"{label} has {len(value)} characters; at most {max_length} are "
                             "allowed")
        return value

    return parse


def choice_list(allowed: tuple[str, ...]) -> Callable[[str, Any], tuple[str, ...]]:
    """Parser of a non-empty list of distinct strings out of ``allowed``."""

    def parse(label: str, value: Any) -> tuple[str, ...]:
        if not isinstance(value, list) or not value:
            raise ValueError(f"{label} = {shown(value)} must be a non-empty list of "
                             f"{_quoted(allowed)}")
        for index, item in enumerate(value):
            if item not in allowed:
                raise ValueError(f"{label}[{index}] = {shown(item)} is not one of "
                                 f"{_quoted(allowed)}")
        if len(set(value)) != len(value):
            raise ValueError(f"{label} = {shown(value)} names an entry twice")
        return tuple(value)

    return parse


def number_list(lower: float, upper: float, unit: str, upper_open: bool = False,
                max_length: int = MAX_JOINTS,
                min_length: int = 1) -> Callable[[str, Any], tuple[float, ...]]:
    """Parser of a list of ``min_length..max_length`` numbers, each inside an interval."""
    item = number(lower, upper, unit, upper_open=upper_open)

    def parse(label: str, value: Any) -> tuple[float, ...]:
        if not isinstance(value, list) or not min_length <= len(value) <= max_length:
            raise ValueError(f"{label} = {shown(value)} must be a list of {min_length} to "
                             f"{max_length} numbers, "
                             f"each in {_describe_range(lower, upper, False, upper_open, unit)}")
        return tuple(item(f"{label}[{index}]", entry) for index, entry in enumerate(value))

    return parse


def bounds_list(lower: float, upper: float, unit: str,
                upper_open: bool = False) -> Callable[[str, Any], Bounds]:
    """Parser of one ``[lower, upper]`` pair or a list of pairs (one per item)."""
    allowed = _describe_range(lower, upper, False, upper_open, unit)

    def parse(label: str, value: Any) -> Bounds:
        if _is_pair(value):
            return per_item_bounds(label, value, 1, lower, upper, unit, upper_open)[0]
        if isinstance(value, list) and value and all(_is_pair(pair) for pair in value):
            return per_item_bounds(label, value, len(value), lower, upper, unit, upper_open)
        raise ValueError(f"{label} = {shown(value)} must be one [lower, upper] pair or a list of "
                         f"pairs, each bound in {allowed}")

    return parse


def case_name(label: str, value: Any) -> str:
    """Parser of a case name: it names the report folder, so it must be a safe file name."""
    if not isinstance(value, str) or not NAME_PATTERN.fullmatch(value):
        raise ValueError(
            f"{label} = {shown(value)} must be 1 to 100 letters, digits, '.', '_' or '-', "
            "starting with a letter or digit (it names the report folder)"
        )
    return value


def _name_from_file(path: str) -> str:
    """The default case name, the file's stem, checked like a given name."""
    stem = Path(path).stem
    try:
        return case_name("name", stem)
    except ValueError as error:
        raise ValueError(f"{error}; the name comes from the file name: rename the file or "
                         "give name = \"...\"") from None


def _is_pair(value: Any) -> bool:
    return (isinstance(value, list) and len(value) == 2
            and all(isinstance(item, (int, float)) and not isinstance(item, bool)
                    for item in value))


def _quoted(items: tuple[str, ...]) -> str:
    return ", ".join(repr(item) for item in items)


# ---------------------------------------------------------------- the schema

COMMON_KEYS: tuple[Key, ...] = (
    Key("", "kind", lambda label, value: value, DEFAULT_KIND, "",
        "a registered kind: 'shaft_series', 'fourbar', 'slider_crank', 'quick_return', "
        "'fourbar_design', 'column', 'driveline'"),
    Key("", "name", case_name, lambda values, path: _name_from_file(path), "",
        "1-100 of A-Z a-z 0-9 . _ -, starting with a letter or digit"),
    Key("", "description", text(), "", "", "free text"),
    Key("output", "formats", choice_list(OUTPUT_FORMATS), OUTPUT_FORMATS, "",
        "non-empty list of 'json', 'csv', 'md', 'html', 'png'"),
    Key(UNITS_TABLE, "confirm", confirmed_labels, (), "",
        "list of dotted keys whose values are meant as given, though they look like another "
        "unit (silences that key's unit warning)"),
)


# Kind -> its keys and builder; each kind's module registers itself when imported
# (:mod:`sso._cases.shaft_series`, :mod:`sso._cases.column`, :mod:`sso._cases.mechanism`).
_REGISTERED: dict[str, CaseKind] = {}

# The module that registers each shipped kind, in the order kinds are listed. A case
# file's kind imports its own module only: a shaft-series run does not load the
# column's geometry, tolerances and spline modules, nor the linkages.
KIND_MODULES: dict[str, str] = {
    "shaft_series": "sso._cases.shaft_series",
    "column": "sso._cases.column",
    "driveline": "sso._cases.driveline",
    **{kind: "sso._cases.mechanism"
       for kind in ("fourbar", "slider_crank", "quick_return", "fourbar_design")},
}


def case_document(case: Any, keys: tuple[Key, ...]) -> dict[str, Any]:
    """A case of a kind that keeps its values by dotted label, in the case-file layout.

    ``case`` has ``kind``, ``name``, ``description``, ``formats`` and ``values``; the
    tables follow the order of ``keys`` whatever the file's (a case read back saves the
    same), tuples become lists and values of ``None`` are left out.
    """
    document: dict[str, Any] = {"kind": case.kind, "name": case.name,
                                "description": case.description,
                                "output": {"formats": list(case.formats)}}
    order = {key.label: index for index, key in enumerate(keys)}
    for label, value in sorted(case.values.items(),
                               key=lambda item: order.get(item[0], len(order))):
        if value is None:
            continue
        table, name = label.split(".", 1)
        document.setdefault(table, {})[name] = _plain_value(value)
    return document


def _plain_value(value: Any) -> Any:
    if isinstance(value, dict):
        return {name: _plain_value(item) for name, item in value.items()}
    return [_plain_value(item) for item in value] if isinstance(value, tuple) else value


def register_case_kind(kind: str, keys: tuple[Key, ...],
                       build: Callable[[dict[str, Any], str], Any],
                       optional_tables: frozenset[str] = frozenset()) -> None:
    """Register a new kind of case: its own keys and the builder of its case object.

    Raises
    ------
    ValueError
        If the kind is already registered or a key repeats a common key.
    """
    if kind in _REGISTERED:
        raise ValueError(f"case kind {shown(kind)} is already registered")
    common = {key.label for key in COMMON_KEYS}
    clashes = [key.label for key in keys if key.label in common]
    if clashes:
        raise ValueError(f"keys {clashes} of kind {shown(kind)} repeat common keys")
    _REGISTERED[kind] = CaseKind(tuple(keys), frozenset(optional_tables), build)


def case_kind(kind: str) -> CaseKind | None:
    """The kind called ``kind``, importing the module that registers it (only that one
    for a shipped kind, every kind module otherwise); None if no kind has that name."""
    if kind not in _REGISTERED:
        if kind in KIND_MODULES:
            import_module(KIND_MODULES[kind])
        else:
            case_kinds()
    return _REGISTERED.get(kind)


def case_kinds() -> dict[str, CaseKind]:
    """Every registered kind, the shipped ones first in the order of
    :data:`KIND_MODULES` (whatever order their modules were imported in)."""
    for module in dict.fromkeys(KIND_MODULES.values()):
        import_module(module)
    order = list(KIND_MODULES)
    return {kind: _REGISTERED[kind] for kind in sorted(
        _REGISTERED, key=lambda kind: order.index(kind) if kind in order else len(order))}


def schema(kind: str = DEFAULT_KIND) -> tuple[Key, ...]:
    """Every key a case of ``kind`` accepts (common keys first).

    Raises
    ------
    KeyError
        If no kind is called ``kind``.
    """
    found = case_kind(kind)
    if found is None:
        raise KeyError(kind)
    return COMMON_KEYS + found.keys


# ---------------------------------------------------------------- reading

class SavedCase:
    """How a checked case is saved in a result and read back: as its case file is.

    A result holds its case as the case-file tables (``to_dict()``) and where it
    came from; reading it back runs every check of a case file, so a saved result
    can hold no value a case file could not.
    """

    source: str

    def to_dict(self) -> dict[str, Any]:
        raise NotImplementedError

    def _record_save(self) -> dict[str, Any]:
        """The saved form: the case-file tables and where they came from."""
        return {"case": self.to_dict(), "source": self.source}

    @classmethod
    def _record_load(cls, saved: Mapping[str, Any], where: str) -> Any:
        """A saved case read back through every check of a case file.

        Raises
        ------
        ValueError
            Naming the key at fault, as for a case file, or the kind if it is not
            this class's.
        """
        if set(saved) != {"case", "source"} or not isinstance(saved["case"], dict) \
                or not isinstance(saved["source"], str):
            raise ValueError('a saved case is {"case": {tables of a case file}, "source": '
                             f'"where it came from"}}, not {shown(saved)}')
        case = parse_case(saved["case"], saved["source"])
        if not isinstance(case, cls):
            raise ValueError(f"kind = {case.kind!r} is not the kind of case this result holds")
        return case



@dataclass(frozen=True)
class TabledCase(SavedCase):
    """A case held as its checked values keyed by dotted label (a column, a planar
    mechanism, a driveline), after defaults.

    Attributes
    ----------
    kind : str
        The case's kind (``"column"``, ``"driveline"``, a mechanism's).
    name : str
        Case name; the report goes to ``<out>/<name>/``.
    description : str
        Free text (escaped wherever it is rendered).
    values : dict
        Every checked value keyed by its dotted label (``"excitation.rpm"``); tables
        left out have no entries.
    formats : tuple of str
        Report files to write.
    source : str
        Path of the case file.
    warnings : tuple of str
        Warnings found while checking the case.
    """

    kind: str
    name: str
    description: str
    values: dict[str, Any]
    formats: tuple[str, ...]
    source: str
    warnings: tuple[str, ...] = field(default=(), compare=False)

def load_case(path: str | Path) -> Any:
    """Read and check one case file.

    Parameters
    ----------
    path : str or pathlib.Path
        The TOML file.

    Returns
    -------
    Case
        Every default filled in; warnings about the design in ``Case.warnings``.

    Raises
    ------
    CaseError
        If the file cannot be read, is not valid TOML, or breaks the schema; the
        message names the file, the line where known, the key, the value and the
        allowed range.
    """
    path_text = str(path)
    try:
        source = read_input_bytes(path).decode("utf-8")
    except ValueError as error:  # UnicodeDecodeError is one too
        reason = (f"not a UTF-8 text file (byte {error.start})"
                  if isinstance(error, UnicodeDecodeError)
                  else f"cannot read the case file: {error}")
        raise CaseError(path_text, reason) from None
    return parse_case(parse_toml(source, path_text, CaseError), path_text, source)


def parse_toml(source: str, path: str, error_type: Callable[..., Exception]) -> dict[str, Any]:
    """Parse TOML text, raising ``error_type(path, reason, line)`` for anything tomllib
    refuses or cannot handle (syntax, integers of more than 4300 digits, nesting too
    deep for the parser)."""
    try:
        return tomllib.loads(source)
    except tomllib.TOMLDecodeError as error:
        raise error_type(path, f"TOML syntax error: {error}",
                         _line_of_decode_error(error, source)) from None
    except ValueError as error:  # int() of a number with more than 4300 digits
        raise error_type(path, f"a number cannot be read: {error}", None) from None
    except RecursionError:
        raise error_type(path, "arrays or tables are nested too deeply to read", None) from None


def parse_case(document: Mapping[str, Any], path: str = "<case>", source: str = "") -> Any:
    """Check a case given as a dictionary (a parsed file, or ``Case.to_dict()``).

    Parameters
    ----------
    document : mapping
        Tables and keys as in a case file.
    path : str
        Where the case came from (for messages and the default name).
    source : str
        The file's text, used to find the line of an offending key.

    Returns
    -------
    Case

    Raises
    ------
    CaseError
        If a key is unknown, has the wrong type or lies out of range.
    """
    kind_value = document.get("kind", DEFAULT_KIND)
    found = case_kind(kind_value) if isinstance(kind_value, str) else None
    if found is None:
        raise CaseError(path, f"kind = {shown(kind_value)} is not one of "
                        f"{_quoted(tuple(case_kinds()))}",
                        _line_of_key(source, "", "kind"))
    keys = COMMON_KEYS + found.keys
    _refuse_unknown_keys(document, keys, path, source)

    values: dict[str, Any] = {}
    for key in keys:
        table = document.get(key.table, {}) if key.table else document
        if key.name in table:
            try:
                values[key.label] = key.parse(key.label, table[key.name])
            except ValueError as error:
                raise CaseError(path, str(error),
                                _line_of_item(source, key, str(error))) from None
            except (TypeError, ArithmeticError, RecursionError):
                raise CaseError(path, f"{key.label} = {shown(table[key.name])} is not "
                                f"allowed: give {key.allowed}",
                                _line_of_key(source, key.table, key.name)) from None
        elif key.default is REQUIRED:
            if key.table in found.optional_tables and key.table not in document:
                continue
            raise CaseError(path, f"{key.label} is missing: give {key.allowed}")
    given = dict(values)
    try:
        check_confirmed(given.get(CONFIRM_LABEL, ()), {key.label for key in keys})
        for key in keys:
            if key.label not in values and key.default is not REQUIRED:
                values[key.label] = (key.default(values, path) if callable(key.default)
                                     else key.default)
        case = found.build(values, path)
        case = replace(case, warnings=unit_warnings(given, values[CONFIRM_LABEL]) + case.warnings)
    except ValueError as error:
        raise CaseError(path, str(error), _line_of_first_label(source, str(error), keys)) from None
    except (TypeError, ArithmeticError, RecursionError) as error:
        raise CaseError(path, f"the values do not fit together ({type(error).__name__}: "
                        f"{shown(str(error))}); check the keys against the case-file "
                        "reference") from None
    return case


def _refuse_unknown_keys(document: Mapping[str, Any], keys: tuple[Key, ...], path: str,
                         source: str) -> None:
    """Refuse every unknown key and table at once, each named with its suggestion."""
    tables = {key.table for key in keys if key.table}
    labels = [key.label for key in keys]
    found: list[tuple[str, int | None]] = []
    for name, value in document.items():
        if name in tables:
            if not isinstance(value, dict):
                raise CaseError(path, f"{name} = {shown(value)} must be a table ([{name}])",
                                _line_of_key(source, "", name))
            known = [key.name for key in keys if key.table == name]
            found.extend((_unknown_message(f"{name}.{inner}", inner, known, labels, name),
                          _line_of_key(source, name, inner))
                         for inner in value if inner not in known)
        elif not any(key.label == name for key in keys if not key.table):
            top_level = [key.name for key in keys if not key.table]
            if isinstance(value, dict):
                suggestion = difflib.get_close_matches(name, sorted(tables), n=1, cutoff=0.6)
                hint = f"; did you mean [{suggestion[0]}]?" if suggestion else ""
                found.append((f"unknown table [{name}]{hint} Tables: {', '.join(sorted(tables))}",
                              _line_of_table(source, name)))
            else:
                found.append((_unknown_message(name, name, top_level, labels, ""),
                              _line_of_key(source, "", name)))
    if len(found) == 1:
        raise CaseError(path, found[0][0], found[0][1])
    if found:
        raise CaseError(path, f"{len(found)} unknown keys or tables: " + "; ".join(
            message if line is None else f"line {line}: {message}" for message, line in found),
            found[0][1])


def _unknown_message(label: str, name: str, same_table: list[str], every_label: list[str],
                     table: str) -> str:
    close = difflib.get_close_matches(name, same_table, n=1, cutoff=0.6)
    if close:
        suggestion: str | None = f"{table}.{close[0]}" if table else close[0]
    else:
        elsewhere = [other for other in every_label if other.rsplit(".", 1)[-1] == name]
        close_labels = difflib.get_close_matches(label, every_label, n=1, cutoff=0.6)
        suggestion = next(iter(elsewhere or close_labels), None)
    hint = f"; did you mean {suggestion}?" if suggestion else ""
    return f"unknown key {label}{hint}"


def _line_of_decode_error(error: tomllib.TOMLDecodeError, source: str) -> int | None:
    found = re.search(r"at line (\d+)", str(error))
    if found:
        return int(found.group(1))
    return len(source.splitlines()) if "end of document" in str(error) else None


def _line_of_first_label(source: str, message: str, keys: tuple[Key, ...]) -> int | None:
    """Line of the key named first in ``message`` (for errors that involve several keys)."""
    positions = []
    for key in keys:
        found = re.search(rf"(?<![\w.]){re.escape(key.label)}(?![\w])", message)
        if found:
            positions.append((found.start(), key))
    if not positions:
        return None
    key = min(positions, key=lambda position: position[0])[1]
    return _line_of_item(source, key, message)


def _line_of_item(source: str, key: Key, message: str) -> int | None:
    """Line of ``key``, or of its item ``[i]`` where ``message`` names one (an array
    written over several lines, ``hardpoints.points_mm[2]``: the line of point 2)."""
    line = _line_of_key(source, key.table, key.name)
    found = re.search(rf"(?<![\w.]){re.escape(key.label)}\[(\d+)\]", message)
    if line is None or found is None:
        return line
    return line + _array_item_offset(source.splitlines()[line - 1:], int(found.group(1)))


def _array_item_offset(lines: list[str], index: int) -> int:
    """Lines from an array's ``key = [`` line to the line where item ``index`` starts
    (0 when it cannot be found: the key's own line)."""
    depth, count, expecting = 0, -1, False
    for offset, text in enumerate(lines):
        quote = ""
        for char in text[text.index("=") + 1 if offset == 0 and "=" in text else 0:]:
            if quote:
                quote = "" if char == quote else quote
                continue
            if char == "#":
                break
            if depth == 1 and expecting and char not in " \t,]":
                count, expecting = count + 1, False
                if count == index:
                    return offset
            if char in "\"'":
                quote = char
            elif char == "[":
                depth += 1
                expecting = expecting or depth == 1
            elif char == "]":
                depth -= 1
                if depth <= 0:
                    return 0
            elif char == "," and depth == 1:
                expecting = True
    return 0


_TABLE_HEADER = re.compile(r"^\s*\[\s*([A-Za-z0-9_.-]+)\s*\]")


def _line_of_table(source: str, table: str) -> int | None:
    for number_of_line, line in enumerate(source.splitlines(), start=1):
        header = _TABLE_HEADER.match(line)
        if header and header.group(1) == table:
            return number_of_line
    return None


def _line_of_key(source: str, table: str, name: str) -> int | None:
    """Line of ``name = ...`` inside ``[table]`` (or ``table.name = ...`` at the top)."""
    current = ""
    assignment = re.compile(rf"^\s*{re.escape(name)}\s*=")
    dotted = re.compile(rf"^\s*{re.escape(table)}\s*\.\s*{re.escape(name)}\s*=") if table else None
    for number_of_line, line in enumerate(source.splitlines(), start=1):
        header = _TABLE_HEADER.match(line)
        if header:
            current = header.group(1)
        elif current == table and assignment.match(line):
            return number_of_line
        elif current == "" and dotted is not None and dotted.match(line):
            return number_of_line
    # A key whose value is a table of its own ([hardpoints.positions]).
    return _line_of_table(source, f"{table}.{name}") if table else None
