"""Every source module has a test module beside the others of its part.

``sso/<part>/<name>.py`` is tested in ``tests/<part>/test_<name>.py`` (or
``tests/<part>/test_<part>_<name>.py``, the column's naming), and ``sso/<name>.py``
in ``tests/test_<name>.py``. Not counted: ``__init__.py`` (re-exports, exercised
through every import of the package) and ``__main__.py`` (``python -m`` entry
points, run by tests/test_packaging.py).
"""

from __future__ import annotations

from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "sso"
NOT_COUNTED = {"__init__.py", "__main__.py"}
TESTED_ELSEWHERE = {
    "sso/_distribution.py": "tests/test_packaging.py",
    # what sso report and --resume check, tested through the command as a user meets it
    "sso/_reports/figure_checks.py": "tests/cli/test_report_checks.py",
    "sso/_studies/saved_rows.py": "tests/cli/test_report_checks.py",
    "sso/_studies/row_checks.py": "tests/cli/test_resume_checks.py",
    "sso/_studies/tolerance_samples.py": "tests/cli/test_tolerance_record.py",
    "sso/_studies/saved_samples.py": "tests/cli/test_tolerance_record.py",
}

# Modules that have no test module of their own yet. Tests of many of them exist under
# other names (tests/cli/test_cli.py, tests/shafts/test_paper_cases.py, ...); each line
# goes when its module gets tests/<part>/test_<name>.py, so this list only shrinks.
STILL_WITHOUT_TEST_MODULE = {
    "sso/_studies/estimate.py",
    "sso/_studies/report.py",
    "sso/_studies/results.py",
    "sso/_cases/column.py",
    "sso/_cases/column_points.py",
    "sso/_cases/column_robust.py",
    "sso/_cases/mechanism.py",
    "sso/_cases/shaft_series.py",
    "sso/_cli/app.py",
    "sso/_cli/report.py",
    "sso/_cli/solve.py",
    "sso/_cli/validate.py",
    "sso/_column/chain_matrix.py",
    "sso/_column/design.py",
    "sso/_column/robust_phasing.py",
    "sso/_column/scenarios.py",
    "sso/_column/tolerances.py",
    "sso/_linkages/table.py",
    "sso/_reports/column_plots.py",
    "sso/_progress.py",
    "sso/_reports/column_report.py",
    "sso/_reports/column_robust_plots.py",
    "sso/_reports/column_robust_report.py",
    "sso/_reports/html.py",
    "sso/_reports/mechanism_plots.py",
    "sso/_reports/plots.py",
    "sso/_reports/speeds.py",
    "sso/_reports/summary.py",
    "sso/_shafts/batch.py",
    "sso/_shafts/perturbed.py",
    "sso/_solvers/solution.py",
}


def source_modules() -> list[str]:
    return sorted(
        path.relative_to(ROOT).as_posix()
        for path in PACKAGE.rglob("*.py")
        if path.name not in NOT_COUNTED
    )


def candidate_test_modules(module: str) -> list[Path]:
    """Where the test module of ``module`` may be."""
    parts = Path(module).relative_to("sso").parts
    name = Path(parts[-1]).stem.removeprefix("_")
    folder = ROOT / "tests" / Path(*(part.removeprefix("_") for part in parts[:-1]))
    candidates = [folder / f"test_{name}.py"]
    if len(parts) > 1:
        candidates.append(folder / f"test_{parts[0].removeprefix('_')}_{name}.py")
    return candidates


def missing_test_modules() -> set[str]:
    return {
        module
        for module in source_modules()
        if module not in TESTED_ELSEWHERE
        and not any(path.is_file() for path in candidate_test_modules(module))
    }


def test_every_module_has_a_test_module():
    missing = missing_test_modules() - STILL_WITHOUT_TEST_MODULE
    assert missing == set(), "add tests/<part>/test_<name>.py for each"


def test_the_list_of_modules_still_without_tests_only_shrinks():
    done = STILL_WITHOUT_TEST_MODULE - missing_test_modules()
    assert done == set(), "these now have a test module: delete them from the list"


def test_modules_tested_elsewhere_are_tested_there():
    for module, test in TESTED_ELSEWHERE.items():
        assert (ROOT / module).is_file() and (ROOT / test).is_file()
        stem = Path(module).stem.lstrip("_")
        assert stem in (ROOT / test).read_text(encoding="utf-8")


def test_the_walk_sees_the_package():
    modules = source_modules()
    assert "sso/_limits.py" in modules and "sso/_solvers/kkt.py" in modules
    assert len(modules) > 50
    assert not any(module.endswith("__init__.py") for module in modules)
    assert (
        candidate_test_modules("sso/_solvers/kkt.py")[0]
        == ROOT / "tests" / "solvers" / "test_kkt.py"
    )
