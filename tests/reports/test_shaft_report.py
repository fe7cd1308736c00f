"""The report of a shaft series, rendered from the result object alone."""

from __future__ import annotations

import sso
from sso._reports.shaft_report import PYTHON_NAME, optimisation_files


def test_an_optimisation_made_in_python_reports_its_problem_and_solvers():
    result = sso.optimise(sso.ShaftSeries([15.0, 20.0, 9.0], [30.0, 40.0]), 1, starts=2)
    files = optimisation_files(result, ("csv", "md"))
    markdown = files["report.md"].decode()
    assert markdown.startswith(f"# SSO report: {PYTHON_NAME}\n")
    assert "| option | 1 (phase) |" in markdown
    assert "| operating-angle bounds (deg) | \\[0, 40] each |" in markdown
    assert "## Solvers" in markdown and "## Versions" not in markdown
    rows = files["speeds.csv"].decode().splitlines()
    assert rows[0] == ("input_angle_deg,input_speed_rpm,output_speed_initial_rpm,"
                       "output_speed_optimum_rpm")
    assert len(rows) == 362
    # the optimum's speeds are the curve the result carries, to six digits
    optimum = result.compared[1]
    assert float(rows[91].split(",")[3]) == float(f"{optimum.output_speed_rpm[90]:.6g}")
