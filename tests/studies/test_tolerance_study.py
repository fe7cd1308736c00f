"""``sso.tolerance_study``: seeded, reproducible, and equal to evaluating each sample directly."""

import json

import numpy as np
import pytest

import sso

# The paper's reported option-3 optimum (docs/model.md).
SERIES = sso.ShaftSeries([15.8362, 10.0, 15.8387], [90.0053, 89.9695])
PERCENTILES = (5.0, 50.0, 95.0)


def test_percentiles_equal_numpy_over_directly_evaluated_samples():
    result = sso.tolerance_study(SERIES, beta_tolerance_deg=[0.5, 0.3, 0.5],
                                 phase_tolerance_deg=2.0, samples=120, seed=11,
                                 percentiles=PERCENTILES, input_speed_rpm=25.0)
    # The documented draw, made here independently.
    generator = np.random.default_rng(11)
    beta_deg = np.array(SERIES.beta_deg) + generator.normal(0.0, [0.5, 0.3, 0.5], (120, 3))
    phase_deg = np.array(SERIES.phase_deg) + generator.normal(0.0, 2.0, (120, 2))
    np.testing.assert_array_equal(result.beta_deg, beta_deg)
    np.testing.assert_array_equal(result.phase_deg, phase_deg)
    evaluations = [sso.ShaftSeries(beta, phase).evaluate(25.0)
                   for beta, phase in zip(beta_deg, phase_deg, strict=True)]
    table = result.percentile_table()
    # Exact model: the same closed forms of the chain matrix, vectorised over the
    # samples in the study and for one design in evaluate(): equal to round-off.
    for metric, rtol in (("residual_error", 1e-12), ("fluctuation", 1e-12),
                         ("max_output_accel_rad_s2", 1e-12)):
        direct = np.array([getattr(evaluation, metric) for evaluation in evaluations])
        np.testing.assert_allclose(getattr(result, metric), direct, rtol=rtol)
        np.testing.assert_allclose(list(table[metric].values()),
                                   np.percentile(direct, PERCENTILES), rtol=rtol)
    assert result.nominal == SERIES.evaluate(25.0)


def test_the_same_seed_gives_the_same_numbers_for_any_chunking():
    first = sso.tolerance_study(SERIES, samples=500, seed=7, distribution="uniform")
    again = sso.tolerance_study(SERIES, samples=500, seed=7, distribution="uniform", chunk_size=77,
                          workers=1)
    other = sso.tolerance_study(SERIES, samples=500, seed=8, distribution="uniform")
    for metric in ("residual_error", "fluctuation", "max_output_accel_rad_s2"):
        np.testing.assert_array_equal(getattr(first, metric), getattr(again, metric))
    assert not np.array_equal(first.residual_error, other.residual_error)
    # Uniform deviations stay inside their half-widths (0.5 deg, 1 deg by default).
    assert np.max(np.abs(first.beta_deg - SERIES.beta_deg)) <= 0.5
    assert np.max(np.abs(first.phase_deg - SERIES.phase_deg)) <= 1.0


def test_zero_tolerance_gives_the_nominal_design_in_every_sample():
    result = sso.tolerance_study(SERIES, beta_tolerance_deg=0.0, phase_tolerance_deg=0.0, samples=4)
    np.testing.assert_allclose(result.residual_error, SERIES.evaluate().residual_error,
                               rtol=1e-12)


def test_one_joint_and_a_case_file_as_the_design(tmp_path):
    one_joint = sso.tolerance_study(sso.ShaftSeries([20.0]), samples=50, beta_tolerance_deg=0.1)
    assert one_joint.phase_deg.shape == (50, 0)
    cos_beta = np.cos(np.radians(one_joint.beta_deg[:, 0]))
    np.testing.assert_allclose(one_joint.fluctuation, 1 / cos_beta - cos_beta, rtol=1e-9)
    result = sso.tolerance_study("cases/paper_option3_exact.toml", samples=200, out_dir=tmp_path)
    assert {path.name for path in result.files} == {
        "tolerance.csv", "tolerance.json", "report.md", "report.html",
        "tolerance_histogram.png", "result.json"}
    summary = json.loads((tmp_path / "tolerance.json").read_text())
    assert summary["samples"] == 200
    assert summary["percentiles"]["residual_error"]["50"] == pytest.approx(
        float(np.percentile(result.residual_error, 50)), rel=1e-15)
    lines = (tmp_path / "tolerance.csv").read_text().splitlines()
    assert len(lines) == 201
    # tolerance.csv holds six significant digits; tolerance.json the full value.
    assert float(lines[1].split(",")[-3]) == pytest.approx(result.residual_error[0], rel=5e-6)
    assert lines[1].split(",")[-3] == f"{result.residual_error[0]:.6g}"


@pytest.mark.parametrize("keywords, message", [
    ({"beta_tolerance_deg": -1.0}, r"beta_tolerance_deg\[0\] = -1 is outside the allowed "
                                   r"range \[0, 45\] deg"),
    ({"phase_tolerance_deg": [1.0, 2.0, 3.0]}, "phase_tolerance_deg has 3 entries; give 1 or 2"),
    ({"distribution": "triangular"}, "distribution = 'triangular' is not one of"),
    ({"samples": 0}, r"samples = 0 is outside the allowed range \[1, 100000000\]"),
    ({"seed": -1}, "seed = -1 must be a whole number >= 0"),
    ({"percentiles": [50, 101]}, r"percentiles\[1\] = 101 is outside the allowed range"),
    ({"beta_tolerance_deg": 20.0}, r"beta_tolerance_deg\[2\] = 20 deg lets joint 2 \(beta "
                                   r"15.8387 deg\) reach 90 deg"),
    ({"input_speed_rpm": 0.0},
     r"input_speed_rpm = 0 is outside the allowed range \(0, 1e\+06\] rpm"),
])
def test_bad_input_is_refused_naming_the_field_and_range(keywords, message):
    with pytest.raises(ValueError, match=message):
        sso.tolerance_study(SERIES, **{"samples": 10, **keywords})


def test_a_tolerance_reaching_angles_float64_cannot_resolve_is_refused():
    """30 joints of 40 deg whose samples may reach 40 + 6 * 5 = 70 deg: a product of
    cosines of 1e-14, below the 1.37e-12 that 30 joints need (equal angles up to
    66.28 deg: docs/model.md, "Numerical limits"). 4 deg (64 deg) is accepted."""
    series = sso.ShaftSeries([40.0] * 30, [90.0] * 29)
    with pytest.raises(ValueError, match=r"^beta_tolerance_deg \(the angles beta \+ 6 \* "
                                         r"tolerance that samples may reach\): float64 cannot "
                                         r"resolve RE of a chain of 30 joints: .*equal angles "
                                         r"up to 66\.2756"):
        sso.tolerance_study(series, samples=10, beta_tolerance_deg=5.0)
    assert sso.tolerance_study(series, samples=10, beta_tolerance_deg=4.0).samples == 10


def test_a_case_tolerance_table_sets_the_study_and_arguments_override_it():
    case = {"design": {"beta_deg": [20.0, 30.0], "phase_deg": [90.0]},
            "tolerance": {"beta_deg": [0.1, 0.2], "distribution": "uniform", "samples": 30,
                          "seed": 5, "percentiles": [50, 90]}}
    from_table = sso.tolerance_study(case)
    assert (from_table.samples, from_table.seed, from_table.distribution) == (30, 5, "uniform")
    assert from_table.beta_tolerance_deg == (0.1, 0.2)
    assert from_table.phase_tolerance_deg == (1.0,)  # not in the table: the default
    assert from_table.percentiles == (50.0, 90.0)
    assert np.all(np.max(np.abs(from_table.beta_deg - [20.0, 30.0]), axis=0) <= [0.1, 0.2])
    overridden = sso.tolerance_study(case, samples=12, seed=6)
    assert (overridden.samples, overridden.seed) == (12, 6)


def test_a_study_of_an_optimisation_result_perturbs_its_optimum(tmp_path):
    # Two equal joints: the optimum phase is 90 deg and cancels exactly (docs/model.md).
    optimum = sso.optimise(sso.ShaftSeries([20.0, 20.0], [40.0], "exact"), 1, starts=1)
    result = sso.tolerance_study(optimum, samples=400, beta_tolerance_deg=0.5,
                           phase_tolerance_deg=1.0, out_dir=tmp_path / "study", plots=False)
    assert result.design == optimum.best.series
    assert result.study_of.startswith("the optimum (")
    assert result.nominal.residual_error < 1e-20
    # Every perturbed sample is worse than the exact cancellation.
    assert np.all(result.residual_error > result.nominal.residual_error)
    report = (tmp_path / "study" / "report.md").read_text()
    assert "Design studied: the optimum (" in report
    assert "| residual error RE (dimensionless) | < 1e-15 |" in report
    assert len(repr(result)) <= 400 and "<table>" in result._repr_html_()
    assert "design studied: the optimum" in result.summary()


def test_samples_below_zero_degrees_are_reflected_and_counted():
    # A joint at 0.2 deg with a 0.5 deg standard deviation: P(beta + d < 0) =
    # Phi(-0.4) = 0.3446, so about 34 % of the samples go below 0 and are reflected.
    result = sso.tolerance_study(sso.ShaftSeries([0.2]), samples=4000, beta_tolerance_deg=0.5,
                                 seed=1)
    assert result.reflected_samples / result.samples == pytest.approx(0.3446, abs=0.025)
    assert np.all(result.beta_deg >= 0.0)
    assert "reflected to |beta|: " + str(result.reflected_samples) in result.summary()


def test_exact_model_samples_agree_with_an_independent_quadrature():
    # The study takes RE and the fluctuation of the exact model from the chain
    # matrix's closed form (no quadrature angles); the rectangle rule on 2048 angles
    # of the angle-by-angle chain and a dense speed-ratio grid are the references.
    from sso._kinematics.hooke import chain_kinematics
    from sso._shafts.objective import residual_error

    result = sso.tolerance_study(SERIES, samples=40, seed=3, beta_tolerance_deg=2.0)
    assert result.quadrature_samples == 0
    theta = np.linspace(0.0, np.pi, 100_001)
    for row in range(0, 40, 7):
        beta = list(np.radians(result.beta_deg[row]))
        phase = list(np.radians(result.phase_deg[row]))
        assert result.residual_error[row] == pytest.approx(
            float(residual_error(beta, phase, "exact", 2048)), rel=1e-10, abs=1e-18)
        ratio = chain_kinematics(np, np.cos(theta), np.sin(theta), beta, phase, "exact").speed_ratio
        assert result.fluctuation[row] == pytest.approx(ratio.max() - ratio.min(), rel=1e-8)
