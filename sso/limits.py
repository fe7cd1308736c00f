"""Every physical limit and default of sso, defined once.

Each module that checks or defaults one of these imports it from here; nothing
here imports anything from sso, so every layer may.
"""

BETA_LIMIT_DEG = 90.0
"""A Hooke joint's operating angle must stay below this, deg (at 90 deg it locks)."""

DEFAULT_INPUT_SPEED_RPM = 25.0
"""Constant input shaft speed when none is given, rpm."""

MAX_STARTS = 10_000
"""Most start points per solver in one design run (a bound on memory and time)."""

DEFAULT_STARTS = 8
"""Start points per solver: the user's start plus seven space-filling points.

One default for the API (:func:`sso.optimise`, :func:`sso.design_fourbar`) and for
case files (``solver.starts``); the shipped cases set their own.
"""

MAX_ITERATIONS = 1_000_000
"""Most iterations a solver may be allowed per start."""

DEFAULT_MAX_ITERATIONS = 500
"""Iterations per solver and start when none is given."""

DEFAULT_SHAFT_SOLVER_TOL = 1e-12
"""Stopping tolerance of the solvers on a shaft series (its RE reaches round-off)."""

DEFAULT_FOURBAR_SOLVER_TOL = 1e-10
"""Stopping tolerance of the solvers on the four-bar design (lengths of order 1-20)."""

TRANSMISSION_BAND_DEG = (40.0, 120.0)
"""Transmission angles a four-bar should keep to over the revolution, deg (the
designer's usual band; the four-bar design's default constraint)."""

OUTPUT_FORMATS = ("json", "csv", "md", "html", "png")
"""Report files a run can write, by format name."""

SOLVER_NAMES = ("ipopt", "slsqp")
"""The solvers every design problem can run (and cross-check when both run)."""

SOLVERS = (*SOLVER_NAMES, "lm")
"""Solver names :func:`sso.optimise` accepts: the two above and ``"lm"``, the
least-squares solver of the exact model's two residuals (``sso.SOLVERS``)."""

CONVENTIONAL_PHASE_DEG = 90.0
"""Relative phase of successive joints when none is given, deg (the in-line
cancelling phasing of a planar column; see docs/model.md for non-planar ones)."""

MAX_JOINTS = 64
"""Most Hooke joints of one shaft series in a case file."""
