"""Figures quoted in the prose of README.md and docs/ are those a run gives today.

Code blocks and their outputs are run by tests/docs/test_doc_blocks.py. This module
holds the figures written into sentences and tables: each is recomputed here, printed
as the page prints it, and looked up in the page (whitespace and line breaks
normalised). A change of the code that moves a figure fails here, naming the page.

Counts of shipped files are checked the same way. Not listed here, by kind (audited
page by page; none is the output of a run):
limits and defaults (64 joints, 90 deg, 1e-15, 4096 MB, 8 starts, ...; their constants
are checked by tests/test_limits.py), case and example inputs (angles, bounds, speeds,
teeth, samples, seeds), tolerances a test asserts (``1e-9 relative on random
columns``: the tolerance of the named test), published values quoted as published
(the paper's optima, objective values and fmincon counts; SAE AE-7's rounded
calibration; reference years and pages), and figure sizes and file formats. The
"about 2 %" of the paper model's two joints at 30 deg (docs/model.md) is checked by
tests/kinematics/test_hooke.py; the figures of docs/scaling.md by
tests/docs/test_scaling_page.py.
"""

from __future__ import annotations

import re

import numpy as np
import pytest
from column.column_cases import load

import sso
from doctools.blocks import ROOT
from sso._column.excitation import equivalent_angles, excitation_table
from sso._column.geometry import ColumnGeometry
from sso._column.steering_criteria import assess_steering

TRUCK = load("truck_three_joints")["points_mm"]
BEST_TEETH = (10.0, -80.0)  # the truck's best 36-tooth assembly (docs/column.md)


def page_text(page: str) -> str:
    return " ".join((ROOT / page).read_text(encoding="utf-8").split())


def short_e(value: float, digits: int) -> str:
    """``4.86e-3`` as the pages write it (no zero in the exponent)."""
    mantissa, exponent = f"{value:.{digits - 1}e}".split("e")
    return f"{mantissa}e{int(exponent)}"


def truck_phasing() -> str:
    result = sso.optimise(ColumnGeometry(TRUCK))
    best = result.fun
    delta = result.yoke_phase_deg
    return (f"yokes in phase RE {short_e(result.in_phase_re, 3)}; textbook correction "
            f"{short_e(result.plane_corrected_re, 3)}; best phasing (`delta = {delta[0]:.1f}, "
            f"{delta[1]:.1f}` deg) {short_e(best, 3)}, {result.in_phase_re / best:.0f} times "
            f"better than in phase and {result.plane_corrected_re / best:.1f} times better "
            "than the textbook correction")


def calibration() -> tuple[object, object]:
    """The SAE AE-7 calibration column (tests/column/test_column_excitation.py)."""
    from column.column_cases import planar_points

    series = ColumnGeometry(planar_points([5.0, -4.0, 3.0, -2.0])).series((90.0, 0.0, 0.0))
    (row,) = excitation_table(series, [2500.0], vehicle="car")
    return equivalent_angles(series), row


def calibration_table() -> str:
    angles, row = calibration()
    return (f"| equivalent angle, deg (published / sso) | 9.90 / {angles.drive_deg:.4f} | "
            f"3.16 / {angles.coast_deg:.4f} | 6.00 / {angles.torsional_deg:.4f} | "
            f"| excitation, rad/s^2 (published / sso) | 2026 / {row.drive_rad_s2:.1f} | "
            f"209 / {row.coast_rad_s2:.1f} | 749 / {row.torsional_rad_s2:.1f} |")


def calibration_exact() -> str:
    angles, row = calibration()
    return (f"`beta_eq = {angles.exact_deg:.3f}` deg, `omega^2 sin^2 beta_eq = "
            f"{row.exact_torsional_rad_s2:.1f}` rad/s^2, and an output acceleration amplitude "
            f"of {row.exact_output_accel_rad_s2:.1f} rad/s^2")


def calibration_amplitude() -> str:
    return f"{calibration()[1].exact_output_accel_rad_s2:.1f} rad/s^2."


def truck_lock_to_lock() -> str:
    designs = [("best", "best", BEST_TEETH), ("in_phase", "in phase", (0.0, 0.0))]
    best, in_phase = ({criterion.name.split(",")[0]: criterion.value
                       for criterion in design.criteria}
                      for design in assess_steering(ColumnGeometry(TRUCK), designs,
                                                    lock_deg=900.0).designs)
    return (f"yokes in phase {in_phase['speed-ratio fluctuation']:.1f} % speed-ratio "
            f"fluctuation and a largest transmission error of "
            f"{in_phase['largest transmission error']:.2f} deg; the best 36-tooth assembly "
            f"{best['speed-ratio fluctuation']:.2f} % and "
            f"{best['largest transmission error']:.2f} deg")


def trial_range(beta_deg: list[float], phase_deg: list[float]) -> tuple[float, float]:
    evaluation = sso.ShaftSeries(beta_deg, phase_deg, model="paper").evaluate(25.0)
    return evaluation.speed_min_rpm, evaluation.speed_max_rpm


def paper_trials() -> str:
    (low_3, high_3), (low_2, high_2) = (trial_range([30, 40, 50], [90, 90]),
                                        trial_range([10, 15, 30], [90, 90]))
    return (f"option-3 trial turns the output between {low_3:.2f} and {high_3:.2f} rpm "
            f"(paper: \"18 - 34\"), the option-2 trial between {low_2:.2f} and {high_2:.2f} rpm")


def option_one_trial(words: str) -> str:
    low, high = trial_range([15, 20, 9], [30, 40])
    return words.format(low=f"{low:.2f}", high=f"{high:.2f}")


def fortran_degree() -> str:
    """The four-bar paper's degree constant (0.0174532, as printed in its program) against
    pi / 180: how far short it is, in parts per million."""
    short_ppm = (1.0 - 0.0174532 / (np.pi / 180.0)) * 1e6
    return f"converts degrees with 0.0174532, {short_ppm:.1f} ppm short"


NUMBER_WORDS = {3: "three", 4: "four", 5: "five", 6: "six", 8: "eight", 9: "nine"}


def lm_kernel_blocks() -> str:
    """The compiled blocks of "lm" (sso/_solvers/lm_kernel.py's constants)."""
    from sso._solvers import lm_kernel

    return (f"Gauss-Newton blocks of {NUMBER_WORDS[lm_kernel.GAUSS_NEWTON_ITERATIONS]} "
            f"iterations and, for up to {lm_kernel.NEWTON_BLOCK_VARIABLES} variables, Newton "
            f"blocks of {NUMBER_WORDS[lm_kernel.NEWTON_ITERATIONS]}")


def lm_kernel_newton() -> str:
    from sso._solvers import lm_kernel

    return (f"Newton blocks are built for up to {lm_kernel.NEWTON_BLOCK_VARIABLES} variables")


def finite_difference_port() -> str:
    from benchmarks.cases import BASELINE_ANGLES_DEG

    return (f"the finite-difference port (SLSQP on RE sampled at {len(BASELINE_ANGLES_DEG)} "
            "angles)")


def sweep_chunks() -> str:
    """How a sweep cuts its points into tasks (sso/_studies/sweep.py's constants)."""
    from sso._studies import sweep

    return (f"in chunks (about {NUMBER_WORDS[sweep.CHUNKS_PER_WORKER]} per worker, at most "
            f"{sweep.DEFAULT_CHUNK_CAP} points each; a sweep that runs as arrays, chunks of "
            f"decreasing size, from at most {sweep.ARRAY_CHUNK_CAP:,} points down to "
            f"{sweep.ARRAY_CHUNK_FLOOR:,}")


def chain_limits() -> str:
    """The largest equal operating angles and tangent sum sso accepts (sso/_validation.py)."""
    import math

    from sso._validation import LARGEST_TANGENT_SUM, least_cosine_product

    def equal_deg(joints: int, decimals: int) -> str:
        cosine = least_cosine_product(joints) ** (1.0 / joints)
        return f"{math.degrees(math.acos(cosine)):.{decimals}f}"

    return (f"equal angles up to {equal_deg(2, 8)} deg for 2 joints, {equal_deg(4, 4)} for 4, "
            f"{equal_deg(8, 2)} for 8, {equal_deg(16, 2)} for 16 and {equal_deg(64, 2)} for 64; "
            f"and tangents summing to at most {short_e(LARGEST_TANGENT_SUM, 2)} (one joint up to "
            f"{math.degrees(math.atan(LARGEST_TANGENT_SUM)):.7f} deg")


def extent_search_column() -> str:
    """The extent search's probes (sso/_shafts/exact_optima.py's constants)."""
    from sso._shafts.exact_optima import EXTENT_PROBES

    return f"Levenberg-Marquardt from the chosen design and {EXTENT_PROBES} seeded random probes"


def extent_search_api() -> str:
    from sso._shafts.exact_optima import EXTENT_HALVINGS, EXTENT_PROBES

    return (f"from the chosen design and then from {EXTENT_PROBES} seeded random probes: the "
            "first that lands is the end's witness, an exact optimum on the bound, and the end "
            "(`at_bound`, \"bound\" in the table) is exact. Where none lands, the pinned value "
            f"is bisected {EXTENT_HALVINGS} times towards the chosen design")


def shipped_cases() -> str:
    cases = ROOT / "cases"
    counts = [len(list(cases.glob(pattern))) for pattern in
              ("**/*.toml", "paper_option*_*.toml", "column_*.toml", "mechanisms/*.toml")]
    total, paper, columns, mechanisms = counts
    drivelines = sum('kind = "driveline"' in path.read_text(encoding="utf-8")
                     for path in cases.glob("driveline_*.toml"))
    return (f"`cases/` ships {total}: {NUMBER_WORDS[paper]} of the paper's three options in the "
            f"exact and the paper model (`paper_option<1|2|3>_<exact|paper>.toml`, each with "
            "the paper's reported optimum as `reference`), a two-joint `steering_column.toml`, "
            "a four-joint truck `driveline_four_joint.toml`, "
            f"{NUMBER_WORDS[columns]} steering columns from hardpoints (`column_*.toml`, see "
            f"[steering columns](steering-columns.md)), {NUMBER_WORDS[drivelines]} drivelines "
            "from a fitter's measurements (the other `driveline_*.toml`, see "
            "[drivelines](drivelines.md)) and "
            f"{NUMBER_WORDS[mechanisms]} mechanism cases")


def shipped_columns() -> str:
    columns = len(list((ROOT / "cases").glob("column_*.toml")))
    return (f"ships the paper's three options in both models, {NUMBER_WORDS[columns]} "
            "steering columns")


def report_renderers() -> str:
    lengths = [len((ROOT / "sso" / "_reports" / name).read_text(encoding="utf-8").splitlines())
               for name in ("markdown.py", "html.py")]
    assert max(lengths) < 100, lengths
    return "(`sso/_reports/markdown.py`, `sso/_reports/html.py`, under 100 lines each)"


FIGURES = {
    "truck phasing (docs/column.md)": ("docs/column.md", truck_phasing),
    "SAE AE-7 calibration (docs/column.md)": ("docs/column.md", calibration_table),
    "SAE AE-7 calibration (docs/guide/steering-columns.md)": (
        "docs/guide/steering-columns.md", calibration_table),
    "exact calibration (docs/guide/steering-columns.md)": (
        "docs/guide/steering-columns.md", calibration_exact),
    "exact calibration amplitude (docs/column.md)": ("docs/column.md", calibration_amplitude),
    "truck lock to lock (docs/column.md)": ("docs/column.md", truck_lock_to_lock),
    "paper trials (docs/model.md)": ("docs/model.md", paper_trials),
    "chain limits (docs/model.md)": ("docs/model.md", chain_limits),
    "extent search (docs/column.md)": ("docs/column.md", extent_search_column),
    "extent search (docs/guide/python-api.md)": ("docs/guide/python-api.md",
                                                 extent_search_api),
    "option-1 trial (docs/model.md)": ("docs/model.md", lambda: option_one_trial(
        "model gives {low} to {high} rpm")),
    "option-1 trial (docs/guide/limits.md)": ("docs/guide/limits.md", lambda: option_one_trial(
        "the model gives {low} - {high} rpm")),
    "shipped cases (docs/guide/case-files.md)": ("docs/guide/case-files.md", shipped_cases),
    "report renderers (docs/dependencies.md)": ("docs/dependencies.md", report_renderers),
    "shipped columns (docs/getting-started.md)": ("docs/getting-started.md", shipped_columns),
    "the paper's degree (docs/tutorials/mechanisms.md)": ("docs/tutorials/mechanisms.md",
                                                          fortran_degree),
    "lm's compiled blocks (docs/performance.md)": ("docs/performance.md", lm_kernel_blocks),
    "the paper model's baseline (docs/performance.md)": ("docs/performance.md",
                                                         finite_difference_port),
    "a sweep's chunks (docs/guide/sweeps.md)": ("docs/guide/sweeps.md", sweep_chunks),
    "lm's compiled Newton steps (docs/architecture.md)": ("docs/architecture.md",
                                                          lm_kernel_newton),
}


@pytest.mark.parametrize("name", list(FIGURES))
def test_a_figure_in_prose_is_what_the_code_gives(name):
    page, figures = FIGURES[name]
    expected = " ".join(figures().split())
    text = page_text(page)
    assert expected in text, f"{page} should say: {expected}"


def test_the_column_solver_tolerance_keeps_slsqp_within_the_cross_check():
    # docs/robust.md: SLSQP's stationarity error at the default column tolerance, on the
    # shipped three-position column with 200 samples, both robust objectives.
    from sso._limits import DEFAULT_COLUMN_SOLVER_TOL, DEFAULT_KKT_TOLERANCE

    positions = load("truck_three_positions")["positions"]
    tolerances = sso.Tolerances(hardpoint_mm=1.0, yoke_phase_deg=1.0, samples=200, seed=1)
    stationarity = [sso.optimise(ColumnGeometry(position["points_mm"]), tolerances=tolerances,
                                 robust_objective=objective).solutions["slsqp"].kkt
                    for position in positions.values() for objective in ("mean", "p95")]
    assert len(stationarity) == 6
    assert max(stationarity) < 0.1 * DEFAULT_KKT_TOLERANCE
    text = page_text("docs/robust.md")
    solver_tol = short_e(DEFAULT_COLUMN_SOLVER_TOL, 1)
    assert f"The default solver tolerance is `{solver_tol}`" in text
    assert ("(200 samples, seed 1, the mean and the CVaR95 objective) SLSQP's stationarity error "
            f"at `{solver_tol}` stays below {short_e(0.1 * DEFAULT_KKT_TOLERANCE, 1)}, a "
            f"tenth of the cross-check's {short_e(DEFAULT_KKT_TOLERANCE, 1)}.") in text


def test_no_timing_in_the_performance_page_s_prose():
    # Times belong to a recorded run (the page's generated section), not to sentences.
    prose = page_text("docs/performance.md").split("<!-- performance run -->")
    for part in prose:
        assert not re.search(r"\d\s*(us|ms|µs)\b", part), part


def test_the_short_exponent_form():
    assert short_e(4.8612e-3, 3) == "4.86e-3"
    assert short_e(np.float64(2.2679e-4), 3) == "2.27e-4"
