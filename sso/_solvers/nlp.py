"""A CasADi NLP wrapped for every solver, built once per shape and cached per thread.

A design problem builds its graph once per shape (see :mod:`sso._shafts.problem`
and :mod:`sso._linkages.fourbar_swing`); fixed values enter as parameters ``p``
and the bounds as ``lbx``/``ubx``, so a new design, new bounds or a new start
reuse the same graph. Each thread gets its own cache: a CasADi function object is
never shared between threads. A cache keeps the
:data:`sso._limits.NLP_CACHE_SHAPES` most recently used shapes and drops older
ones, so memory stays bounded however many shapes a session visits.
"""

from __future__ import annotations

import threading
from collections import OrderedDict
from collections.abc import Callable, Hashable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from sso._interrupts import raised_after_native_call
from sso._limits import NLP_CACHE_SHAPES

_cache = threading.local()


@dataclass
class CompiledNLP:
    """CasADi functions of one problem shape, shared by every solver.

    Attributes
    ----------
    name : str
        Name given to the CasADi functions.
    symbols : dict
        ``{"x", "p", "f"}`` and ``"g"`` when there are constraints.
    objective_and_gradient : BufferedFunction or callable
        ``(x, p) -> (f, df/dx)`` as ``(float, numpy.ndarray)``, used by SLSQP and
        by the optimality measures: the CasADi function of ``f``, or a closed form
        given to :func:`compile_nlp`.
    objective_and_gradient_floats : callable or None
        The same numbers with the gradient as a list of floats (the measures work on
        plain floats), where the problem has them in closed form; None otherwise.
    constraints_and_jacobian : BufferedFunction or None
        ``(x, p) -> (g, dg/dx)`` as numpy arrays, when the problem has
        constraint functions.
    ipopt_solvers : dict
        ``nlpsol`` instances (each a :class:`BufferedSolver`) keyed by their option
        tuple, built on first use.
    residuals_and_jacobian : callable or None
        For a least-squares objective ``f = r1^2 + r2^2``: ``(x, p) -> (rho,
        jacobian)`` with ``RE = |rho|^2`` and one complex derivative per
        variable (lists of floats in, Python complex numbers out), used by the
        ``"lm"`` solver; None otherwise.
    residuals : casadi.SX or None
        For a least-squares objective, its two residuals as an expression of
        ``symbols["x"]`` and ``symbols["p"]``; None otherwise.
    lm_kernel : ShapeKernels or None
        The ``"lm"`` solver's rules as CasADi functions of the shape, made on its first
        run (:func:`sso._solvers.lm_kernel.kernels_of`).
    objective_hessian : callable or None
        ``(x, p) -> d2f/dx2`` as a list of lists of floats, when the problem has
        it in closed form: the ``"lm"`` solver's Newton steps and the
        second-order checks use it instead of differences of the gradient; None
        otherwise.
    nonnegative_objective : bool
        True when the objective is never negative (a sum of squares): a point at
        round-off zero is then a global minimum and needs no second-order check.
    """

    name: str
    symbols: dict[str, Any]
    objective_and_gradient: Any
    constraints_and_jacobian: Any = None
    objective_and_gradient_floats: Any = None
    ipopt_solvers: dict[tuple[tuple[str, Any], ...], BufferedSolver] = field(
        default_factory=dict)
    residuals_and_jacobian: Any = None
    objective_hessian: Any = None
    residuals: Any = None
    nonnegative_objective: bool = False
    lm_kernel: Any = None

    def ipopt(self, options: dict[str, Any]) -> BufferedSolver:
        """The IPOPT ``nlpsol`` for these options (exact Hessian), built once."""
        import casadi

        options_key = tuple(sorted(options.items()))
        solver = self.ipopt_solvers.get(options_key)
        if solver is None:
            solver = BufferedSolver(casadi.nlpsol(
                f"{self.name}_ipopt",
                "ipopt",
                self.symbols,
                {
                    "print_time": False,
                    "error_on_fail": False,
                    "ipopt": {"print_level": 0, "sb": "yes", **options},
                },
            ))
            self.ipopt_solvers[options_key] = solver
        return solver


def cached_nlp(key: Hashable, build: Callable[[], CompiledNLP]) -> CompiledNLP:
    """This thread's NLP for ``key``, built by ``build()`` when it is not cached.

    The least recently used shape is dropped when more than
    :data:`sso._limits.NLP_CACHE_SHAPES` are cached in this thread.
    """
    cache = cached_shapes()
    nlp = cache.get(key)
    if nlp is None:
        # CasADi's bindings call back into Python while a graph is built and discard
        # what a signal handler raises there: keep it and raise it after the build
        with raised_after_native_call():
            nlp = build()
        cache[key] = nlp
        if len(cache) > NLP_CACHE_SHAPES:
            while len(cache) > NLP_CACHE_SHAPES:
                cache.popitem(last=False)
            _return_freed_memory()
    else:
        cache.move_to_end(key)
    return nlp


def _return_freed_memory() -> None:
    """Hand memory freed by dropped CasADi objects back to the system (glibc only).

    Without this the C++ heap keeps the freed pages and the process's resident
    memory reflects every shape ever built, not the ones cached.
    """
    import ctypes
    import ctypes.util

    library = ctypes.util.find_library("c")
    trim = getattr(ctypes.CDLL(library), "malloc_trim", None) if library else None
    if trim is not None:
        trim(0)


def cached_shapes() -> OrderedDict[Hashable, CompiledNLP]:
    """This thread's cache of built NLPs, least recently used first."""
    cache: OrderedDict[Hashable, CompiledNLP] | None = getattr(_cache, "nlps", None)
    if cache is None:
        cache = _cache.nlps = OrderedDict()
    return cache


class BufferedFunction:
    """A CasADi function called through preallocated numpy buffers.

    A plain Python call of a CasADi function converts every argument and result
    (about 60 us each time here, more than evaluating RE itself); writing into
    buffers CasADi already points at costs a few microseconds. Not re-entrant:
    one instance per thread, as the NLP cache already is.

    Parameters
    ----------
    function : casadi.Function
        Function with dense inputs and outputs (every entry has a buffer slot).
    scalar_first : bool
        Return the first output as a float (an objective value).

    Attributes
    ----------
    buffer : casadi.FunctionBuffer
        The buffer the function is evaluated through (its ``stats()`` are those of
        the last evaluation).
    inputs, outputs : list of numpy.ndarray
        The buffers of the inputs and outputs, one flat array each (a matrix column by
        column, as CasADi stores it).
    evaluate : callable
        Evaluates the function from ``inputs`` into ``outputs`` (no arguments).
    """

    def __init__(self, function: Any, scalar_first: bool = False) -> None:
        self._function = function
        self.buffer, self.evaluate = self._function.buffer()
        self.inputs = [np.zeros(self._function.nnz_in(i)) for i in range(self._function.n_in())]
        self.outputs = [np.zeros(self._function.nnz_out(i))
                        for i in range(self._function.n_out())]
        self._shapes = [self._function.size_out(i) for i in range(self._function.n_out())]
        for index, array in enumerate(self.inputs):
            self.buffer.set_arg(index, array.data)
        for index, array in enumerate(self.outputs):
            self.buffer.set_res(index, array.data)
        self._scalar_first = scalar_first

    def __call__(self, *arguments: Any) -> tuple[Any, ...]:
        """Evaluate at ``arguments`` (array-likes); returns fresh numpy arrays."""
        for destination, value in zip(self.inputs, arguments, strict=True):
            destination[:] = np.ravel(value)
        self.evaluate()
        results: list[Any] = []
        for array, (rows, columns) in zip(self.outputs, self._shapes, strict=True):
            # CasADi stores dense matrices column by column.
            results.append(array.reshape((rows, columns), order="F").squeeze(axis=1).copy()
                           if columns == 1 else array.reshape((rows, columns), order="F").copy())
        if self._scalar_first:
            results[0] = float(results[0][0])
        return tuple(results)

    def flat(self, *arguments: list[float]) -> list[float]:
        """Evaluate at ``arguments`` (flat lists of floats); the first output as a flat list.

        The lean path for a function called in a loop on lists: no reshaping, and no
        intermediate array per input.
        """
        for destination, value in zip(self.inputs, arguments, strict=True):
            destination[:] = value
        self.evaluate()
        values: list[float] = self.outputs[0].tolist()
        return values


class BufferedSolver:
    """A CasADi solver (``nlpsol``) called through numpy buffers, by input name.

    The plain call converts the solver's eight inputs and six outputs to and from
    CasADi matrices on every solve: on a three-joint shaft series about a tenth of
    IPOPT's whole solve (0.15 of 2.0 ms of CPU time). Here they are copied into and
    out of buffers the solver already points at. Not re-entrant: one instance per
    thread, as the NLP cache already is.

    Parameters
    ----------
    solver : casadi.Function
        The ``nlpsol`` instance.
    """

    def __init__(self, solver: Any) -> None:
        function = BufferedFunction(solver)
        self._function = function
        self._names_in = frozenset(solver.name_in())
        # (name, buffer, default) of each input; every output of nlpsol is a column (x, f,
        # g and their multipliers), so its buffer is the flat vector itself.
        self._inputs = tuple((name, array, solver.default_in(index)) for index, (name, array)
                             in enumerate(zip(solver.name_in(), function.inputs, strict=True)))
        self._outputs = tuple(zip(solver.name_out(), function.outputs, strict=True))
        for _, array, default in self._inputs:
            array[:] = default
        self._given: frozenset[str] | set[str] = frozenset()
        self._totals: dict[str, Any] = {}
        self._stats: dict[str, Any] = {}

    def __call__(self, **arguments: Any) -> dict[str, np.ndarray]:
        """Solve with the given inputs (``x0``, ``p``, ``lbx``, ...; the solver's defaults
        for the others); the outputs by name (``x``, ``f``, ``lam_x``, ...) as 1-D arrays.

        Raises
        ------
        TypeError
            For an input the solver does not have.
        RuntimeError
            What CasADi raises (an ill-posed problem, such as crossed bounds).
        """
        if not self._names_in.issuperset(arguments):
            unknown = sorted(set(arguments) - self._names_in)
            raise TypeError(f"unknown solver inputs {unknown}; "
                            f"allowed: {[name for name, *_ in self._inputs]}")
        # An input left out holds its default already unless an earlier call wrote it
        # (until this call's writes are done, any of the two may have).
        previous = self._given
        self._given = previous | arguments.keys()
        for name, array, default in self._inputs:
            if name in arguments:
                array[:] = np.ravel(arguments[name])
            elif name in previous:
                array[:] = default
        self._given = frozenset(arguments)
        try:
            self._function.evaluate()
        finally:
            self._stats = self._own_stats(self._function.buffer.stats())
        return {name: array.copy() for name, array in self._outputs}

    def stats(self) -> dict[str, Any]:
        """The statistics of the last solve (``return_status``, ``iter_count``,
        ``n_call_nlp_f``, ...), as the plain call's ``stats()`` gives them."""
        return self._stats

    def _own_stats(self, cumulative: dict[str, Any]) -> dict[str, Any]:
        """The last solve's statistics from the buffer's: its function-call counts and
        times (``n_call_*``, ``t_proc_*``, ``t_wall_*``) add up over every solve of the
        buffer, where the plain call gives each solve's own; the rest is the last
        solve's."""
        totals = self._totals
        if not totals:
            totals.update((name, 0) for name in cumulative
                          if name.startswith(("n_call_", "t_proc_", "t_wall_")))
        for name, previous in totals.items():
            value = cumulative.get(name)
            if value is not None:
                totals[name] = value
                cumulative[name] = value - previous
        return cumulative


def value_and_gradient_floats(nlp: Any, x: Any, parameters: Any) -> tuple[float, list[float]]:
    """The objective at ``x`` and its gradient, a float and a list of floats: the problem's
    closed form on plain floats where it has one (``nlp.objective_and_gradient_floats``),
    else its objective-and-gradient function."""
    floats = getattr(nlp, "objective_and_gradient_floats", None)
    if floats is not None:
        value, slopes = floats(x, parameters)
        return float(value), slopes
    value, gradient = nlp.objective_and_gradient(x, parameters)
    return float(value), np.ravel(gradient).tolist()


def compile_nlp(name: str, x: Any, p: Any, objective: Any, constraints: Any = None,
                objective_and_gradient: Any = None) -> CompiledNLP:
    """Wrap CasADi symbols of an NLP into the functions the solvers use.

    Parameters
    ----------
    name : str
        Name of the CasADi functions.
    x, p : casadi.SX
        Design variables and parameters (column vectors).
    objective : casadi.SX
        Scalar objective.
    constraints : casadi.SX, optional
        Constraint functions ``g(x, p)``, bounded per solve.
    objective_and_gradient : callable, optional
        ``(x, p) -> (f, df/dx)`` as ``(float, numpy.ndarray)`` computed without
        CasADi (a closed form), used instead of a CasADi function of ``objective``;
        it must agree with ``objective``, which IPOPT still solves.
    """
    import casadi

    symbols = {"x": x, "p": p, "f": objective}
    if objective_and_gradient is None:
        objective_and_gradient = BufferedFunction(
            casadi.Function(f"{name}_f", [x, p],
                            [objective, casadi.densify(casadi.gradient(objective, x))],
                            ["x", "p"], ["f", "grad"]),
            scalar_first=True,
        )
    constraints_and_jacobian = None
    if constraints is not None:
        symbols["g"] = constraints
        constraints_and_jacobian = BufferedFunction(
            casadi.Function(f"{name}_g", [x, p],
                            [casadi.densify(constraints),
                             casadi.densify(casadi.jacobian(constraints, x))],
                            ["x", "p"], ["g", "jac"])
        )
    return CompiledNLP(name=name, symbols=symbols, objective_and_gradient=objective_and_gradient,
                       constraints_and_jacobian=constraints_and_jacobian)
