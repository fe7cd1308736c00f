"""Every computation is safe at the documented limits: a clear error or a correct result.

The limits: 64 joints (``sso._limits.MAX_JOINTS``, the most a case file takes) and
operating angles up to the largest float below 90 deg. Where float64 cannot resolve
a chain's RE (docs/model.md, "Numerical limits": rounding the ``2 n - 1`` angles by a
float spacing, 2^-50 rad, may move the residuals by up to
``(2 n - 1) 2^-50 / sqrt(2 prod cos beta)``, and that must stay within
sqrt(1e-15) = 3.2e-8), a design (or the upper bounds on free angles) is refused naming
the field. On generated cases ``sso validate`` and then ``sso evaluate`` / ``sso run``
agree: both refuse with exit 2, or validate accepts and the evaluation exits 0 with
figures equal to mpmath's at 700 digits. No run ends in an internal error.

The reference (:func:`reference_figures`) multiplies the chain matrix
``M = D_n R(phi_(n-1)) ... R(phi_1) D_1`` (``D_k = diag(1, cos beta_k)``, docs/model.md)
in mpmath and reads every figure off ``G = M^T M``; the ratio's slope peak is checked
against a direct numerical maximisation in mpmath below. It takes each angle in
radians exactly as the package converts it (one rounding of ``deg * pi / 180``,
1.1e-16 rad, smaller than half the spacing of floats at 90 deg, 7e-15 deg): what is
asserted is that nothing after that conversion loses accuracy.
"""

from __future__ import annotations

import json
import math
import re
import warnings
from typing import Any

import mpmath
import numpy as np
import pytest
from fuzzing import run_sso
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

import sso
from sso._cases.schema import load_case
from sso._limits import INPUT_MAGNITUDE_RANGE, MAX_JOINTS

LARGEST_BELOW_90 = math.nextafter(90.0, 0.0)
SPEED_RPM = 25.0
DIGITS = 700  # A - R = det^2 / (A + R) is a difference of numbers near 1 / det M

SPACING_RAD = 2.0**-50
"""Spacing of floats from 4 to 8 rad: the largest rounding of a phase (docs/model.md,
"Numerical limits"; ``math.ulp(2 * math.pi)`` is this)."""
RESOLUTION = math.sqrt(1e-15)
"""The residuals' rounding error sso allows: RE near zero to the round-off floor of
reports, 1e-15."""

CASES = settings(max_examples=30, deadline=None,
                 suppress_health_check=[HealthCheck.function_scoped_fixture])


def mp_radians(angle_deg: float) -> mpmath.mpf:
    return mpmath.mpf(math.radians(angle_deg))


def mp_chain_matrix(beta_deg: list[float], phase_deg: list[float]) -> mpmath.matrix:
    """``M = D_n R(phi_(n-1)) ... R(phi_1) D_1`` at mpmath's working precision."""
    matrix = mpmath.eye(2)
    for index, beta in enumerate(beta_deg):
        if index:
            phase = mp_radians(phase_deg[index - 1])
            matrix = mpmath.matrix([[mpmath.cos(phase), -mpmath.sin(phase)],
                                    [mpmath.sin(phase), mpmath.cos(phase)]]) * matrix
        matrix = mpmath.matrix([[1, 0], [0, mpmath.cos(mp_radians(beta))]]) * matrix
    return matrix


def reference_figures(beta_deg: list[float], phase_deg: list[float],
                      speed_rpm: float) -> dict[str, mpmath.mpf]:
    """The exact model's figures of one design, in mpmath at :data:`DIGITS` digits."""
    with mpmath.workdps(DIGITS):
        matrix = mp_chain_matrix(beta_deg, phase_deg)
        determinant = mpmath.det(matrix)
        gram = matrix.T * matrix
        # |M v|^2 = A + R cos(2 theta - delta) and the ratio is det / |M v|^2.
        mean = (gram[0, 0] + gram[1, 1]) / 2
        amplitude = mpmath.sqrt(((gram[0, 0] - gram[1, 1]) / 2) ** 2 + gram[0, 1] ** 2)
        return {
            "residual_error": mean / determinant - 1,  # |M|_F^2 / (2 det) - 1
            "speed_min_rpm": speed_rpm * determinant / (mean + amplitude),
            "speed_max_rpm": speed_rpm * determinant / (mean - amplitude),
            "fluctuation": determinant / (mean - amplitude) - determinant / (mean + amplitude),
            "max_output_accel_rad_s2": (mpmath.mpf(speed_rpm) * mpmath.pi / 30) ** 2
            * peak_slope(mean, amplitude, determinant),
        }


def peak_slope(mean: mpmath.mpf, amplitude: mpmath.mpf, determinant: mpmath.mpf) -> mpmath.mpf:
    """Largest ``|d ratio / d theta|`` of ``det / (A + R cos u)``, ``u = 2 theta - delta``:
    where ``R c^2 - A c - 2 R = 0`` for ``c = cos u`` (the slope's derivative vanishes)."""
    if amplitude == 0:
        return mpmath.mpf(0)
    cosine = (mean - mpmath.sqrt(mean**2 + 8 * amplitude**2)) / (2 * amplitude)
    return (2 * amplitude * determinant * mpmath.sqrt(1 - cosine**2)
            / (mean + amplitude * cosine) ** 2)


def scale_of(figure: str, speed_rpm: float) -> float:
    """The figure's size for a chain at rest, below which its error is measured absolutely."""
    return {"speed_min_rpm": speed_rpm, "speed_max_rpm": speed_rpm,
            "max_output_accel_rad_s2": (speed_rpm * math.pi / 30) ** 2}.get(figure, 1.0)


def assert_figures_match(evaluation: sso.Evaluation, beta_deg: list[float],
                         phase_deg: list[float], speed_rpm: float) -> None:
    # Measured over 500 random designs of 1 to 64 joints (and 200 near-cancelling
    # ones): the largest error was 4e-14 of the figure plus its scale.
    for figure, expected in reference_figures(beta_deg, phase_deg, speed_rpm).items():
        got = getattr(evaluation, figure)
        assert math.isfinite(got), (figure, got)
        assert abs(mpmath.mpf(got) - expected) <= 1e-12 * (abs(expected)
                                                            + scale_of(figure, speed_rpm)), (
            figure, got, float(expected))


def cosine_product_log10(beta_deg: list[float]) -> mpmath.mpf:
    with mpmath.workdps(50):
        return sum(mpmath.log10(mpmath.cos(mp_radians(beta))) for beta in beta_deg)


def rounding_bound(beta_deg: list[float]) -> float:
    """``(2 n - 1) SPACING_RAD / sqrt(2 prod cos beta)`` in mpmath: how far one rounding
    of every angle may move the residuals, whatever the phases (docs/model.md)."""
    with mpmath.workdps(50):
        product = mpmath.power(10, cosine_product_log10(beta_deg))
        return float((2 * len(beta_deg) - 1) * SPACING_RAD / mpmath.sqrt(2 * product))


def relative_bound(beta_deg: list[float]) -> float:
    """``(SPACING_RAD / 2) sum tan beta``: how far, relative to themselves, the residuals
    move through ``det M`` when the operating angles are rounded (docs/model.md)."""
    with mpmath.workdps(50):
        return float(SPACING_RAD / 2 * mpmath.fsum(mpmath.tan(mp_radians(beta))
                                                   for beta in beta_deg))


def refused(beta_deg: list[float]) -> bool | None:
    """Whether sso must refuse these operating angles; None within 1e-9 (relative) of
    either limit, where the float sums sso uses may fall either way."""
    ratios = (rounding_bound(beta_deg) / RESOLUTION, relative_bound(beta_deg) / RESOLUTION)
    if any(abs(ratio - 1.0) < 1e-9 for ratio in ratios):
        return None
    return max(ratios) > 1.0


def resolution_of(beta_deg: list[float], sqrt_re: float) -> float:
    """How far one rounding of every angle may move ``sqrt(RE)`` of a design of RE
    ``sqrt_re^2`` (docs/model.md, "Numerical limits")."""
    return rounding_bound(beta_deg) + sqrt_re * relative_bound(beta_deg)


def largest_equal_deg(joints: int) -> float:
    """The largest equal operating angle of ``joints`` joints sso accepts (mpmath)."""
    with mpmath.workdps(50):
        least = ((2 * joints - 1) * SPACING_RAD / mpmath.mpf(RESOLUTION)) ** 2 / 2
        return float(mpmath.degrees(mpmath.acos(least ** (mpmath.mpf(1) / joints))))


REFUSAL = r"float64 cannot resolve RE of a chain of {} joints?"


def test_the_reference_slope_is_the_numerical_maximum():
    """The closed form in :func:`peak_slope` against a search over the turn (mpmath)."""
    beta_deg, phase_deg = [35.0, 60.0, 20.0], [30.0, 75.0]
    figures = reference_figures(beta_deg, phase_deg, SPEED_RPM)
    with mpmath.workdps(40):
        matrix = mp_chain_matrix(beta_deg, phase_deg)
        determinant = mpmath.det(matrix)

        def ratio(theta):
            image = matrix * mpmath.matrix([mpmath.cos(theta), mpmath.sin(theta)])
            return determinant / (image[0] ** 2 + image[1] ** 2)

        def slope(theta):
            return mpmath.diff(ratio, theta)

        grid = [mpmath.pi * k / 720 for k in range(720)]
        start = max(grid, key=lambda theta: abs(slope(theta)))
        peak = mpmath.findroot(lambda theta: mpmath.diff(ratio, theta, 2), start)
        largest = abs(slope(peak)) * (mpmath.mpf(SPEED_RPM) * mpmath.pi / 30) ** 2
    assert float(largest) == pytest.approx(float(figures["max_output_accel_rad_s2"]), rel=1e-12)


def readable(value: float) -> float:
    """A number a case file takes: 0 or of magnitude 1e-100 to 1e100
    (``sso._limits.INPUT_MAGNITUDE_RANGE``)."""
    return value if abs(value) >= INPUT_MAGNITUDE_RANGE[0] else 0.0


def angles_deg() -> st.SearchStrategy[float]:
    """Operating angles over the whole allowed range, crowded towards 90 deg."""
    return st.one_of(
        st.floats(0.0, 90.0, exclude_max=True),
        st.floats(-14.0, 1.0).map(lambda power: 90.0 - 10.0**power),
        st.just(LARGEST_BELOW_90),
        st.sampled_from([0.0, 10.0, 45.0, 89.9, 89.99999]),
    ).map(lambda angle: readable(min(max(angle, 0.0), LARGEST_BELOW_90)))


@st.composite
def designs(draw: st.DrawFn) -> tuple[list[float], list[float]]:
    joints = draw(st.integers(1, MAX_JOINTS))
    beta_deg = draw(st.one_of(
        st.lists(angles_deg(), min_size=joints, max_size=joints),
        angles_deg().map(lambda angle: [angle] * joints),  # the issue's equal joints
        st.floats(-6.0, 1.0).map(  # equal joints at or just inside sso's limit
            lambda power: [readable(max(largest_equal_deg(joints) - 10.0**power, 0.0))] * joints),
    ))
    phase_deg = draw(st.lists(
        st.one_of(st.sampled_from([0.0, 90.0, 180.0]), st.floats(-360.0, 360.0).map(readable)),
        min_size=joints - 1, max_size=joints - 1))
    return beta_deg, phase_deg


def case_text(name: str, beta_deg: list[float], phase_deg: list[float], option: int,
              solvers: tuple[str, ...] = ("lm",), starts: int = 1) -> str:
    upper = max(beta_deg)
    return "\n".join([
        f'name = "{name}"', 'model = "exact"', f"option = {option}",
        f"input_speed_rpm = {SPEED_RPM!r}", "[design]",
        f"beta_deg = [{', '.join(repr(beta) for beta in beta_deg)}]",
        f"phase_deg = [{', '.join(repr(phase) for phase in phase_deg)}]",
        "[bounds]", f"beta_deg = [0.0, {upper!r}]", "phase_deg = [-90.0, 270.0]",
        "[solver]", f"solvers = [{', '.join(f'{name!r}' for name in solvers)}]".replace("'", '"'),
        f"starts = {starts}", "",
    ])


@CASES
@given(design=designs())
@example(design=([89.9] * 30, [0.0] * 29))  # the issue's: validated, then ZeroDivisionError
@example(design=([89.99999] * 12, [0.0] * 11))
@example(design=([89.99999] * 64, [90.0] * 63))
@example(design=([48.05] * 64, [0.0] * 31 + [270.0] + [0.0] * 31))  # at the 64-joint limit
@example(design=([89.9999965] * 2, [270.0]))  # at the 2-joint limit
def test_validate_then_evaluate_refuses_both_times_or_gives_the_exact_figures(tmp_path, design):
    beta_deg, phase_deg = design
    option = 1 if len(beta_deg) > 1 else 2
    path = tmp_path / "limit.toml"
    path.write_text(case_text("limit", beta_deg, phase_deg, option), encoding="utf-8")
    validated, said = run_sso(["validate", str(path)])
    evaluated, told = run_sso(["evaluate", str(path), "--out", str(tmp_path / "out"),
                               "--formats", "json", "--quiet"])
    assert "internal error" not in said + told
    assert (validated, evaluated) in ((0, 0), (2, 2)), said + told
    must_refuse = refused(beta_deg)
    assert must_refuse is None or (validated == 2) == must_refuse, said
    if validated == 2:
        assert re.search("beta_deg: " + REFUSAL.format(len(beta_deg)), said), said
        return
    case = load_case(path)
    assert_figures_match(case.series().evaluate(SPEED_RPM), beta_deg, phase_deg, SPEED_RPM)


PROBE_DIGITS = 200
"""Far more than the RE of any chain sso accepts needs: its matrix entries fall no lower
than sqrt(det M) (det M >= 3.9e-16, docs/model.md "Numerical limits") from partial
products of size up to 1, and RE is a difference from 1 (40 more digits for RE down
to 1e-40)."""

PROBE_STEPS_RAD = (1e-9, 1e-6, 1e-3)
"""Moves of one design variable tried around a reported optimum (rad)."""


def mp_residual_error(matrix: mpmath.matrix, cosine_product: mpmath.mpf) -> mpmath.mpf:
    """``|M|_F^2 / (2 det M) - 1``, with ``det M`` the product of the cosines."""
    return sum(matrix[i, j] ** 2 for i in range(2) for j in range(2)) / (2 * cosine_product) - 1


def chain_factors(beta: list[Any], phase: list[Any]) -> list[tuple[str, Any]]:
    """The chain's factors as ``(kind, angle)``, first applied first (angles in rad)."""
    factors = []
    for index, angle in enumerate(beta):
        if index:
            factors.append(("phase", phase[index - 1]))
        factors.append(("beta", angle))
    return factors


def mp_factor(kind: str, angle: Any) -> mpmath.matrix:
    """``D(beta)`` or the phase's rotation at mpmath's working precision (angle in rad,
    a float taken exactly)."""
    if kind == "beta":
        return mpmath.matrix([[1, 0], [0, mpmath.cos(angle)]])
    return mpmath.matrix([[mpmath.cos(angle), -mpmath.sin(angle)],
                          [mpmath.sin(angle), mpmath.cos(angle)]])


def mp_partial_products(factors: list[tuple[str, Any]]) -> tuple[list[Any], list[Any]]:
    """``before[k]``: the product of the factors before factor ``k`` (``before[-1]`` is the
    chain); ``after[k]``: the product of the factors from ``k`` on, last first."""
    before = [mpmath.eye(2)]
    for kind, angle in factors:
        before.append(mp_factor(kind, angle) * before[-1])
    after = [mpmath.eye(2)]
    for kind, angle in reversed(factors):
        after.append(after[-1] * mp_factor(kind, angle))
    after.reverse()
    return before, after


def lowest_neighbour_re(beta_deg: list[float], phase_deg: list[float], option: int,
                        beta_bounds_deg: tuple[float, float],
                        phase_bounds_deg: tuple[float, float]) -> tuple[float, float]:
    """The RE of a design and the lowest RE of the designs one free variable away by
    :data:`PROBE_STEPS_RAD` (either way, within the bounds), in mpmath.

    Each neighbour's chain matrix is ``L_k X_k R_k``: the products of the factors after
    and before the moved one (``D(beta)`` or the phase's rotation), computed once.
    """
    with mpmath.workdps(PROBE_DIGITS):
        factors = chain_factors([mp_radians(beta) for beta in beta_deg],
                                [mp_radians(phase) for phase in phase_deg])
        before, after = mp_partial_products(factors)
        moves = []
        cosines = [mpmath.cos(angle) for kind, angle in factors if kind == "beta"]
        product = mpmath.fprod(cosines)
        at_design = mp_residual_error(before[-1], product)
        beta_free, phase_free = option in (2, 3), option in (1, 3)
        lowest = at_design
        for position, (kind, angle) in enumerate(factors):
            if not (beta_free if kind == "beta" else phase_free):
                continue
            low, high = (beta_bounds_deg if kind == "beta" else phase_bounds_deg)
            for step in PROBE_STEPS_RAD:
                for moved in (angle - step, angle + step):
                    if not mp_radians(low) <= moved <= mp_radians(high):
                        continue
                    matrix = after[position + 1] * mp_factor(kind, moved) * before[position]
                    moved_product = (product / mpmath.cos(angle) * mpmath.cos(moved)
                                     if kind == "beta" else product)
                    moves.append(mp_residual_error(matrix, moved_product))
        if moves:
            lowest = min(lowest, min(moves))
        return float(at_design), float(lowest)


def test_the_neighbour_probe_finds_a_lower_design_and_none_at_a_minimum():
    """The probe itself: from the conventional phasing of three equal joints (RE 0 at
    phases of 90 deg only for pairs, so above zero for three, and a minimum) no move
    helps; one phase 10 deg off, a move of 1e-3 rad does."""
    at_minimum = lowest_neighbour_re([30.0, 30.0], [90.0], 1, (0.0, 89.0), (-90.0, 270.0))
    assert at_minimum[0] == pytest.approx(0.0, abs=1e-30)
    assert at_minimum[1] >= at_minimum[0]
    off = lowest_neighbour_re([30.0, 30.0], [80.0], 1, (0.0, 89.0), (-90.0, 270.0))
    assert off[1] < off[0] * (1 - 1e-4)


def assert_no_neighbour_lower(at_design: float, lowest: float, beta_deg: list[float]) -> None:
    """No neighbour's RE below the design's by more than the solver's tolerance (1e-6
    relative, 1e-15) or than float64 resolves at these angles: a design reported in
    degrees was found by a float evaluation (one rounding per factor) and went through
    degrees and back (up to 1.6 spacings of its angles), so its sqrt(RE) is known to
    within three times :func:`resolution_of` (docs/model.md, "Numerical limits")."""
    # mpmath's RE of a cancelling design may come out a few units of its last digit
    # below zero
    root_at, root_lowest = math.sqrt(max(at_design, 0.0)), math.sqrt(max(lowest, 0.0))
    resolution = resolution_of(beta_deg, root_at)
    assert (lowest >= at_design * (1 - 1e-6) - 1e-15
            or root_at <= root_lowest + 3 * resolution), (at_design, lowest, resolution)


def assert_a_minimum_as_reported(result: dict[str, Any], option: int, upper_deg: float) -> None:
    """A run that says it succeeded reports a design whose RE is mpmath's, and that no
    move of one free variable improves (a reported success that a neighbour beats is
    the false success of the issue: 12 joints at 89.9999999998 deg once ended as
    "solved" with RE 7.7e100)."""
    optimisation = result["optimisation"]
    design = optimisation["best"]["series"]
    reported = optimisation["optimum"]["residual_error"]
    at_design, lowest = lowest_neighbour_re(design["beta_deg"], design["phase_deg"], option,
                                            (0.0, upper_deg), (-90.0, 270.0))
    assert reported == pytest.approx(at_design, rel=1e-9, abs=1e-15), (reported, at_design)
    assert_no_neighbour_lower(at_design, lowest, design["beta_deg"])


@settings(max_examples=8, deadline=None,
          suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(design=designs(), option=st.sampled_from([1, 2, 3]),
       solvers=st.sampled_from([("lm",), ("ipopt", "slsqp")]))
@example(design=([30.0, 40.0, 35.0], [10.0, 20.0]), option=3, solvers=("ipopt", "slsqp"))
@example(design=([89.6] * 64, [0.0] * 63), option=1, solvers=("lm",))
def test_validate_then_run_refuses_both_times_or_reports_a_true_minimum(tmp_path, design,
                                                                        option, solvers):
    """``sso run`` (``sso.optimise``) on what ``sso validate`` accepted: exit 0 with a
    design no neighbour beats, or exit 1 with the failure said; never a false success."""
    beta_deg, phase_deg = design
    option = option if len(beta_deg) > 1 else 2
    path = tmp_path / "limit.toml"
    path.write_text(case_text("limit", beta_deg, phase_deg, option, solvers), encoding="utf-8")
    validated, said = run_sso(["validate", str(path)])
    ran, told = run_sso(["run", str(path), "--out", str(tmp_path / "out"),
                         "--formats", "json", "--quiet"])
    assert "internal error" not in said + told
    if validated == 2:
        assert ran == 2, told
        return
    assert validated == 0 and ran in (0, 1), said + told
    result = json.loads((tmp_path / "out" / "limit" / "result.json").read_text(encoding="utf-8"))
    if ran == 1:
        assert "solver failed" in told or "solvers disagree" in told, told
        return
    assert_a_minimum_as_reported(result, option, max(beta_deg))


def test_the_issues_designs():
    """Issue reproductions: 30 joints of 89.9 deg (phases 0), 12 and 64 of 89.99999 deg
    are refused naming the field, the least product and the largest equal angle; 30 and
    12 joints at their largest equal angles evaluate to the exact figures."""
    # cos(89.99999 deg) = 1.745329e-7, and its 64th power is 3.02e-433; 64 joints need
    # ((127 * 2^-50 / sqrt(1e-15))^2 / 2 = 6.36e-12, equal angles up to 48.05 deg.
    with pytest.raises(ValueError, match=r"^beta_deg: float64 cannot resolve RE of a chain of 64 "
                                         r"joints: the product of cos\(beta\) is 3\.02e-433, "
                                         r".*64 joints need a product of at least 6\.36e-12 "
                                         r"\(equal angles up to 48\.05\d+ deg\)"):
        sso.ShaftSeries([89.99999] * 64, [90.0] * 63)
    for joints, angle_deg in ((30, 89.9), (12, 89.99999)):
        with pytest.raises(ValueError, match=REFUSAL.format(joints)):
            sso.ShaftSeries([angle_deg] * joints, [0.0] * (joints - 1))
        largest = largest_equal_deg(joints)  # 66.2757 deg for 30, 84.9654 deg for 12
        accepted = largest - 1e-6
        evaluation = sso.ShaftSeries([accepted] * joints, [0.0] * (joints - 1)).evaluate(SPEED_RPM)
        assert_figures_match(evaluation, [accepted] * joints, [0.0] * (joints - 1), SPEED_RPM)
        with pytest.raises(ValueError, match=REFUSAL.format(joints)):
            sso.ShaftSeries([largest + 1e-6] * joints, [0.0] * (joints - 1))


@pytest.mark.parametrize("solvers", [("lm",), ("ipopt", "slsqp")])
def test_twelve_joints_at_their_limit_never_end_in_a_false_success(tmp_path, solvers):
    """The issue's false success: 12 joints at 89.9999999998 deg, option 1, from phases
    of 0, once ended "solved" with RE 7.7e100; float64 cannot resolve RE there and the
    case is refused. At the largest angle 12 joints may have (84.9654 deg) the run
    exits 1 with the failure said, or reports a design no neighbour beats."""
    refused_case = tmp_path / "refused.toml"
    refused_case.write_text(case_text("refused", [89.9999999998] * 12, [0.0] * 11, 1, solvers),
                            encoding="utf-8")
    code, said = run_sso(["validate", str(refused_case)])
    assert code == 2 and re.search(REFUSAL.format(12), said), said
    angle_deg = math.floor(largest_equal_deg(12) * 1e4) / 1e4
    path = tmp_path / "limit.toml"
    path.write_text(case_text("limit", [angle_deg] * 12, [0.0] * 11, 1, solvers),
                    encoding="utf-8")
    assert run_sso(["validate", str(path)])[0] == 0
    ran, told = run_sso(["run", str(path), "--out", str(tmp_path / "out"), "--formats", "json",
                         "--quiet"])
    result = json.loads((tmp_path / "out" / "limit" / "result.json").read_text(encoding="utf-8"))
    assert ran in (0, 1), told
    if ran == 0:
        assert_a_minimum_as_reported(result, 1, angle_deg)
    else:
        assert "solver failed" in told or "solvers disagree" in told, told


def assert_batch_rows_true_minima(beta_deg: np.ndarray, phase_deg: np.ndarray, option: int,
                                  upper_deg: float) -> sso.BatchResult:
    """Every row of ``sso.optimise_batch`` that says it converged is a design no
    neighbour beats (mpmath, :func:`assert_no_neighbour_lower`); the others say why
    they did not."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = sso.optimise_batch(beta_deg, phase_deg, option=option,
                                    beta_bounds_deg=(0.0, upper_deg),
                                    phase_bounds_deg=(-90.0, 270.0))
    for row in range(len(beta_deg)):
        if not result.success[row]:
            assert result.message[row], row
            continue
        at_design, lowest = lowest_neighbour_re(result.beta_deg[row].tolist(),
                                                result.phase_deg[row].tolist(), option,
                                                (0.0, upper_deg), (-90.0, 270.0))
        assert_no_neighbour_lower(at_design, lowest, result.beta_deg[row].tolist())
    return result


def test_optimise_batch_at_the_limit_never_reports_a_false_success():
    """12 joints at 89.9999999998 deg, option 1, from phases of 0, 90 and a spread: the
    batched solver once called all three converged, at RE 5.5e89, 5.4e-9 and 1.4e107.
    Refused now; at the 12-joint limit (84.9654 deg) every row is a minimum or says why
    not."""
    phase_deg = np.stack([np.zeros(11), np.full(11, 90.0), np.linspace(0.0, 170.0, 11)])
    with pytest.raises(ValueError, match=r"^beta_deg\[0\]: " + REFUSAL.format(12)):
        sso.optimise_batch(np.full((3, 12), 89.9999999998), phase_deg, option=1)
    angle_deg = math.floor(largest_equal_deg(12) * 1e4) / 1e4
    assert_batch_rows_true_minima(np.full((3, 12), angle_deg), phase_deg, 1, angle_deg)


@settings(max_examples=10, deadline=None)
@given(design=designs(), option=st.sampled_from([1, 2, 3]))
def test_optimise_batch_of_what_validate_accepts_is_refused_or_a_true_minimum(design, option):
    """What ``sso validate`` refuses (angles, or upper bounds on free angles, with which
    float64 cannot resolve RE), ``optimise_batch`` refuses naming the field; anything
    else ends in rows that are minima or say why not. (A design of option 1 below the
    earlier floor once ended in numpy's LinAlgError "Singular matrix", and 16 joints of
    89.99999 deg, above that floor, in a reported success at RE 1.7e-4 where mpmath
    gives 5.6e8.)"""
    beta_deg, phase_deg = design
    option = option if len(beta_deg) > 1 else 2
    chain = beta_deg if option == 1 else [max(beta_deg)] * len(beta_deg)
    must_refuse = refused(chain)
    field = r"beta_deg\[0\]" if option == 1 else r"beta_bounds_deg \(their upper bounds\)"
    try:
        assert_batch_rows_true_minima(np.array([beta_deg]), np.array([phase_deg]).reshape(1, -1),
                                      option, max(beta_deg))
    except ValueError as error:
        assert must_refuse is not False, error
        assert re.match(f"^{field}: {REFUSAL.format(len(beta_deg))}", str(error)), error
    else:
        assert must_refuse is not True


def test_sixteen_joints_near_90_deg_are_refused_or_a_true_minimum():
    """The design hypothesis found for the test above: 16 joints of 89.99999 deg, option
    1, passed the earlier floor on the cosines' product (7e-109 > 1e-140), and
    optimise_batch reported success at RE 1.7e-4 where mpmath gives 5.6e8 at the
    returned design and 3.0e8 one variable away. Float64 cannot resolve RE there
    (rounding moves sqrt(RE) by up to 2.3e40), so it is refused; at the 16-joint limit
    (80.3652 deg) the same phases end in minima."""
    phase_deg = [0.0, 0.0, 90.0, 268.0, 90.0, 87.5, 90.0, 0.0, 0.0, 270.0, 0.0, 0.0, 90.0,
                 0.0, 0.0]
    with pytest.raises(ValueError, match=r"^beta_deg\[0\]: " + REFUSAL.format(16)
                       + r".* by up to 2\.3e\+40, above the allowed 3\.2e-08"):
        assert_batch_rows_true_minima(np.array([[89.99999] * 16]), np.array([phase_deg]), 1,
                                      89.99999)
    angle_deg = math.floor(largest_equal_deg(16) * 1e4) / 1e4
    assert angle_deg == 80.3652
    assert_batch_rows_true_minima(np.array([[angle_deg] * 16]), np.array([phase_deg]), 1,
                                  angle_deg)


GRID_JOINTS = (2, 3, 4, 8, 16, 32, 64)


def mp_residual_moves(beta_rad: list[float], phase_rad: list[float],
                      moving: bool = True) -> tuple[float, list[float]]:
    """``sqrt(RE)`` of a design given in radians and (if ``moving``) how far ``r`` moves
    when each of its angles, one at a time, goes to the next float up (mpmath, 60
    digits; the chain through prefix and suffix products)."""
    with mpmath.workdps(60):
        kinds = chain_factors(beta_rad, phase_rad)
        before, after = mp_partial_products(kinds)
        product = mpmath.fprod(mpmath.cos(mpmath.mpf(beta)) for beta in beta_rad)

        def residual(matrix: mpmath.matrix, determinant: mpmath.mpf) -> tuple[Any, Any]:
            scale = 1 / mpmath.sqrt(2 * determinant)
            return (matrix[0, 0] - matrix[1, 1]) * scale, (matrix[0, 1] + matrix[1, 0]) * scale

        first, second = residual(before[-1], product)
        moves = []
        for position, (kind, angle) in enumerate(kinds if moving else []):
            moved = math.nextafter(angle, math.inf)
            determinant = (product / mpmath.cos(mpmath.mpf(angle)) * mpmath.cos(mpmath.mpf(moved))
                           if kind == "beta" else product)
            one, two = residual(after[position + 1] * mp_factor(kind, moved) * before[position],
                                determinant)
            moves.append(float(mpmath.sqrt((one - first) ** 2 + (two - second) ** 2)))
        return float(mpmath.sqrt(first**2 + second**2)), moves


def worst_phasing(joints: int) -> list[float]:
    """Phases of 0 but one of 270 deg in the middle: ``M = diag(1, a) R diag(1, b)``,
    whose residuals move by ``2^-50 / sqrt(2 det M)`` per float step of that phase, a
    ``(2 n - 1)``-th of the bound (docs/model.md)."""
    phase_deg = [0.0] * (joints - 1)
    if phase_deg:
        phase_deg[(joints - 1) // 2] = 270.0
    return phase_deg


@pytest.mark.parametrize("joints", GRID_JOINTS)
def test_accepted_chains_resolve_re_within_the_stated_tolerance(joints):
    """On a grid up to the largest accepted equal angle (and one of mixed angles at the
    limit), over phasings of 0, of 90 deg, of the worst case and seeded random ones,
    and over what ``optimise_batch`` returns from them: every figure is mpmath's to
    1e-12 of its size (at the same radians), a float step of any one angle moves the
    residuals by at most ``2^-50 / sqrt(2 prod cos beta)`` (the per-factor bound of
    docs/model.md, plus ``sqrt(RE) (2^-50 / 2) tan beta`` for a bend) and all of them
    together by at most the refusal's bounds, 3.2e-8 plus 3.2e-8 of ``sqrt(RE)``; the
    batch's reported RE is mpmath's at its reported design to within that resolution
    (``|sqrt(RE) - sqrt(RE_mpmath)|`` at most three times it)."""
    rng = np.random.default_rng(joints)
    largest = largest_equal_deg(joints)
    # Every other joint at 30 deg, the others at the angle that puts the chain at the
    # nearer of the two limits (the sum of tangents binds for 2 joints).
    lower = joints // 2
    with mpmath.workdps(50):
        least = ((2 * joints - 1) * SPACING_RAD / mpmath.mpf(RESOLUTION)) ** 2 / 2
        cosine = (least * (1 + 1e-9) / mpmath.cos(mpmath.radians(30)) ** lower) ** (
            mpmath.mpf(1) / (joints - lower))
        tangent = ((2 * RESOLUTION / SPACING_RAD - lower * mpmath.tan(mpmath.radians(30)))
                   / (joints - lower) * (1 - 1e-6))
        steep = float(min(mpmath.degrees(mpmath.acos(cosine)),
                          mpmath.degrees(mpmath.atan(tangent))))
    mixed = [30.0 if index % 2 else steep for index in range(joints)]
    chains = [[0.9 * largest] * joints, [largest - 1e-6] * joints, mixed]
    for beta_deg in chains:
        bound = rounding_bound(beta_deg)
        assert bound <= RESOLUTION and relative_bound(beta_deg) <= RESOLUTION
        phasings = [[0.0] * (joints - 1), [90.0] * (joints - 1), worst_phasing(joints),
                    *rng.uniform(-90.0, 270.0, size=(2, joints - 1)).tolist()]
        for phase_deg in phasings:
            evaluation = sso.ShaftSeries(beta_deg, phase_deg).evaluate(SPEED_RPM)
            assert_figures_match(evaluation, beta_deg, phase_deg, SPEED_RPM)
            size, moves = mp_residual_moves([math.radians(beta) for beta in beta_deg],
                                            [math.radians(phase) for phase in phase_deg])
            for position, move in enumerate(moves):  # bends at even positions
                through_det = (size * SPACING_RAD / 2 * math.tan(math.radians(
                    beta_deg[position // 2])) if position % 2 == 0 else 0.0)
                assert move <= (bound / (2 * joints - 1) + through_det) * (1 + 1e-9), (
                    position, move, bound, through_det)
            assert sum(moves) <= resolution_of(beta_deg, size)
        if joints == 1:
            continue
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            batch = sso.optimise_batch([beta_deg] * len(phasings), phasings, option=1)
        for row in np.flatnonzero(batch.success):
            at_design, _ = mp_residual_moves(np.radians(batch.beta_deg[row]).tolist(),
                                             np.radians(batch.phase_deg[row]).tolist(), False)
            assert abs(math.sqrt(batch.fun[row]) - at_design) <= 3 * resolution_of(
                beta_deg, at_design), (beta_deg[0], row, batch.fun[row], at_design**2)


def test_the_limit_is_within_a_factor_2n_minus_1_of_where_float64_stops_resolving_re():
    """The worst phasing's residuals move by a float step of its 270 deg phase exactly as
    docs/model.md derives, ``2^-50 / sqrt(2 det M)``: a (2 n - 1)-th of the refusal's
    bound. That step reaches the allowed 3.2e-8 where ``det M = (2^-50 / 3.2e-8)^2 / 2``:
    for 16 equal joints at 83.7449 deg and for 64 at 54.9333 deg, against limits of
    80.3653 and 48.0540 deg. Between each pair the refusal is conservative; beyond the
    second, float64 does not resolve RE for that phasing."""
    cases = ((2, 89.9999965863, 89.9999988621), (16, 80.3653, 83.7449),
             (64, 48.0540, 54.9333))
    for joints, limit_deg, resolving_deg in cases:
        assert largest_equal_deg(joints) == pytest.approx(limit_deg, abs=1e-4)
        with mpmath.workdps(50):
            least = (SPACING_RAD / mpmath.mpf(RESOLUTION)) ** 2 / 2
            stops_deg = float(mpmath.degrees(mpmath.acos(least ** (mpmath.mpf(1) / joints))))
        assert stops_deg == pytest.approx(resolving_deg, abs=1e-4)
        for beta_deg in ([limit_deg] * joints, [stops_deg] * joints):
            phase_rad = [math.radians(phase) for phase in worst_phasing(joints)]
            _, moves = mp_residual_moves([math.radians(beta) for beta in beta_deg], phase_rad)
            middle = 2 * ((joints - 1) // 2) + 1  # the 270 deg phase among the factors
            expected = SPACING_RAD / math.sqrt(2 * 10 ** float(cosine_product_log10(beta_deg)))
            assert moves[middle] == pytest.approx(expected, rel=1e-3)
            assert max(moves) == moves[middle]
        assert moves[middle] == pytest.approx(RESOLUTION, rel=1e-3)
        with pytest.raises(ValueError, match=REFUSAL.format(joints)):
            sso.ShaftSeries([stops_deg] * joints, worst_phasing(joints))


def test_free_angles_whose_upper_bounds_float64_cannot_resolve_are_refused():
    """The optimiser can walk to the upper bounds, so they are checked as a chain."""
    series = sso.ShaftSeries([10.0] * 64, [90.0] * 63)
    for upper_deg in (89.9, largest_equal_deg(64) + 1e-6):
        with pytest.raises(ValueError, match=r"^beta_bounds_deg \(their upper bounds\): "
                                             + REFUSAL.format(64)):
            sso.optimise(series, 3, beta_bounds_deg=(0.0, upper_deg))
        with pytest.raises(ValueError, match=r"^beta_bounds_deg \(their upper bounds\): "
                                             + REFUSAL.format(64)):
            sso.optimise_batch([[10.0] * 64], [[90.0] * 63], option=2,
                               beta_bounds_deg=(0.0, upper_deg))
    # Option 1 keeps the angles, so their bounds are not the chain's.
    assert sso.optimise(series, 1, beta_bounds_deg=(0.0, 89.9), solvers="lm", starts=1).success


def zigzag_mm(joints: int, offset_mm: float) -> list[list[float]]:
    """Points of a planar zigzag: every joint bent by ``2 atan(2 offset / 100)``."""
    return [[0.0, 0.0, 0.0]] + [[100.0 * (index + 1), offset_mm * (2 * (index % 2) - 1), 0.0]
                                for index in range(joints + 1)]


def test_a_thousand_joint_zigzag_column_is_refused_or_evaluated_exactly():
    steep = zigzag_mm(1000, 30.0)  # 1000 joints of 61.9 deg: product 1e-327
    with pytest.raises(ValueError, match=r"points_mm \(the operating angles they give\): "
                                         + REFUSAL.format(1000)):
        sso.ColumnGeometry(steep)
    # 11.4 deg each: product 2.6e-9, above the 1.6e-9 that 1000 joints need
    gentle = sso.ColumnGeometry(zigzag_mm(1000, 5.0))
    series = gentle.series()
    assert_figures_match(series.evaluate(SPEED_RPM), list(series.beta_deg),
                         list(series.phase_deg), SPEED_RPM)
    verdict = sso.can_cancel(gentle.beta_deg)
    assert verdict.possible and verdict.minimum_residual_error == 0.0


def test_coordinates_beyond_1e100_mm_are_refused_naming_the_coordinate():
    huge = [[0.0, 0.0, 0.0], [1.4e154, 0.0, 0.0], [2.8e154, 1.4e154, 0.0],
            [4.2e154, 1.4e154, 1.4e154]]
    with pytest.raises(ValueError, match=r"points_mm\[1\]\[0\] = 1\.4e\+154 mm is outside "
                                         r"the allowed range \[-1e\+100, 1e\+100\] mm"):
        sso.ColumnGeometry(huge)
    # At the limit the geometry is that of the same column in millimetres (scale-free).
    scaled = sso.ColumnGeometry([[coordinate * 1e99 / 1.4e154 for coordinate in point]
                                 for point in huge])
    unit = sso.ColumnGeometry([[coordinate / 1.4e154 for coordinate in point] for point in huge])
    assert scaled.beta_deg == pytest.approx(unit.beta_deg, rel=1e-14)
    assert scaled.plane_angle_deg == pytest.approx(unit.plane_angle_deg, rel=1e-14)
    assert scaled.shaft_length_mm == pytest.approx(
        [length * 1e99 for length in unit.shaft_length_mm], rel=1e-14)


@settings(max_examples=60, deadline=None)
@given(first=st.floats(0.0, 88.9), step_exponent=st.floats(-15.0, 0.0),
       others=st.lists(st.floats(0.0, 60.0), max_size=3))
def test_can_cancel_keeps_its_digits_for_nearly_equal_angles(first, step_exponent, others):
    """``can_cancel([10, 10 + 1e-13])`` once gave minimum_residual_error 0 beside
    possible=False (cancellation in cosh(d) - 1). Margin and least RE against mpmath."""
    beta_deg = [first, first + 10.0**step_exponent, *others]
    verdict = sso.can_cancel(beta_deg)
    with mpmath.workdps(200):  # cosh(d) - 1 of d down to 1e-30 keeps 140 digits
        cosines = [mpmath.cos(mpmath.radians(mpmath.mpf(beta))) for beta in beta_deg]
        largest = max(range(len(beta_deg)), key=lambda index: beta_deg[index])
        product = mpmath.fprod(cosine for index, cosine in enumerate(cosines)
                               if index != largest)
        margin = cosines[largest] - product
        least = (mpmath.cosh(mpmath.log(product / cosines[largest])) - 1 if margin < 0
                 else mpmath.mpf(0))
    assert verdict.possible == (margin >= 0) or abs(margin) < 1e-16
    if len(beta_deg) == 2:  # the difference of two cosines is exact in the angles
        assert float(margin) == pytest.approx(verdict.margin, rel=1e-12, abs=1e-300)
        assert float(least) == pytest.approx(verdict.minimum_residual_error, rel=1e-9,
                                             abs=1e-300)
    else:  # from the rounded cosines: within a few of their rounding errors (1.1e-16)
        assert abs(float(margin) - verdict.margin) <= 1e-15
    assert (verdict.minimum_residual_error > 0.0) == (not verdict.possible)
