"""The concept pages' figures, drawn from the package's own functions at build time.

Each function returns one PNG as bytes; :func:`all_figures` names them for the site
(``figures/<name>.png``). ``python -m doctools.figures FOLDER`` writes them to a
folder (the README's figure, ``docs/images/speed_ratio.png``, is one of them).
"""

from __future__ import annotations

import io
import sys
import tomllib
from collections.abc import Callable
from pathlib import Path

import numpy as np

import sso

ROOT = Path(__file__).resolve().parents[1]
FOLDER = "figures"
THETA_DEG = np.linspace(0.0, 360.0, 721)


def _new_figure(width: float = 7.0, height: float = 3.6):  # type: ignore[no-untyped-def]
    from matplotlib.figure import Figure

    figure = Figure(figsize=(width, height), dpi=110, layout="constrained")
    return figure


def _png(figure) -> bytes:  # type: ignore[no-untyped-def]
    buffer = io.BytesIO()
    figure.savefig(buffer, format="png", metadata={"Software": None})
    return buffer.getvalue()


def _re_text(value: float) -> str:
    return "< 1e-15" if value <= 1e-15 else f"{value:.3g}"


def _legend_below(axes) -> None:  # type: ignore[no-untyped-def]
    axes.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.2), ncol=2,
                frameon=False)


def speed_ratio() -> bytes:
    """One joint's speed ratio over a revolution at several angles, and a cancelling pair."""
    figure = _new_figure(7.0, 4.0)
    left, right = figure.subplots(1, 2, sharey=True)
    for beta_deg in (10, 20, 30, 40):
        series = sso.ShaftSeries(beta_deg=[beta_deg], phase_deg=[], model="exact")
        ratio = series.speed_ratio(THETA_DEG)
        re = series.evaluate().residual_error
        left.plot(THETA_DEG, ratio, label=f"beta = {beta_deg} deg, RE {_re_text(re)}")
    left.set(title="one Hooke joint", xlabel="input angle theta (deg)",
             ylabel="output / input speed", xticks=range(0, 361, 90))
    _legend_below(left)
    for phase_deg, style in ((90.0, "-"), (60.0, "--"), (0.0, ":")):
        series = sso.ShaftSeries(beta_deg=[30, 30], phase_deg=[phase_deg], model="exact")
        re = series.evaluate().residual_error
        right.plot(THETA_DEG, series.speed_ratio(THETA_DEG), style,
                   label=f"phi = {phase_deg:g} deg, RE {_re_text(re)}")
    right.set(title="two joints of 30 deg", xlabel="input angle theta (deg)",
              xticks=range(0, 361, 90))
    _legend_below(right)
    return _png(figure)


def design_options() -> bytes:
    """RE of a three-joint series against a phase (option 1) and an operating angle (option 2)."""
    figure = _new_figure()
    left, right = figure.subplots(1, 2)
    phases = np.linspace(0.0, 180.0, 181)
    for second_deg in (60.0, 90.0, 120.0):
        values = [sso.ShaftSeries(beta_deg=[30, 40, 40], phase_deg=[first, second_deg]
                                  ).evaluate().residual_error for first in phases]
        left.semilogy(phases, np.maximum(values, 1e-12), label=f"phi_2 = {second_deg:g} deg")
    left.set(title="option 1: phases free", xlabel="phi_1 (deg); beta 30, 40, 40 deg",
             ylabel="RE", xticks=range(0, 181, 45))
    left.legend(fontsize=7)
    betas = np.linspace(10.0, 40.0, 121)
    for first_deg in (20.0, 30.0, 40.0):
        values = [sso.ShaftSeries(beta_deg=[first_deg, beta, 40.0], phase_deg=[90, 90]
                                  ).evaluate().residual_error for beta in betas]
        right.semilogy(betas, np.maximum(values, 1e-12), label=f"beta_1 = {first_deg:g} deg")
    right.set(title="option 2: angles free",
              xlabel="beta_2 (deg); beta_3 = 40 deg, phases 90 deg", ylabel="RE")
    right.legend(fontsize=7)
    return _png(figure)


def models() -> bytes:
    """The exact and the paper model on the paper's option-3 start."""
    figure = _new_figure()
    axes = figure.subplots()
    for model, style in (("exact", "-"), ("paper", "--")):
        series = sso.ShaftSeries(beta_deg=[30, 40, 40], phase_deg=[90, 90], model=model)
        mean = float(np.mean(series.speed_ratio(THETA_DEG[:-1])))
        axes.plot(THETA_DEG, series.speed_ratio(THETA_DEG), style,
                  label=f"{model} model (mean ratio {mean:.4f})")
    axes.axhline(1.0, color="grey", linewidth=0.8)
    axes.set(title="beta = 30, 40, 40 deg, phi = 90, 90 deg", xlabel="input angle (deg)",
             ylabel="output / input speed", xticks=range(0, 361, 45))
    axes.legend(fontsize=8)
    return _png(figure)


def _car_column() -> sso.ColumnGeometry:
    case = tomllib.loads((ROOT / "cases/column_car_intermediate_shaft.toml").read_text())
    return sso.ColumnGeometry(case["hardpoints"]["points_mm"])


def _re_over_phasing(column: sso.ColumnGeometry, deltas: np.ndarray) -> np.ndarray:
    """RE of a one-phasing column at each yoke phasing (deg), floored for a log axis."""
    values = [column.series(yoke_phase_deg=[delta]).evaluate().residual_error
              for delta in deltas]
    return np.maximum(values, 1e-16)


def phase_convention() -> bytes:
    """RE of a non-planar two-joint column against its yoke phasing delta."""
    column = _car_column()
    gamma = float(column.plane_angle_deg[0])
    deltas = np.linspace(-90.0, 90.0, 361)
    figure = _new_figure()
    axes = figure.subplots()
    axes.semilogy(deltas, _re_over_phasing(column, deltas), label="RE of the column")
    axes.axvline(0.0, color="C1", linestyle="--", label="delta = 0: yokes in phase")
    textbook = (gamma + 90.0) % 180.0 - 90.0
    axes.axvline(textbook, color="C2", linestyle=":",
                 label=f"delta = gamma = {textbook:.1f} deg: phi = 90")
    axes.set(title=f"car column, beta = {column.beta_deg[0]:.1f}, {column.beta_deg[1]:.1f} deg,"
             f" bend planes {gamma:.1f} deg apart", xlabel="yoke phasing delta (deg)",
             ylabel="RE", xticks=range(-90, 91, 30))
    axes.legend(fontsize=8)
    return _png(figure)


def cancellation() -> bytes:
    """Where three joints can cancel: the margin of the cancellation criterion."""
    betas = np.linspace(1.0, 45.0, 89)
    margin = np.array([[sso.can_cancel([20.0, second, third]).margin for second in betas]
                       for third in betas])
    figure = _new_figure(5.6, 4.4)
    axes = figure.subplots()
    image = axes.contourf(betas, betas, margin, levels=21, cmap="RdBu")
    axes.contour(betas, betas, margin, levels=[0.0], colors="k")
    figure.colorbar(image, ax=axes, label="margin (positive: can cancel)")
    axes.set(title="beta_1 = 20 deg: which beta_2, beta_3 can cancel", xlabel="beta_2 (deg)",
             ylabel="beta_3 (deg)")
    return _png(figure)


def spline_teeth() -> bytes:
    """RE near the best yoke phasing, and the phasings a 36-tooth spline allows."""
    column = _car_column()
    deltas = np.linspace(-90.0, 90.0, 721)
    teeth = np.arange(-90.0, 90.01, 10.0)
    figure = _new_figure()
    axes = figure.subplots()
    axes.semilogy(deltas, _re_over_phasing(column, deltas), label="continuous phasing")
    axes.semilogy(teeth, _re_over_phasing(column, teeth), "o",
                  label="tooth positions (36 teeth: every 10 deg)")
    axes.set(title="car column: the spline allows only every 10 deg of phasing",
             xlabel="yoke phasing delta (deg)", ylabel="RE", xticks=range(-90, 91, 30))
    axes.legend(fontsize=8)
    return _png(figure)


def robust_phasing() -> bytes:
    """RE of a tilting truck column at three positions against one yoke phasing."""
    case = tomllib.loads((ROOT / "cases/column_truck_three_positions.toml").read_text())
    positions = case["hardpoints"]["positions"]
    second_deg = float(case["phasing"]["yoke_phase_deg"][1])
    deltas = np.linspace(-90.0, 90.0, 181)
    figure = _new_figure()
    axes = figure.subplots()
    worst = np.zeros_like(deltas)
    for name, points in positions.items():
        column = sso.ColumnGeometry(points)
        values = np.array([column.series(yoke_phase_deg=[delta, second_deg]).evaluate(
        ).residual_error for delta in deltas])
        worst = np.maximum(worst, values)
        axes.semilogy(deltas, np.maximum(values, 1e-16), label=name)
    axes.semilogy(deltas, worst, "k", linewidth=2, label="worst position")
    axes.set(title=f"truck column, delta_2 = {second_deg:g} deg: one phasing for every tilt",
             xlabel="yoke phasing delta_1 (deg)", ylabel="RE", xticks=range(-90, 91, 30))
    axes.legend(fontsize=8)
    return _png(figure)


def cross_check() -> bytes:
    """Where each solver's runs stop on the paper's option 3 (exact model), from 8 starts."""
    series = sso.ShaftSeries(beta_deg=[30, 40, 40], phase_deg=[90, 90])
    result = sso.optimise(series, option=3, beta_bounds_deg=(10, 40),
                          phase_bounds_deg=(0, 180), solvers=("ipopt", "slsqp"),
                          starts=8, screen_starts=False)
    figure = _new_figure()
    axes = figure.subplots()
    for offset, name in enumerate(("ipopt", "slsqp")):
        runs = [run for run in result.runs if run.solver == name]
        axes.semilogy(np.arange(len(runs)) + 0.15 * offset,
                      [max(run.fun, 1e-18) for run in runs], "o", label=name)
    axes.set(title="paper's option 3: final RE of each start (at 1e-18: round-off zero)",
             xlabel="start", ylabel="final RE")
    axes.legend(fontsize=8)
    return _png(figure)


def driveline_conventions() -> bytes:
    """The compound pickup in side and plan view, and its axle excitation against phasing."""
    from sso._driveline.excitation import excitations

    with open(ROOT / "cases" / "driveline_compound_pickup.toml", "rb") as file:
        measured = tomllib.load(file)["measurements"]
    driveline = sso.Driveline.from_measurements(
        **measured, tubes=(sso.Tube(88.9, 2.1),), max_shaft_speed_rpm=3500.0,
        torque_n_m=1500.0)
    points = np.asarray(driveline.points_mm)
    gamma = float(driveline.geometry.plane_angle_deg[0])
    deltas = np.linspace(-90.0, 90.0, 181)
    torsional = [excitations(driveline.geometry, (float(delta),), 3500.0).torsional_rad_s2
                 for delta in deltas]
    figure = _new_figure(8.0, 3.8)
    views, right = figure.subplots(1, 2, width_ratios=(1.0, 1.2))
    views.plot(points[:, 0], points[:, 2], "o-", label="side view: z (up)")
    views.plot(points[:, 0], points[:, 1], "s--", label="plan view: y (left)")
    views.annotate("gearbox", points[0, [0, 2]], fontsize=7)
    views.annotate("pinion", points[-1, [0, 2]], fontsize=7)
    views.set(title="x forward; slopes: front higher +", xlabel="x (mm)",
              ylabel="mm")
    views.invert_xaxis()
    views.legend(fontsize=7)
    right.plot(deltas, torsional, label="pinion's peak acceleration")
    right.axhline(300.0, color="r", linestyle="--", label="torsional limit 300 rad/s^2")
    right.axvline(0.0, color="C1", linestyle=":", label="yokes in phase")
    right.axvline(gamma, color="C2", linestyle=":",
                  label=f"delta = plane angle {gamma:.1f} deg")
    right.set(title="pickup at 3,500 rpm: planes 82 deg apart",
              xlabel="yoke phasing delta of the propshaft (deg)", ylabel="rad/s^2",
              xticks=range(-90, 91, 30))
    right.legend(fontsize=7)
    return _png(figure)


FIGURES: dict[str, Callable[[], bytes]] = {
    "speed_ratio.png": speed_ratio,
    "design_options.png": design_options,
    "models.png": models,
    "phase_convention.png": phase_convention,
    "cancellation.png": cancellation,
    "spline_teeth.png": spline_teeth,
    "robust_phasing.png": robust_phasing,
    "cross_check.png": cross_check,
    "driveline_conventions.png": driveline_conventions,
}


def all_figures() -> dict[str, bytes]:
    """Every concept figure, by file name."""
    return {name: draw() for name, draw in FIGURES.items()}


def main(arguments: list[str] | None = None) -> int:
    """``python -m doctools.figures FOLDER [NAME ...]``: write the figures (all by default)."""
    folder, *names = arguments if arguments is not None else sys.argv[1:]
    Path(folder).mkdir(parents=True, exist_ok=True)
    for name in names or list(FIGURES):
        (Path(folder) / name).write_bytes(FIGURES[name]())
    return 0


if __name__ == "__main__":
    sys.exit(main())
