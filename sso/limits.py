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

BATCH_SCREEN_STARTS = 64
"""Starts left after the user's start from which the least-squares screening of a
multi-start run solves them in one batch (numpy arrays) rather than one after another.
It does so only when the user's start stops above zero: where zero is reachable the
first start usually reaches it and ends the screening. Measured on the paper's option 1
(three joints, no zero to reach): the batch alone was 3x to 10x slower than one by one
at 8 to 32 starts and 1.1x faster at 64; the shipped rule is 1.08x faster at 128
starts and 2.1x at 512, with the same RE, since each run's iterations are compiled
(1.6x and 2.9x before; ``benchmarks/batch_throughput.py``, "Screening")."""

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

ROUND_OFF_FLOOR = 1e-15
"""Magnitudes at or below this are not data: reports and summaries print them as
``"< 1e-15"`` and plots draw them at this floor. An RE of 1e-15 is an rms speed-ratio
error of about 3e-8; a design a thousandth of a degree off a cancelling optimum
already has RE near 1e-10, so differences below the floor only say where the solver
stopped and how the floating-point sums rounded (1e-31 and 1e-26 are the same
design). The floor applies to the magnitude of every number in summaries and in
Markdown and HTML reports; CSV cells stay numbers (six digits) so that programs can
read them, and ``result.json`` keeps the full value."""

REPORT_DIGITS = 6
"""Significant digits of every number in report tables (CSV, Markdown, HTML) and
summaries; ``result.json`` keeps full precision."""
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

NLP_CACHE_SHAPES = 4
"""Built NLPs (CasADi graphs and their IPOPT instances) kept per thread.

Least recently used shapes are dropped beyond this count, so a long session that
varies joints, option, model or quadrature count keeps a bounded memory: a shaft
series of 6 joints costs about 25 MB (mostly IPOPT's exact Hessian), and a shape
is rebuilt in well under a second when it comes back.
"""

QUADRATURE_BLOCK_SAMPLES = 16
"""Quadrature angles written out in one block of the optimiser's graph.

A rule with more angles maps this block over the angle grid, so the size, memory
and build time of the graph (and of its exact Hessian) do not grow with the angle
count that the bounds call for; only its evaluation time does.
"""

MAX_INPUT_SPEED_RPM = 1e6
"""Largest input shaft speed, rpm (beyond any shaft; its square and the figures
derived from it stay far from floating-point overflow)."""

INPUT_MAGNITUDE_RANGE = (1e-100, 1e100)
"""A number in an input file is 0 or has a magnitude in this range: squares,
products and ratios of such numbers neither overflow nor vanish."""

MAX_INPUT_FILE_BYTES = 1_000_000
"""Largest case, sweep or result file read, bytes (1 MB); larger files, and paths
that are not regular files (FIFOs, devices, folders), are refused unread."""

DEFAULT_MEMORY_LIMIT_MB = 4096.0
"""Memory a tolerance study, sweep or multi-start run may be estimated to need, MB.

Suits a laptop of 8 GB. Work estimated above it is refused before it starts, with
the estimate and how to lower it. Raise it per call (``memory_limit_mb=``), per
command (``--memory-limit``) or per session (environment ``SSO_MEMORY_LIMIT_MB``).
"""

MEMORY_LIMIT_VARIABLE = "SSO_MEMORY_LIMIT_MB"
"""Environment variable that replaces :data:`DEFAULT_MEMORY_LIMIT_MB`."""

NO_WORKER_TIMEOUT_S = 60.0
"""How long a sweep or tolerance study on a Dask cluster waits with no worker
connected, s, before it stops (exit 1, with what to do): the rows done so far are
on disk, and ``--resume`` completes the sweep once workers are back. A worker that
restarts (its nanny) reconnects within seconds; a cluster whose last worker is gone
for a minute is not coming back by itself. Environment variable
``SSO_NO_WORKER_TIMEOUT_S`` replaces it."""

NO_WORKER_TIMEOUT_VARIABLE = "SSO_NO_WORKER_TIMEOUT_S"
"""Environment variable that replaces :data:`NO_WORKER_TIMEOUT_S`."""
