"""``sso.optimise_batch``: many shaft-series designs of one shape optimised at once.

The exact model's residual error is the squared norm of two residuals of the chain
matrix (``sso._kinematics.hooke_matrix``), so ``m`` starts form ``m`` tiny
least-squares problems that the ``"lm"`` solver's functions of the shape solve
together (:func:`sso._solvers.lm_kernel.solve_states`: the same CasADi instructions
per design, mapped over the designs): no quadrature, no per-design Python loop, and
bit for bit the answer of ``sso.optimise(..., solvers="lm", starts=1)`` from the same
start (a design that stops on a saddle point is left by that same call). The
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
from sso._resources import (
    batch_estimate,
    batch_least_squares_mb,
    check_memory,
)
from sso._resources import memory_limit_mb as resolve_memory_limit
from sso._shafts.optimise import measured_end, on_saddle, optimise
from sso._shafts.options import (
    OPTION_FIXED_PHASE_DEG,
    StartMovedWarning,
    build_problem,
    free_angles,
    validate_option_and_bounds,
)
from sso._shafts.problem import compiled_nlp
from sso._shafts.series import ShaftSeries
from sso._solvers import lm
from sso._solvers.lm_kernel import kernels_of, solve_states
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
        Stopping reason, a key of :data:`sso._solvers.lm.MESSAGES`.
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
        return tuple(lm.MESSAGES[int(code)] for code in self.status)

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
    nlp = compiled_nlp(build_problem(beta[0].tolist(), phase[0].tolist(), model, option_number,
                                     beta_bounds, phase_bounds), 0)
    shape = _Shape(nlp, n_joints, option_number, beta_bounds, phase_bounds, free, lower, upper)
    parts = [_solve(shape, design_deg[part], np.radians(start[part]), gradient_tolerance,
                    iterations)
             for part in _parts(len(start), n_joints, len(free), memory_limit_mb)]
    solved = _Solved(*(np.concatenate([getattr(part, field.name) for part in parts])
                       for field in fields(_Solved)))
    design_deg[:, free] = solved.x_deg
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
class _Shape:
    """What every part of a batch shares: the shape's NLP, its layout and bounds."""

    nlp: Any
    n_joints: int
    option: int
    beta_bounds: tuple[tuple[float, float], ...]
    phase_bounds: tuple[tuple[float, float], ...]
    free: np.ndarray
    lower_deg: np.ndarray
    upper_deg: np.ndarray


@dataclass(frozen=True)
class _Solved:
    """Each start's answer, as arrays (the design's free values in deg)."""

    x_deg: np.ndarray
    fun: np.ndarray
    kkt: np.ndarray
    nit: np.ndarray
    nfev: np.ndarray
    status: np.ndarray
    success: np.ndarray


def _solve(shape: _Shape, design_deg: np.ndarray, start: np.ndarray, tolerance: float,
           max_iterations: int) -> _Solved:
    """Every start by the shape's ``"lm"`` functions, each as the single solve
    ``sso.optimise(..., solvers="lm", starts=1)`` takes it: the same functions (mapped over
    the starts), then, design by design, the same reading of the end (:func:`lm.end_of`),
    the same measure (:func:`measured_end`), and a design that succeeded on a saddle point
    above zero solved by that very call (which leaves the saddle)."""
    design_rad = np.radians(design_deg)
    fixed = np.setdiff1d(np.arange(design_rad.shape[1]), shape.free)
    lower, upper = np.radians(shape.lower_deg), np.radians(shape.upper_deg)
    kernels = kernels_of(shape.nlp)
    assert kernels is not None, "the exact model has a residual expression"
    problems = np.empty((len(start), kernels.problem_size))
    problems[:, :len(fixed)] = design_rad[:, fixed]
    problems[:, len(fixed):-1] = [*lower, *upper, tolerance]
    problems[:, -1] = max_iterations
    states = solve_states(kernels, start, problems).tolist()
    lower_list, upper_list = lower.tolist(), upper.tolist()
    bounds_deg = (tuple(shape.lower_deg.tolist()), tuple(shape.upper_deg.tolist()))
    rows = []
    for parameters, state, row_deg in zip(design_rad[:, fixed].tolist(), states, design_deg,
                                          strict=True):
        end = lm.end_of(shape.nlp, parameters, state, lower_list, upper_list, tolerance,
                        max_iterations)
        if on_saddle(shape.nlp, end, parameters, lower, upper):
            best = _alone(shape, row_deg, tolerance, max_iterations)
            rows.append((best.x, best.fun, best.kkt, best.nit, best.nfev, best.status))
            continue
        x_deg, fun, kkt = measured_end(shape.nlp, end, parameters, lower_list, upper_list,
                                       bounds_deg)
        rows.append((x_deg, fun, kkt, end.nit, end.nfev, end.status))
    columns = [np.array(column) for column in zip(*rows, strict=True)]
    status = columns[5].astype(int)
    return _Solved(columns[0].reshape(len(start), len(shape.free)), columns[1].astype(float),
                   columns[2].astype(float), columns[3].astype(int), columns[4].astype(int),
                   status, np.isin(status, lm.SUCCESS_STATUSES))


def _alone(shape: _Shape, design_deg: np.ndarray, tolerance: float, max_iterations: int) -> Any:
    """The best solution of ``sso.optimise(..., solvers="lm", starts=1)`` from one design."""
    n_joints = shape.n_joints
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", StartMovedWarning)
        return optimise(ShaftSeries(design_deg[:n_joints].tolist(),
                                    design_deg[n_joints:].tolist()),
                        shape.option, beta_bounds_deg=shape.beta_bounds,
                        phase_bounds_deg=shape.phase_bounds, solvers=("lm",), starts=1,
                        solver_tol=tolerance, max_iterations=max_iterations).best


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
