"""No extent table holds a row whose ends are one value (issue 35, item 8): a variable
the set of exact optima holds at one value reads "a single value", and a set that is
a single point in every variable shows no extent table at all.

Situations: cases/steering_column.toml, whose optimum's phase is pinned at 90 deg
while its two bends move along a curve of exact optima (its report had a phase_1 row
from 90 to 90); cases/column_truck_three_positions.toml, whose nominal optimum of the
hardpoints is isolated (a set of dimension 0, whose extent table read from = to for
both shafts).
"""

from __future__ import annotations

from pathlib import Path

import sso
from sso._reports.column_report import column_blocks
from sso._reports.markdown import render_markdown
from sso._reports.shaft_report import SINGLE_VALUE, run_files

CASES = Path(__file__).resolve().parents[2] / "cases"


def rows_with_equal_ends(markdown: str) -> list[str]:
    """Rows of the extent table (variable, unit, set from, set to, chosen, ends) whose
    set-from and set-to cells hold one number."""
    found = []
    for line in markdown.splitlines():
        cells = [cell.strip() for cell in line.strip().strip("|").split("|")]
        if len(cells) == 6 and cells[1] in ("deg", "mm") and cells[2] == cells[3]:
            found.append(line)
    return found


def test_a_variable_held_at_one_value_reads_a_single_value():
    run = sso.run_case(CASES / "steering_column.toml")
    markdown = run_files(run, ("md",))["report.md"].decode()
    assert f"| phase_1 | deg | 90 | {SINGLE_VALUE} | 90 |" in markdown
    assert "| phase_1 | from = to | 90 |" in markdown
    assert "| phase_1 | to |" not in markdown
    assert rows_with_equal_ends(markdown) == []
    before = markdown.replace(f"| {SINGLE_VALUE} |", "| 90 |")  # the row as it read before
    assert len(rows_with_equal_ends(before)) == 1  # the check finds such a row


def test_an_isolated_optimum_shows_no_extent_table():
    run = sso.run_case(CASES / "column_truck_three_positions.toml")
    markdown = render_markdown(column_blocks(run, ()))
    assert ("shaft 1: a single value, 60.576 deg; shaft 2: a single value, 66.698 deg. Each "
            "shaft's delta is a single value: no other phasing near the chosen one reaches "
            "RE = 0.") in markdown
    assert "| intermediate shaft | end | delta (deg) |" not in markdown
    assert "from = to" not in markdown
