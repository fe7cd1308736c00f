"""``sso.tolerance_study``: how manufacturing tolerances on
angles and phases spread the results.

Every sample perturbs the operating angles and phases of one design by draws from
a normal or uniform distribution (deg) and is evaluated like
:meth:`sso.ShaftSeries.evaluate` (:mod:`sso._shafts.perturbed` holds that kernel):
residual error, peak-to-peak fluctuation and peak output acceleration. The samples
are evaluated as arrays (thousands of designs per numpy call), drawn once in the
calling process from a seeded generator, and so are the same for any chunking,
executor or worker count.
"""

from __future__ import annotations

import time
from collections.abc import Mapping, Sequence
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np

from sso._cases.column import ColumnCase
from sso._column.steering_criteria import SteeringLimits
from sso._column.tolerances import Tolerances
from sso._files import check_report_folder
from sso._limits import (
    DEFAULT_CHUNK_SAMPLES,
    DEFAULT_INPUT_SPEED_RPM,
    DEFAULT_QUADRATURE_ATOL,
    DEFAULT_QUADRATURE_RTOL,
    OUTPUT_FORMATS,
)
from sso._progress import interactive
from sso._reports.kinds import write_report
from sso._resources import check_memory
from sso._shafts.optimise import OptimisationResult
from sso._shafts.perturbed import (
    DEFAULT_TOLERANCES,
    DISTRIBUTIONS,
    MAX_SAMPLES,
    per_item_tolerances,
)
from sso._shafts.quadrature import rule_for_bounds
from sso._shafts.series import ShaftSeries
from sso._studies.axes import base_case
from sso._studies.column_tolerance import (
    ColumnToleranceResult,
    column_tolerance_study,
    is_column_design,
    study_settings,
)
from sso._studies.execution import validate_workers
from sso._studies.report import TOLERANCE_FOLDER
from sso._studies.results import ToleranceResult
from sso._studies.tolerance_samples import drawn_samples, evaluate_samples, study_estimate
from sso._validation import (
    as_float_tuple,
    check_choice,
    check_in_range,
    validate_count,
    validate_speed,
)

DEFAULT_PERCENTILES = (5.0, 50.0, 95.0, 99.0)
# Settings of a study when neither the call nor the case's [tolerance] table gives them.
DEFAULT_SETTINGS: dict[str, Any] = {**DEFAULT_TOLERANCES, "percentiles": DEFAULT_PERCENTILES}


def tolerance_study(
    design: Any,
    *,
    beta_tolerance_deg: float | Sequence[float] | None = None,
    phase_tolerance_deg: float | Sequence[float] | None = None,
    distribution: str | None = None,
    samples: int | None = None,
    seed: int | None = None,
    input_speed_rpm: float | None = None,
    percentiles: Sequence[float] | None = None,
    out_dir: str | Path | None = None,
    client: Any = None,
    workers: int | None = None,
    chunk_size: int = DEFAULT_CHUNK_SAMPLES,
    progress: bool | None = None,
    plots: bool = True,
    memory_limit_mb: float | None = None,
    tolerances: Tolerances | None = None,
    limits: SteeringLimits | None = None,
    required_yield: float | None = None,
) -> ToleranceResult | ColumnToleranceResult:
    """Monte Carlo study of a design under angle and phase tolerances (a shaft series), or
    under hardpoint and yoke-phasing tolerances (a column).

    Sample ``i`` is ``beta_deg + d_beta[i]`` and ``phase_deg + d_phase[i]``, where
    ``rng = numpy.random.default_rng(seed)`` draws ``d_beta = rng.normal(0,
    beta_tolerance_deg, (samples, joints))`` and then ``d_phase = rng.normal(0,
    phase_tolerance_deg, (samples, joints - 1))`` (``rng.uniform(-t, t, ...)`` for
    the uniform distribution).

    Samples out of the physical range: a sampled operating angle below 0 deg is
    reflected to its magnitude (the same joint bent the other way: the joint law
    depends on ``cos beta`` only), and the samples so reflected are counted in
    :attr:`ToleranceResult.reflected_samples` and in the report. A tolerance that
    could carry an angle to 90 deg (the joint locks) is refused before sampling:
    ``beta + 6 * tolerance`` (normal) or ``beta + tolerance`` (uniform) must stay
    below 90 deg.

    A column design (``(sso.ColumnGeometry, yoke_phase_deg)``, a result holding a
    column's ``geometry`` and ``yoke_phase_deg``, or a column case, whose assembly as
    built is studied) is studied by :func:`sso._studies.column_tolerance.column_tolerance_study`:
    each sample a built column, its hardpoints (mm) and yoke phasings (deg) moved by
    ``tolerances`` (default: the case's ``[tolerances]``, else 0.5 mm and 1 deg normal),
    reporting RE and the steering figures from lock to lock (the case's ``[steering]``
    range, else the defaults of :func:`sso.steering_range`); ``samples``, ``seed``,
    ``distribution``, ``percentiles`` and the execution keywords apply, the angle
    tolerances and ``input_speed_rpm`` do not. It returns a
    :class:`sso.ColumnToleranceResult`.

    Parameters
    ----------
    design : OptimisationResult, ShaftSeries, str, pathlib.Path, Case, mapping or a column design
        What to study: the best design of an optimisation result (the usual
        case: how its optimum spreads under tolerances), a design, or a case
        whose design as given (its start) is perturbed; a case also gives the
        input speed and, in its ``[tolerance]`` table, the defaults of the
        settings below. ``sso tolerance CASE`` optimises the case first.
    beta_tolerance_deg, phase_tolerance_deg : float or sequence of float, optional
        Standard deviation (normal) or half-width (uniform) of the deviation, deg,
        in ``[0, 45]``: one value for all, or one per joint / per phase
        (default 0.5 and 1).
    distribution : {"normal", "uniform"}, optional
        Default ``"normal"``.
    samples : int, optional
        Number of samples, ``1..1e8`` (default 10000).
    seed : int, optional
        Seed of the generator, >= 0 (default 0); the same seed gives the same numbers.
    input_speed_rpm : float, optional
        Input speed, rpm (> 0); default the case's, or 25.
    percentiles : sequence of float, optional
        Percentiles to report, each in ``[0, 100]`` (default 5, 50, 95, 99).
    out_dir : str or pathlib.Path, optional
        Report folder, written afresh (:func:`sso.write_report`):
        ``tolerance.csv`` (every sample, 6 digits), ``tolerance.json`` (summary,
        full precision), ``report.md``, ``report.html`` and
        ``tolerance_histogram.png``.
    client : dask.distributed.Client, optional
        Evaluate the chunks on this Dask cluster.
    workers : int, optional
        Local processes when there is more than one chunk (default: every core).
    chunk_size : int
        Samples per task, ``1..1e8``; a study of one chunk runs in this process.
    progress : bool, optional
        Progress bar on stderr (default: only on an interactive terminal outside CI).
    plots : bool
        Draw the histogram (needs ``out_dir``; imports matplotlib).
    memory_limit_mb : float, optional
        Refuse the study if its memory estimate exceeds this, MB (default
        ``SSO_MEMORY_LIMIT_MB`` or :data:`sso._limits.DEFAULT_MEMORY_LIMIT_MB`).
    tolerances : sso.Tolerances, optional
        A column's hardpoint and yoke-phasing tolerances (a column design only).
    limits : sso.SteeringLimits, optional
        The limits a column's built columns are judged against (a column design
        only; a column case's ``[limits]`` unless given): the yield of each and of
        all together, with its 95 % confidence interval, and which tolerance matters.
    required_yield : float, optional
        The yield of all limits together a column must show, in ``(0, 1]`` (a
        column case's ``[limits] yield`` unless given); the result's
        ``yields.verdict`` says whether it does.

    Returns
    -------
    ToleranceResult or ColumnToleranceResult

    Raises
    ------
    ValueError
        Naming the field, the value and the allowed range; or, before anything is
        drawn, if the memory estimate exceeds the limit (the message gives both
        and how many samples fit).
    """
    started = time.perf_counter()
    if isinstance(design, (str, Path, Mapping, ColumnCase)):
        design = base_case(design)
    column_case = design if isinstance(design, ColumnCase) else None
    if column_case is not None or is_column_design(design):
        shaft_keywords = [name for name, value in (
            ("beta_tolerance_deg", beta_tolerance_deg),
            ("phase_tolerance_deg", phase_tolerance_deg),
            ("input_speed_rpm", input_speed_rpm)) if value is not None]
        if shaft_keywords:
            raise ValueError(f"{', '.join(shaft_keywords)}: a column's tolerance study takes "
                             "tolerances=sso.Tolerances(hardpoint_mm=..., yoke_phase_deg=...) "
                             "instead (it studies hardpoints and yoke phasings)")
        chosen, count = study_settings(tolerances, column_case, samples, seed, distribution)
        steering = ({} if column_case is None else
                    {name: column_case.values[f"steering.{name}"]
                     for name in ("lock_deg", "straight_ahead_deg")})
        if column_case is not None:
            design = (column_case.geometry(), column_case.values["phasing.yoke_phase_deg"])
            limits = column_case.steering_limits() if limits is None else limits
            required_yield = (column_case.required_yield if required_yield is None
                              else required_yield)
        return column_tolerance_study(
            design, chosen, samples=count, percentiles=percentiles, out_dir=out_dir,
            client=client, workers=workers, chunk_size=chunk_size, progress=progress,
            plots=plots, memory_limit_mb=memory_limit_mb, limits=limits,
            required_yield=required_yield, **steering,
            study_of="the given design" if column_case is None else
            f"the assembly as built in case {column_case.name!r}")
    if tolerances is not None:
        raise ValueError("tolerances = sso.Tolerances(...) is a column's; a shaft series takes "
                         "beta_tolerance_deg= and phase_tolerance_deg=")
    if limits is not None or required_yield is not None:
        raise ValueError("limits and required_yield judge a column's built columns; a shaft "
                         "series' tolerance study takes neither")
    series, speed_rpm, quadrature, case_settings, study_of = _nominal(design, input_speed_rpm)
    if out_dir is not None:
        out_dir = check_report_folder(out_dir, TOLERANCE_FOLDER)
    given = {"beta_tolerance_deg": beta_tolerance_deg, "phase_tolerance_deg": phase_tolerance_deg,
             "distribution": distribution, "samples": samples, "seed": seed,
             "percentiles": percentiles}
    settings = {**DEFAULT_SETTINGS, **case_settings,
                **{name: value for name, value in given.items() if value is not None}}
    distribution = check_choice("distribution", settings["distribution"], DISTRIBUTIONS)
    samples = settings["samples"]
    seed = settings["seed"]
    samples = validate_count("samples", samples, 1, MAX_SAMPLES)
    chunk_size = validate_count("chunk_size", chunk_size, 1, MAX_SAMPLES)
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise ValueError(f"seed = {seed!r} must be a whole number >= 0")
    quantiles = tuple(check_in_range(f"percentiles[{index}]", value, 0.0, 100.0)
                      for index, value in enumerate(as_float_tuple("percentiles",
                                                                   settings["percentiles"])))
    if not quantiles:
        raise ValueError("percentiles is empty: give one or more values in [0, 100]")
    beta_tolerance = per_item_tolerances("beta_tolerance_deg", settings["beta_tolerance_deg"],
                                 series.n_joints)
    phase_tolerance = per_item_tolerances("phase_tolerance_deg", settings["phase_tolerance_deg"],
                                  series.n_joints - 1)
    worker_count = validate_workers(workers)
    check_memory(study_estimate(series, samples, quadrature,
                                worker_count if client is None else 1, chunk_size),
                 memory_limit_mb)

    beta_deg, phase_deg, reflected = drawn_samples(series, beta_tolerance, phase_tolerance,
                                                   distribution, samples, seed)
    # The exact model's RE is the closed form of the chain matrix (0 quadrature angles).
    quadrature_samples = (rule_for_bounds(np.radians(beta_deg.max(axis=0)).tolist(),
                                          series.model, *quadrature).samples
                          if series.model == "paper" else 0)
    metrics = evaluate_samples(beta_deg, phase_deg, series.model, quadrature_samples, speed_rpm,
                               chunk_size, client, worker_count,
                               interactive() if progress is None else progress)

    result = ToleranceResult(
        design=series, nominal=series.evaluate(speed_rpm, quadrature_rtol=quadrature[0],
                                               quadrature_atol=quadrature[1]),
        distribution=distribution, beta_tolerance_deg=beta_tolerance,
        phase_tolerance_deg=phase_tolerance, seed=int(seed), input_speed_rpm=speed_rpm,
        quadrature_samples=quadrature_samples, percentiles=quantiles, beta_deg=beta_deg,
        phase_deg=phase_deg, residual_error=metrics[0], fluctuation=metrics[1],
        max_output_accel_rad_s2=metrics[2], elapsed_s=time.perf_counter() - started,
        study_of=study_of, reflected_samples=reflected)
    if out_dir is None:
        return result
    formats = tuple(name for name in OUTPUT_FORMATS if plots or name != "png")
    return replace(result, files=tuple(write_report(result, out_dir, formats)))


def _nominal(design: Any, input_speed_rpm: Any) -> tuple[ShaftSeries, float, tuple[float, float],
                                                         dict[str, Any], str]:
    """The nominal series, input speed, quadrature tolerance, settings and origin of ``design``."""
    if isinstance(design, OptimisationResult):
        speed = design.input_speed_rpm if input_speed_rpm is None else input_speed_rpm
        return (design.best_series, validate_speed("input_speed_rpm", speed),
                (DEFAULT_QUADRATURE_RTOL, DEFAULT_QUADRATURE_ATOL), {},
                f"the optimum ({design.best.solver}) of an optimisation, option "
                f"{design.option} ({design.option_name})")
    if isinstance(design, ShaftSeries):
        speed = DEFAULT_INPUT_SPEED_RPM if input_speed_rpm is None else input_speed_rpm
        return (design, validate_speed("input_speed_rpm", speed),
                (DEFAULT_QUADRATURE_RTOL, DEFAULT_QUADRATURE_ATOL), {}, "the given design")
    case = base_case(design)
    speed = case.input_speed_rpm if input_speed_rpm is None else input_speed_rpm
    return (case.series(), validate_speed("input_speed_rpm", speed),
            (case.quadrature_rtol, case.quadrature_atol), case.tolerance_study or {},
            f"the design as given (start) in case {case.name!r}")
