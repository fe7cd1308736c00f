"""Sweep files: a base case, the axes to vary, and what to do at each point (TOML).

::

    name = "option3-start-map"            # output folder name (default: file name)
    case = "paper_option3_exact.toml"     # base case file, relative to this file,
                                          # or a [case] table laid out like a case file
    action = "optimise"                   # or "evaluate"
    mode = "product"                      # or "listed"
    chunk_size = 10                       # points per task (default: automatic)

    [axes]
    "design.beta_deg[0]" = { start = 10, stop = 40, num = 7 }
    option = [2, 3]

Like a case file, a sweep file is data only; nothing in it is executed.
"""

from __future__ import annotations

import difflib
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from sso._cases.schema import NAME_PATTERN, parse_toml
from sso._files import read_input_bytes
from sso._studies.worker import ACTIONS
from sso._validation import shown

KEYS = ("name", "case", "action", "mode", "chunk_size", "axes")


@dataclass(frozen=True)
class SweepSpec:
    """A sweep file as read: the arguments of :func:`sso.sweep`.

    Attributes
    ----------
    name : str
        Output folder name.
    base : pathlib.Path or dict
        Base case file, or a case laid out as in a case file.
    axes : dict
        Axis path to values or range.
    action, mode : str
    chunk_size : int or None
    """

    name: str
    base: Path | dict[str, Any]
    axes: dict[str, Any]
    action: str
    mode: str
    chunk_size: int | None


def load_sweep(path: str | Path) -> SweepSpec:
    """Read a sweep file; the axes and base case are checked by :func:`sso.sweep`.

    Raises
    ------
    ValueError
        Naming the file and the key, for unreadable TOML, an unknown key (with the
        nearest valid one), a missing base case or axes, or a wrong type.
    """
    path = Path(path)
    try:
        source = read_input_bytes(path).decode("utf-8")
    except UnicodeDecodeError as error:
        raise ValueError(f"{path}: not a valid TOML sweep file: {error}") from None
    except ValueError as error:
        raise ValueError(f"{path}: cannot read the sweep file: {error}") from None
    document = parse_toml(source, str(path), _sweep_file_error)
    for key in document:
        if key not in KEYS:
            close = difflib.get_close_matches(key, KEYS, n=1, cutoff=0.6)
            hint = f"; did you mean {close[0]}?" if close else ""
            raise ValueError(f"{path}: unknown key {key}{hint} Keys: {', '.join(KEYS)}")
    name = document.get("name", path.stem)
    if not isinstance(name, str) or not NAME_PATTERN.fullmatch(name):
        raise ValueError(f"{path}: name = {shown(name)} must be 1 to 100 letters, digits, '.', '_' "
                         "or '-', starting with a letter or digit (it names the output folder)")
    base = document.get("case")
    if isinstance(base, str):
        base = path.parent / base
    elif not isinstance(base, dict):
        raise ValueError(f"{path}: case = {shown(base)} must be a case file path (relative to the "
                         "sweep file) or a [case] table laid out like a case file")
    axes = document.get("axes")
    if not isinstance(axes, dict) or not axes:
        raise ValueError(f"{path}: [axes] is missing or empty: give one or more case keys "
                         "with their values, e.g. option = [2, 3]")
    action = document.get("action", "optimise")
    if action not in ACTIONS:
        raise ValueError(f"{path}: action = {shown(action)} is not one of "
                         f"{', '.join(map(repr, ACTIONS))}")
    return SweepSpec(name=name, base=base, axes=axes, action=action,
                     mode=document.get("mode", "product"), chunk_size=document.get("chunk_size"))


def _sweep_file_error(path: str, reason: str, line: int | None) -> ValueError:
    where = f"{path}, line {line}" if line is not None else path
    return ValueError(f"{where}: not a valid TOML sweep file: {reason}")
