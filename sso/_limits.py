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

One default for the API (:func:`sso.optimise` of a shaft series or a four-bar) and for
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

CROSS_CHECK_SOLVERS = ("ipopt", "slsqp")
"""The solvers every design problem can run, and the default: two independent methods
on one NLP, cross-checked when both run. ``"lm"`` is not among them: it needs the
problem as residuals, which only the exact model of a shaft series has."""

SOLVERS = (*CROSS_CHECK_SOLVERS, "lm")
"""Solver names :func:`sso.optimise` accepts: the two above and ``"lm"``, the
least-squares solver of the exact model's two residuals (``sso.SOLVERS``)."""

CONVENTIONAL_PHASE_DEG = 90.0
"""Relative phase of successive joints when none is given, deg (the in-line
cancelling phasing of a planar column; see docs/model.md for non-planar ones)."""

MAX_JOINTS = 64
"""Most Hooke joints of one shaft series in a case file."""

RESIDUAL_RESOLUTION: float = ROUND_OFF_FLOOR**0.5
"""How far a rounding of a chain's angles may move its two residuals ``r``
(``RE = |r|^2``), whatever its phases: 3.2e-8 absolute and 3.2e-8 of ``|r|``, so that
float64 resolves RE to the round-off floor near zero and sqrt(RE), the rms
speed-ratio error, to 3.2e-8 (docs/model.md, "Numerical limits").

Rounding each of the chain's ``2 n - 1`` angles by :data:`ANGLE_SPACING_RAD` moves
``r`` by at most ``(2 n - 1) ANGLE_SPACING_RAD / sqrt(2 prod cos beta)`` plus
``|r| (ANGLE_SPACING_RAD / 2) sum tan beta``. Operating angles, or upper bounds on free
ones, with either term above this are refused naming the field
(``sso._validation.check_chain_conditioning``): equal angles are allowed up to 89.9786
deg for 4 joints, 80.37 deg for 16 and 48.05 deg for 64. One phasing attains a
(2 n - 1)-th of the first term, so float64 stops resolving RE no later than 83.74 deg
for 16 joints and 54.93 deg for 64 (tests/test_numerical_limits.py checks both in
mpmath)."""

ANGLE_SPACING_RAD = 2.0**-50
"""Spacing of floats from 4 to 8 rad (8.9e-16 rad): one rounding of a phase up to
360 deg, or of its round trip through degrees, moves it by at most this much (an
operating angle, below pi / 2, by a quarter of it)."""

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
"""Largest case or sweep file read, bytes (1 MB); larger files, and paths that are
not regular files (FIFOs, devices, folders), are refused unread."""

MAX_RESULT_FILE_BYTES = 100_000_000
"""Largest saved result (``result.json``) read back, bytes (100 MB): sso reads back
what it writes, and the result of a column case with positions, tolerances and a
steering feel holds about 2 MB of the curves its report draws."""

DEFAULT_MEMORY_LIMIT_MB = 4096.0
"""Memory a tolerance study, sweep or multi-start run may be estimated to need, MB.

Suits a laptop of 8 GB. Work estimated above it is refused before it starts, with
the estimate and how to lower it. Raise it per call (``memory_limit_mb=``), per
command (``--memory-limit``) or per session (environment ``SSO_MEMORY_LIMIT_MB``).
"""

MEMORY_LIMIT_VARIABLE = "SSO_MEMORY_LIMIT_MB"
"""Environment variable that replaces :data:`DEFAULT_MEMORY_LIMIT_MB`."""

DEFAULT_SEED = 20251122
"""Seed of the space-filling starts when none is given: the API and case files alike."""

DEFAULT_COLUMN_SEED = 0
"""Seed of the starts of the column's optimisers (phasing, joint centres, positions,
tolerances, on-centre) in the Python API. Where a continuum of phasings cancels, the
seed picks the one reported, and the documented examples show seed 0's; it is to
become :data:`DEFAULT_SEED`, with those examples, in one step (column case files
already use that)."""

DEFAULT_WINDOW_DEG = 30.0
"""Half-width of the on-centre and lock windows of the steering feel, deg."""

DEFAULT_ON_CENTRE_WEIGHT = 10.0
"""Weight of the on-centre variance in the on-centre phasing's objective."""

DEFAULT_JOINT_BETA_BOUNDS_DEG = (1.0, 45.0)
"""Bounds on every operating angle while joint centres move in their boxes, deg
(positive below: a straight joint has no bend plane)."""

DEFAULT_SHORTEST_SHAFT_FRACTION = 0.5
"""While joint centres move, each shaft may shrink to this fraction of its given
length (away from zero length, where its direction is undefined); no upper bound."""

DEFAULT_COLUMN_STARTS = 4
"""Starts per solver of the column's shared-phasing problems (positions, tolerances,
on-centre), besides the starts each adds of its own; column case files too."""

DEFAULT_COLUMN_SOLVER_TOL = 1e-13
"""Stopping tolerance of the solvers on the column's shared-phasing problems."""

DEFAULT_LOCK_DEG = 540.0
"""Steering-wheel angle from straight ahead to each lock when none is given, deg."""

DEFAULT_STRAIGHT_AHEAD_DEG = 0.0
"""Input angle at straight ahead when none is given, deg (from the first bend plane's
normal)."""

DEFAULT_ON_CENTRE_DEG = DEFAULT_WINDOW_DEG
"""Half-width of the on-centre range of the steering figures, deg."""

DEFAULT_TOLERANCE_SAMPLES = 200
"""Built columns in the seeded sample of a column's tolerances."""

DEFAULT_COLUMN_STUDY_SAMPLES = 10_000
"""Built columns of a column's Monte Carlo tolerance study (``sso tolerance``) when
neither the command nor the case's ``[tolerances]`` gives a count."""
MAX_COLUMN_SAMPLES = 2_000_000
"""Most built columns of a column's tolerance study (its hardpoint draws take 8 (3 n + 6)
bytes each), and of the sample a case run judges its yield on
(``[tolerances] yield_samples``)."""

DEFAULT_HARDPOINT_TOLERANCE_MM = 0.5
"""Standard deviation of every hardpoint coordinate in ``sso tolerance`` of a column case
without ``[tolerances]``, mm: sso's default, not a published figure."""

DEFAULT_YOKE_PHASE_TOLERANCE_DEG = 1.0
"""Standard deviation of each yoke phasing in ``sso tolerance`` of a column case without
``[tolerances]``, deg (spline backlash and assembly): sso's default, not a published
figure."""

DEFAULT_MAX_OPERATING_ANGLE_DEG = 35.0
"""The maker's limit on a joint's operating angle when none is given, deg."""

SPLINE_ENUMERATION_LIMIT = 200_000
"""Most spline-tooth assemblies the best-teeth search enumerates before it branches
and bounds instead."""

DEFAULT_OPTION = 3
"""Which angles of a shaft series are free when none is said: 3, operating angles and
phases (1: phases, 2: operating angles)."""

DEFAULT_BETA_BOUNDS_DEG = (0.0, 40.0)
"""Bounds on a shaft series' free operating angles when none are given, deg."""

DEFAULT_PHASE_BOUNDS_DEG = (0.0, 180.0)
"""Bounds on a shaft series' free phases when none are given, deg (one period)."""

DEFAULT_SPLINE_TEETH = 36
"""Spline teeth per intermediate shaft when none are given (a common steering spline)."""

DEFAULT_PHASE_ERROR_SPAN_DEG = 10.0
"""Half-width of the yoke-phasing errors of the RE-against-error figure, deg."""

DEFAULT_PHASE_ERROR_POINTS = 201
"""Errors per curve of the RE-against-error figure."""

CSV_DIGITS = 17
"""Significant digits of floats in a mechanism table's own CSV (17 round-trip exactly;
reports show :data:`REPORT_DIGITS`)."""

DEFAULT_QUADRATURE_RTOL = 1e-10
"""Relative tolerance of the paper model's residual-error quadrature."""

DEFAULT_QUADRATURE_ATOL = 1e-16
"""Absolute tolerance of the paper model's residual-error quadrature."""

DEFAULT_OBJECTIVE_RTOL = 1e-6
"""Two solvers agree when their objectives differ by at most this fraction (plus
:data:`DEFAULT_OBJECTIVE_ATOL`)."""

DEFAULT_OBJECTIVE_ATOL = 1e-14
"""Objectives closer than this agree whatever their size (round-off near zero)."""

DEFAULT_KKT_TOLERANCE = 1e-6
"""Largest first-order optimality measure of an answer the cross-check accepts."""

DEFAULT_CHUNK_SAMPLES = 20_000
"""Samples a tolerance study evaluates per task, in one numpy call."""

NO_WORKER_TIMEOUT_S = 60.0
"""How long a sweep or tolerance study on a Dask cluster waits with no worker
connected, s, before it stops (exit 1, with what to do): the rows done so far are
on disk, and ``--resume`` completes the sweep once workers are back. A worker that
restarts (its nanny) reconnects within seconds; a cluster whose last worker is gone
for a minute is not coming back by itself. Environment variable
``SSO_NO_WORKER_TIMEOUT_S`` replaces it."""

NO_WORKER_TIMEOUT_VARIABLE = "SSO_NO_WORKER_TIMEOUT_S"
"""Environment variable that replaces :data:`NO_WORKER_TIMEOUT_S`."""

DEFAULT_PLAN_ANGLE_DEG = 0.0
"""A driveline's gearbox or pinion plan-view angle when the fitter measured none, deg:
the shaft's line in plan view straight along the vehicle's x axis."""
