"""The most robust of many exact optima (sso._shafts.exact_optima through sso.optimise).

References: RE of the chosen designs by the adaptive quadrature of the angle-by-angle
chain (sso._shafts.quadrature with sso._kinematics.hooke, no chain matrix); p95 RE by
sso.tolerance_study's own Monte Carlo of the returned result. The figures of the
optimum returned before this choice existed (p95 2.31e-4 on the README example under
0.5 deg / 1 deg normal tolerances, 10,000 samples, seed 0; best of 150 random starts
1.2e-5) are the issue's measurements.
"""

import functools

import numpy as np
import pytest

import sso
from sso._shafts.exact_optima import RANK_TOLERANCE, _rank_of_two_rows
from sso._shafts.quadrature import adaptive_residual_error

README_SERIES = sso.ShaftSeries(beta_deg=[30, 40, 40], phase_deg=[90, 90], model="exact")
README_CALL = {"option": 3, "beta_bounds_deg": (10, 40), "phase_bounds_deg": (0, 180),
               "solvers": ("ipopt", "slsqp"), "starts": 8, "input_speed_rpm": 25}
TOLERANCES = {"beta_tolerance_deg": 0.5, "phase_tolerance_deg": 1.0, "distribution": "normal",
              "samples": 10_000, "seed": 0}
BOUNDS_DEG = [(10.0, 40.0)] * 3 + [(0.0, 180.0)] * 2


def _quadrature_residual_error(series):
    value, rule = adaptive_residual_error(list(np.radians(series.beta_deg)),
                                          list(np.radians(series.phase_deg)), "exact",
                                          rtol=1e-12, atol=1e-18)
    assert rule.converged
    return value


def test_without_tolerances_the_chosen_exact_optimum_lies_strictly_inside_the_bounds():
    result = sso.optimise(README_SERIES, **README_CALL)
    exact = result.exact_optima
    assert exact is not None and exact.criterion == "largest margin to the bounds"
    design = (*result.best.series.beta_deg, *result.best.series.phase_deg)
    margins = [min(value - low, high - value)
               for value, (low, high) in zip(design, BOUNDS_DEG, strict=True)]
    # strictly inside: every variable at least 10 deg from its bounds (the first exact
    # optimum found sits on the 40 deg bound)
    assert min(margins) >= 10.0
    assert exact.margin == pytest.approx(min(margins), rel=1e-9)
    assert exact.margin > exact.first_margin + 5.0
    assert _quadrature_residual_error(result.best.series) <= 1e-18
    assert result.best.role == "selection"
    assert result.found_by == "lm choosing within the exact optima"
    assert result.best in result.runs
    assert result.success


def test_the_extent_is_the_whole_sets_with_a_witness_at_every_bound():
    # The branch of the set SLSQP followed from the chosen design stopped at beta_2 =
    # 14.106 deg and beta_1, beta_3 = 38.9348 deg (the lead's random pinned
    # projections found exact optima at the bounds 10 and 40 deg in 233 and 192 of 300
    # tries); the whole set reaches every bound, and each end's witness is checked here
    # by the adaptive quadrature of the angle-by-angle chain.
    result = sso.optimise(README_SERIES, **README_CALL)
    exact = result.exact_optima
    assert exact.variables == ("beta_1", "beta_2", "beta_3", "phase_1", "phase_2")
    assert exact.dimension == 3  # five free angles, two residuals
    assert exact.extent == tuple(BOUNDS_DEG)
    search = exact.extent_search
    for index, (pair, bounds) in enumerate(zip(search.ends, BOUNDS_DEG, strict=True)):
        for end, bound in zip(pair, bounds, strict=True):
            assert end.at_bound and end.value == bound
            assert end.witness[index] == bound
            for value, (lower, upper) in zip(end.witness, BOUNDS_DEG, strict=True):
                assert lower <= value <= upper
            series = sso.ShaftSeries(beta_deg=end.witness[:3], phase_deg=end.witness[3:],
                                     model="exact")
            assert _quadrature_residual_error(series) <= 1e-18, (index, end)
            assert end.witness_residual_error <= 1e-20
    # the stated bound on the search's cost: 2 sides of 5 variables, each at most
    # 1 + 32 probes + 12 halvings of 2 starts (measured: 14 solves)
    assert search.probes == 32
    assert 10 <= search.solves <= 2 * 5 * (1 + 32 + 12 * 2)
    summary = result.summary()
    assert "set from" in summary and "a set of dimension 3" in summary
    assert "bound / bound" in summary and "reached" not in summary.split("set from")[1]
    document = result.to_dict()["exact_optima"]
    assert [[end["value"] for end in pair] for pair in document["extent_search"]["ends"]] == [
        list(pair) for pair in exact.extent]
    reloaded = sso.OptimisationResult.from_dict(result.to_dict()).exact_optima
    assert reloaded.extent_of is None and reloaded.extent_search == search


def test_phases_whose_bounds_span_two_periods_are_searched_modulo_the_period():
    # Phase bounds of one and a half periods each way hold every exact optimum twice, so
    # no end could be a bound: each phase is walked from the chosen value in 5 deg steps
    # (all land on this set) and the extent is half a period each way, found, not a bound.
    call = {**README_CALL, "phase_bounds_deg": (-90, 270)}
    exact = sso.optimise(README_SERIES, **call).exact_optima
    bounds = [(10.0, 40.0)] * 3 + [(-90.0, 270.0)] * 2
    for index, ((low, high), chosen) in enumerate(zip(exact.extent_search.ends, exact.chosen,
                                                      strict=True)):
        if index < 3:
            assert low.at_bound and high.at_bound
            continue
        assert not low.at_bound and not high.at_bound
        assert high.value - low.value == pytest.approx(180.0, abs=1e-9)
        assert low.value <= chosen <= high.value
        for end in (low, high):
            assert end.witness[index] == end.value
            for value, (lower, upper) in zip(end.witness, bounds, strict=True):
                assert lower <= value <= upper
            series = sso.ShaftSeries(beta_deg=end.witness[:3], phase_deg=end.witness[3:],
                                     model="exact")
            assert _quadrature_residual_error(series) <= 1e-18, (index, end)
    assert "reached / reached" in exact.summary()


def test_round_off_in_the_chosen_design_does_not_move_the_extent():
    # Designs 1e-14 rad apart (as solver paths and processes leave them) once ended the
    # branch's beta_1 at 40 or at 38.93 deg; the ends at the bounds do not move.
    from sso._shafts.exact_optima import _minimised, series_set_problem, set_extent
    from sso._shafts.options import build_problem
    from sso._shafts.problem import compiled_nlp

    exact = sso.optimise(README_SERIES, **README_CALL).exact_optima
    problem = build_problem([30, 40, 40], [90, 90], "exact", 3, (10, 40), (0, 180))
    fixed = problem.parameters_rad.tolist()

    def residuals(x):
        return compiled_nlp(problem, 0).residuals_and_jacobian(x, fixed)

    chosen = np.radians(exact.chosen)
    for nudge in (-1e-14, 1e-14, 3e-14):
        moved = chosen + nudge * np.array([-0.7, 1.0, 1.9, 1.1, 1.1])
        found = set_extent(series_set_problem(problem), residuals,
                           functools.partial(_minimised, residuals), moved)
        assert tuple((low.value, high.value) for low, high in found.ends) == exact.extent
        assert all(low.at_bound and high.at_bound for low, high in found.ends)


def test_with_tolerances_the_chosen_exact_optimum_has_the_lowest_p95():
    result = sso.optimise(README_SERIES, **README_CALL, **TOLERANCES)
    exact = result.exact_optima
    assert exact.criterion == "lowest p95 RE under the given tolerances"
    assert exact.p95_residual_error <= 1.5e-5
    # the exact optimum first found (IPOPT's own answer) is far less robust
    assert exact.first_p95_residual_error > 5.0 * exact.p95_residual_error
    study = sso.tolerance_study(result, **TOLERANCES)
    p95 = study.percentile_table()["residual_error"][95.0]
    assert p95 == pytest.approx(exact.p95_residual_error, rel=1e-9)
    assert p95 <= 1.5e-5
    assert _quadrature_residual_error(result.best.series) <= 1e-18


@pytest.mark.parametrize("starts", [1, 8])
def test_one_solver_reports_what_it_reached(starts):
    result = sso.optimise(README_SERIES, 3, beta_bounds_deg=(10, 40), solvers=("lm",),
                          starts=starts)
    assert result.exact_optima is None
    assert result.best.role == "solve"


@pytest.mark.parametrize(("keywords", "message"), [
    ({"beta_tolerance_deg": -1.0}, r"beta_tolerance_deg\[0\]"),
    ({"phase_tolerance_deg": [1.0, 2.0, 3.0]}, "phase_tolerance_deg has 3 entries"),
    ({"distribution": "cauchy"}, "distribution"),
    ({"samples": 0}, "samples"),
    ({"samples": 10, "seed": -1}, "seed"),
])
def test_bad_tolerances_name_the_field(keywords, message):
    with pytest.raises(ValueError, match=message):
        sso.optimise(README_SERIES, 3, **keywords)


def test_the_paper_model_refuses_tolerances():
    with pytest.raises(ValueError, match="only the exact model"):
        sso.optimise(sso.ShaftSeries([30, 40, 40], [90, 90], model="paper"), 3,
                     beta_tolerance_deg=0.5)


def test_the_set_s_rank_is_numpy_s_svd_rank():
    # The rank behind the set's dimension (closed form for two residual rows) against
    # numpy's SVD at the same tolerance, on random rows, nearly dependent rows (down to
    # 1e-14 apart), a zero row and rows of extreme scale.
    rng = np.random.default_rng(20261125)
    for trial in range(4000):
        size = int(rng.integers(1, 9))
        real, imag = rng.normal(size=size), rng.normal(size=size)
        if trial % 4 == 1:
            imag = real * rng.normal() + rng.normal(size=size) * 10.0 ** rng.uniform(-14, -5)
        elif trial % 4 == 2:
            imag = np.zeros(size)
        elif trial % 4 == 3:
            real = real * 10.0 ** rng.uniform(-200, 200)
            imag = imag * 10.0 ** rng.uniform(-3, 3) * np.abs(real).max()
        singular = np.linalg.svd(np.vstack([real, imag]), compute_uv=False)
        expected = int(np.sum(singular > RANK_TOLERANCE * max(float(singular[0]), 1e-300)))
        columns = [complex(a, b) for a, b in zip(real, imag, strict=True)]
        assert _rank_of_two_rows(columns) == expected
