"""``sso.optimise_batch``: many shaft-series designs of one shape optimised at once.

The exact model's residual error is the squared norm of two residuals of the chain
matrix (``sso._kinematics.hooke_matrix``), so ``m`` starts form ``m`` tiny
least-squares problems that the ``"lm"`` solver's rules solve together as array work
(:mod:`sso._solvers.lm_batch`; compiled to machine code for a shape solved often,
:mod:`sso._solvers.lm_native`): no quadrature, no per-design Python loop, and the
iterates of a single ``sso.optimise(..., solvers="lm")`` solve. The
paper's model has no closed form and is refused here (use :func:`sso.optimise`);
falling back to a per-design quadrature solve would silently change the speed a
caller relies on.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, fields
from importlib import import_module
from typing import Any

import numpy as np

from sso._display import Part, Readable, TextTable, format_number, format_numbers
from sso._kinematics.hooke import MODELS
from sso._kinematics.hooke_matrix import (
    ratio_extremes,
    residual_jacobian,
    residuals_and_jacobian_numpy,
)
from sso._limits import (
    BETA_LIMIT_DEG,
    DEFAULT_BETA_BOUNDS_DEG,
    DEFAULT_INPUT_SPEED_RPM,
    DEFAULT_MAX_ITERATIONS,
    DEFAULT_OPTION,
    DEFAULT_PHASE_BOUNDS_DEG,
    DEFAULT_SHAFT_SOLVER_TOL,
    MAX_ITERATIONS,
)
from sso._record import Record
from sso._shafts.options import (
    OPTION_FIXED_PHASE_DEG,
    StartMovedWarning,
    build_problem,
    free_angles,
    validate_option_and_bounds,
)
from sso._shafts.problem import compiled_nlp, native_shape
from sso._solvers import round_off_stops
from sso._solvers.least_squares import STATUS_MESSAGES, SUCCESS_STATUSES, batch_least_squares
from sso._solvers.lm_batch import solve_batch
from sso._solvers.lm_native import (
    NativeSolver,
    native_solver_of,
    rows_of,
    solve_native_leaving_saddles,
)
from sso._solvers.lm_rules import NEWTON, NEWTON_INDEFINITE
from sso._solvers.resources import (
    batch_estimate,
    batch_least_squares_mb,
    check_memory,
)
from sso._solvers.resources import memory_limit_mb as resolve_memory_limit
from sso._validation import (
    check_chain_conditioning,
    check_choice,
    unresolvable_chains,
    validate_count,
    validate_solver_tol,
    validate_speed,
)

SUMMARY_ROWS = 5
"""Designs a batch's summary lists (the lowest RE first)."""
ZERO_RESIDUAL_LEVEL = 1e-20
"""RE at or below this is round-off zero: a global minimum, needing no Newton steps or
saddle check (the batched least squares' default)."""


@dataclass(frozen=True, eq=False, repr=False)
class BatchResult(Record, Readable):
    """Optimised designs of a batch, one row per start.

    Attributes
    ----------
    fun : numpy.ndarray of shape (m,)
        Residual error RE of each optimised design (dimensionless, exact model,
        closed form).
    beta_deg : numpy.ndarray of shape (m, n)
        Operating angles of each design, deg (option 1: the given ones).
    phase_deg : numpy.ndarray of shape (m, n - 1)
        Relative phases, deg (option 2: 90 deg).
    success : numpy.ndarray of shape (m,)
        Whether the solver converged for that start.
    status : numpy.ndarray of shape (m,)
        Stopping reason, a key of :data:`sso._solvers.least_squares.STATUS_MESSAGES`.
    nit, nfev : numpy.ndarray of shape (m,)
        Iterations and residual evaluations of each start.
    kkt : numpy.ndarray of shape (m,)
        Infinity norm of RE's projected gradient under the bounds (per rad), the
        first-order optimality measure of :class:`sso.Solution`.
    speed_min_rpm, speed_max_rpm : numpy.ndarray of shape (m,)
        Output speed extremes over a turn at ``input_speed_rpm``.
    option : int
    model : str
    input_speed_rpm : float
    beta_bounds_deg, phase_bounds_deg : tuple of (float, float)
        Per-joint / per-phase bounds used, deg.
    """

    fun: np.ndarray
    beta_deg: np.ndarray
    phase_deg: np.ndarray
    success: np.ndarray
    status: np.ndarray
    nit: np.ndarray
    nfev: np.ndarray
    kkt: np.ndarray
    speed_min_rpm: np.ndarray
    speed_max_rpm: np.ndarray
    option: int
    model: str
    input_speed_rpm: float
    beta_bounds_deg: tuple[tuple[float, float], ...]
    phase_bounds_deg: tuple[tuple[float, float], ...]

    def _repr_text(self) -> str:
        best = int(np.argmin(self.fun)) if len(self.fun) else None
        lowest = "" if best is None else (f", lowest RE {format_number(self.fun[best], 4)} at "
                                          f"start {best}")
        return (f"{len(self.fun)} starts, option {self.option}, {self.model} model, "
                f"{int(np.count_nonzero(self.success))} converged{lowest}")

    def _summary_parts(self) -> list[Part]:
        order = np.argsort(self.fun, kind="stable")[:SUMMARY_ROWS]
        rows = tuple((str(int(index)), format_numbers(self.beta_deg[index]),
                      format_numbers(self.phase_deg[index]), format_number(self.fun[index]),
                      "yes" if self.success[index] else "no") for index in order)
        title = (f"Batch of {len(self.fun)} starts, option {self.option}, {self.model} model: "
                 f"{int(np.count_nonzero(self.success))} converged; the {len(order)} lowest RE:")
        return [title, TextTable(("start", "beta (deg)", "phase (deg)", "RE", "converged"), rows)]

    @property
    def message(self) -> tuple[str, ...]:
        """Each start's stopping reason in words."""
        return tuple(STATUS_MESSAGES[int(code)] for code in self.status)

    def to_columns(self) -> dict[str, np.ndarray]:
        """One flat column per figure (``beta_deg_1 .. beta_deg_n``, ``phase_deg_1 ..``)."""
        columns: dict[str, np.ndarray] = {"fun": self.fun}
        for index in range(self.beta_deg.shape[1]):
            columns[f"beta_deg_{index + 1}"] = self.beta_deg[:, index]
        for index in range(self.phase_deg.shape[1]):
            columns[f"phase_deg_{index + 1}"] = self.phase_deg[:, index]
        for name in ("success", "status", "nit", "nfev", "kkt", "speed_min_rpm",
                     "speed_max_rpm"):
            columns[name] = getattr(self, name)
        return columns

    def to_frame(self) -> Any:
        """The columns of :meth:`to_columns` as a ``pandas.DataFrame``.

        Raises
        ------
        ImportError
            If pandas is not installed (sso does not depend on it; use
            :meth:`to_columns` or :meth:`to_dict` instead).
        """
        try:
            pandas = import_module("pandas")
        except ImportError:
            raise ImportError(
                "BatchResult.to_frame needs pandas, which sso does not install; "
                "install pandas or use to_columns() / to_dict()"
            ) from None
        return pandas.DataFrame(self.to_columns())


def optimise_batch(
    beta_deg: Any,
    phase_deg: Any,
    *,
    option: int | str = DEFAULT_OPTION,
    beta_bounds_deg: Any = DEFAULT_BETA_BOUNDS_DEG,
    phase_bounds_deg: Any = DEFAULT_PHASE_BOUNDS_DEG,
    model: str = "exact",
    input_speed_rpm: float = DEFAULT_INPUT_SPEED_RPM,
    solver_tol: float = DEFAULT_SHAFT_SOLVER_TOL,
    max_iterations: int = DEFAULT_MAX_ITERATIONS,
    memory_limit_mb: float | None = None,
) -> BatchResult:
    """Optimise ``m`` start designs of one shape at once (exact model, closed form).

    Each row is an independent problem with the meaning of :func:`sso.optimise`
    with one start: minimise the residual error under the bounds from that start.

    Parameters
    ----------
    beta_deg : array of shape (m, n) or (n,)
        Operating angles of each start, deg, in ``[0, 90)``; option 1 keeps them.
    phase_deg : array of shape (m, n - 1) or (n - 1,)
        Relative phases of each start, deg; option 2 replaces them by 90 deg.
    option : {1, 2, 3, "phase", "angle", "both"}
        Which angles are design variables.
    beta_bounds_deg : (float, float) or sequence of pairs
        Bounds on the operating angles, deg, inside ``[0, 90)``; one pair for all
        joints or one per joint.
    phase_bounds_deg : (float, float) or sequence of pairs
        Bounds on the relative phases, deg, inside ``[-360, 360]``.
    model : {"exact"}
        Only the exact model has the closed form.
    input_speed_rpm : float
        Input speed, rpm (> 0); it scales the reported speeds, not the optimum.
    solver_tol : float
        In ``(0, 1)``: a start stops when RE's projected gradient (per rad) is at
        most this, as :func:`sso.optimise`'s default cross-check measures it.
    max_iterations : int
        Iteration limit of each start, ``1..1000000``.
    memory_limit_mb : float, optional
        Memory the call may be estimated to need, MB (default: ``SSO_MEMORY_LIMIT_MB``
        or :data:`sso._limits.DEFAULT_MEMORY_LIMIT_MB`). The solver's arrays grow with
        the starts and the square of the free angles; starts estimated above the limit
        are solved in consecutive parts that fit it, with the same answers.

    Returns
    -------
    BatchResult
        Solver failures are reported per start in ``success``/``status``.

    Raises
    ------
    ValueError
        For bad input (naming the field, the value and the allowed range), for
        ``model = "paper"``, which has no closed form, and when not even one start
        fits the memory limit (with the estimate).
    TypeError
        If the start angles are not arrays of numbers, or a keyword is unknown.
    """
    check_choice("model", model, MODELS)
    if model != "exact":
        raise ValueError(
            f"model = {model!r} has no closed form, and optimise_batch solves the exact "
            "model only; use sso.optimise for the paper model"
        )
    speed_rpm = validate_speed("input_speed_rpm", input_speed_rpm)
    gradient_tolerance = validate_solver_tol(solver_tol)
    iterations = validate_count("max_iterations", max_iterations, 1, MAX_ITERATIONS)
    beta = _design_array("beta_deg", beta_deg, None)
    n_joints = beta.shape[1]
    phase = _design_array("phase_deg", phase_deg, (beta.shape[0], n_joints - 1))
    out_of_range = (beta < 0.0) | (beta >= BETA_LIMIT_DEG)
    if np.any(out_of_range):
        row, column = np.argwhere(out_of_range)[0]
        raise ValueError(f"beta_deg[{row}, {column}] = {beta[row, column]:g} is outside the "
                         f"allowed range [0, {BETA_LIMIT_DEG:g}) deg")
    option_number, beta_bounds, phase_bounds = validate_option_and_bounds(
        option, n_joints, beta_bounds_deg, phase_bounds_deg)
    beta_free, phase_free = free_angles(option_number)
    if not beta_free:  # the given angles are the chain's (else the bounds were checked)
        for row in np.flatnonzero(unresolvable_chains(beta))[:1]:
            check_chain_conditioning(f"beta_deg[{row}]", beta[row].tolist())
    if option_number == 2:
        phase = np.full_like(phase, OPTION_FIXED_PHASE_DEG)

    # The full design row is (beta_1 .. beta_n, phi_1 .. phi_(n-1)); the option frees some.
    design_deg = np.hstack([beta, phase])
    free = np.r_[np.arange(n_joints) if beta_free else [],
                 n_joints + np.arange(n_joints - 1) if phase_free else []].astype(int)
    lower, upper = np.array([*beta_bounds, *phase_bounds], dtype=float).reshape(-1, 2)[free].T
    start = design_deg[:, free]
    moved = np.count_nonzero((start < lower) | (start > upper))
    if moved:
        warnings.warn(f"{moved} start values lie outside their bounds; moved onto the nearer bound",
                      StartMovedWarning, stacklevel=2)
    native = native_solver_of(
        native_shape(n_joints, option_number), len(free),
        lambda: compiled_nlp(build_problem(beta[0].tolist(), phase[0].tolist(), model,
                                           option_number, beta_bounds, phase_bounds), 0))
    parts = [_solve(design_deg[part], free, n_joints, beta_free, phase_free,
                    np.radians(start[part]), np.radians(lower), np.radians(upper),
                    gradient_tolerance, iterations, native)
             for part in _parts(len(start), n_joints, len(free), memory_limit_mb)]
    solved = _Solved(*(np.concatenate([getattr(part, field.name) for part in parts])
                       for field in fields(_Solved)))
    # Back in degrees, a value on a bound is that bound exactly (not a round-trip ulp off).
    design_deg[:, free] = np.clip(np.degrees(solved.x), lower, upper)
    beta_out, phase_out = design_deg[:, :n_joints], design_deg[:, n_joints:]
    beta_rad, phase_rad = np.radians(beta_out), np.radians(phase_out)
    least, greatest = ratio_extremes(np, [beta_rad[:, k] for k in range(n_joints)],
                                     [phase_rad[:, k] for k in range(n_joints - 1)])
    return BatchResult(
        fun=solved.fun,
        beta_deg=np.array(beta_out, dtype=float),
        phase_deg=np.array(phase_out, dtype=float),
        success=solved.success,
        status=solved.status,
        nit=solved.nit,
        nfev=solved.nfev,
        kkt=solved.kkt,
        speed_min_rpm=speed_rpm * np.broadcast_to(least, solved.fun.shape),
        speed_max_rpm=speed_rpm * np.broadcast_to(greatest, solved.fun.shape),
        option=option_number,
        model=model,
        input_speed_rpm=speed_rpm,
        beta_bounds_deg=beta_bounds,
        phase_bounds_deg=phase_bounds,
    )


def _parts(starts: int, joints: int, free_variables: int,
           memory_limit: float | None) -> list[slice]:
    """Consecutive parts of the starts, each estimated to fit the memory limit.

    Raises
    ------
    ValueError
        If not even one start fits (with the estimate of one and of all).
    """
    limit = resolve_memory_limit(memory_limit)
    if batch_estimate(starts, joints, free_variables).memory_mb <= limit:
        return [slice(0, starts)]
    check_memory(batch_estimate(1, joints, free_variables), limit)
    per_start = batch_least_squares_mb(1, free_variables)
    size = max(1, int((limit - batch_estimate(0, joints, free_variables).memory_mb) // per_start))
    return [slice(first, first + size) for first in range(0, starts, size)]


@dataclass(frozen=True)
class _Solved:
    """Each start's answer (rad), as arrays."""

    x: np.ndarray
    fun: np.ndarray
    kkt: np.ndarray
    nit: np.ndarray
    nfev: np.ndarray
    status: np.ndarray
    success: np.ndarray


def _solve(design_deg: np.ndarray, free: np.ndarray, n_joints: int, beta_free: bool,
           phase_free: bool, start: np.ndarray, lower: np.ndarray, upper: np.ndarray,
           tolerance: float, max_iterations: int, native: NativeSolver | None) -> _Solved:
    """Every start by the ``"lm"`` rules, compiled or in numpy, those above zero finished by
    the batched least squares (saddle escapes; on the numpy path Newton steps too).

    With the shape's compiled rules (``native``, :mod:`sso._solvers.lm_native`) every
    start runs as the single solve ``sso.optimise(..., solvers="lm")`` runs it, Newton
    steps included. On the numpy path (:mod:`sso._solvers.lm_batch`) the Gauss-Newton
    iterations are the single solve's, so a start that Gauss-Newton takes to round-off
    zero ends where the single solve ends; a start whose steps turned to Newton steps
    goes to :func:`sso._solvers.least_squares.batch_least_squares` afresh from its start.
    A start whose sum of squares stays above round-off zero either way goes to it from
    where it stopped, which checks for saddles and leaves them. The iterations already
    taken count against the limit.
    """
    design_rad = np.radians(design_deg)
    fixed = np.setdiff1d(np.arange(design_rad.shape[1]), free)

    def column_residuals(point: list[np.ndarray], parameters: list[np.ndarray]
                         ) -> tuple[np.ndarray, np.ndarray, list[np.ndarray], list[np.ndarray]]:
        if beta_free and phase_free:
            beta, phase = point[:n_joints], point[n_joints:]
        else:
            beta, phase = (point, parameters) if beta_free else (parameters, point)
        # Real arithmetic: numpy's complex products round differently with the length of
        # the arrays, which would make a design's answer depend on the batch it is in.
        (first, second), d_beta, d_phase = residual_jacobian(np, beta, phase)
        derivatives = [*(d_beta if beta_free else []), *(d_phase if phase_free else [])]
        return (first, second, [pair[0] for pair in derivatives],
                [pair[1] for pair in derivatives])

    def residual_and_jacobian(x_rad: np.ndarray, rows: np.ndarray
                              ) -> tuple[np.ndarray, np.ndarray]:
        full = design_rad[rows]
        full[:, free] = x_rad
        residual, jacobian = residuals_and_jacobian_numpy(full[:, :n_joints], full[:, n_joints:])
        return residual, jacobian[..., free]

    run = (None if native is None else
           solve_native_leaving_saddles(native, start, design_rad[:, fixed], lower, upper,
                                        tolerance, max_iterations, residual_and_jacobian,
                                        ZERO_RESIDUAL_LEVEL))
    compiled = run is not None
    if run is None:
        run = solve_batch(column_residuals, start, design_rad[:, fixed], lower, upper,
                          tolerance, max_iterations)
    x, fun, nit, nfev, status = run.x, run.fun, run.nit, run.nfev, run.status
    # A design that turned to Newton steps on its last allowed iteration ends there, as
    # the single solve does at the iteration limit.
    status[np.isin(status, (NEWTON, NEWTON_INDEFINITE)) & (nit >= max_iterations)] = 0
    held = ((x <= lower) & (run.gradient > 0)) | ((x >= upper) & (run.gradient < 0))
    kkt = np.max(np.where(held, 0.0, np.abs(run.gradient)), axis=1, initial=0.0)
    # The compiled path has left its saddles already: only its failures above zero go on.
    unfinished = np.flatnonzero((fun > ZERO_RESIDUAL_LEVEL) & (status != -2)
                                & (nit < max_iterations)
                                & ~(compiled & np.isin(status, SUCCESS_STATUSES)))
    # A design that turned to Newton steps on the numpy path, or whose shifted Newton step
    # stayed indefinite, starts the batched least squares afresh from its start (Newton
    # steps from where Gauss-Newton slowed down, taken without the single solve's
    # eigenvalue shift, can stall); the others continue from where they stopped (a
    # saddle check of a point that has converged).
    restart = np.isin(status[unfinished], (NEWTON, NEWTON_INDEFINITE))
    if unfinished.size:
        finished = batch_least_squares(rows_of(residual_and_jacobian, unfinished),
                                       np.where(restart[:, None], start[unfinished],
                                                x[unfinished]), lower, upper,
                                       gtol=tolerance, max_iterations=max_iterations,
                                       iterations_taken=nit[unfinished])
        x[unfinished], fun[unfinished] = finished.x, finished.fun
        kkt[unfinished] = finished.projected_gradient
        nit[unfinished] = finished.nit
        nfev[unfinished] += finished.nfev
        status[unfinished] = finished.status
    # A stop at round-off with a gradient far from zero: a minimum, or only a vanished step?
    suspects = np.flatnonzero(np.isin(status, round_off_stops.ROUND_OFF_STOPS)
                              & (kkt > round_off_stops.SUSPECT_GRADIENT))
    if suspects.size:
        def sum_of_squares(points: np.ndarray, rows: np.ndarray) -> np.ndarray:
            residual = residual_and_jacobian(points, rows)[0]
            values: np.ndarray = residual[:, 0] ** 2 + residual[:, 1] ** 2
            return values

        status[suspects[round_off_stops.refuted(sum_of_squares, x, fun, lower, upper,
                                                suspects)]] = round_off_stops.REFUTED
    return _Solved(x, fun, kkt, nit, nfev, status, np.isin(status, SUCCESS_STATUSES))


def _design_array(field: str, values: Any, shape: tuple[int, int] | None) -> np.ndarray:
    """Start angles as a finite float array of shape ``(m, k)`` (a 1-D array is one row).

    Raises
    ------
    ValueError
        Naming the field if the entries are not finite numbers or the shape is wrong.
    """
    if isinstance(values, (str, bytes)):
        raise TypeError(f"{field} = {values!r} must be an array of numbers")
    try:
        raw = np.asarray(values)
        array = np.array(raw, dtype=float, ndmin=2)
    except (TypeError, ValueError):
        raise TypeError(f"{field} must be an array of numbers (m starts x angles)") from None
    if raw.dtype == bool or raw.dtype.kind not in "iuf":
        raise TypeError(f"{field} must be an array of numbers, not of {raw.dtype}")
    if shape is not None and array.size == 0 and shape[1] == 0:
        return np.zeros(shape)
    if array.ndim != 2:
        raise ValueError(f"{field} has shape {np.shape(values)}; expected (m starts, angles)")
    if shape is None and (array.shape[0] == 0 or array.shape[1] == 0):
        raise ValueError(f"{field} has shape {array.shape}: it needs at least 1 start and 1 joint")
    if shape is not None and array.shape != shape:
        raise ValueError(f"{field} has shape {array.shape}; the starts of beta_deg need {shape}")
    bad = np.argwhere(~np.isfinite(array))
    if bad.size:
        row, column = bad[0]
        raise ValueError(f"{field}[{row}, {column}] = {float(array[row, column])!r} must be finite "
                         "(not NaN or infinite)")
    return array
