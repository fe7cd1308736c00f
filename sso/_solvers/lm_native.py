"""The ``"lm"`` rules compiled to machine code, for many designs of one shape.

The batch's numpy path (:mod:`sso._solvers.lm_batch`) runs an iteration of every design
as a few hundred array operations: near numpy's limit at a few thousand designs, and it
cannot take the Newton steps of a minimum above zero without a per-step pass of Python
over a shrinking tail. Here the iterations of :mod:`sso._solvers.lm_kernel` (the start,
Gauss-Newton, Newton, and the Newton step shifted past a negative eigenvalue, each an
SX function) are written out as C by CasADi's code generator, with a loop that runs
each design from its start to its end, Newton steps included, and compiled by the
system's C compiler (``$CC``, else ``cc``) into a shared library loaded with ctypes:
one call solves every design. ``-ffp-contract=off`` keeps each operation rounded as
CasADi's virtual machine rounds it, so a design ends where the single solve's kernels
end it, bit for bit.

Every call of a shape uses the library when it can be had, whatever ran before, so a
design's answer does not depend on the history of the process (a sweep gives the same
rows in one process, a pool or a cluster). The build (about a second for a few
variables, up to about 7 s on 2 busy cores) is kept in a cache folder
(:func:`cache_folder`) under a name that hashes the shape, the package's code, the
compiler command and the machine, written atomically: a shape is compiled once per
machine and version of the code, and each process loads it in milliseconds. Without a
compiler, where the build fails, for more than :data:`NATIVE_VARIABLES` variables, or
with
``SSO_NATIVE_LM=0`` in the environment, the numpy path runs: the same rules, whose
answers differ from these in the last digits (and, for a design that turns to Newton
steps, by the batched least squares' finish).

The single solve (:func:`sso._solvers.lm.solve`) runs a shape it has solved often in
this process through the same library, one design per call (:class:`OneDesign`), up to
:data:`sso._solvers.lm_kernel.NEWTON_KERNEL_VARIABLES` variables (11 variables, 6
joints of option 3, built in about 6 s on 2 busy cores).
"""

from __future__ import annotations

import ctypes
import hashlib
import os
import platform
import subprocess
import tempfile
from collections.abc import Callable, Hashable
from dataclasses import dataclass
from functools import cache
from importlib import metadata
from pathlib import Path
from typing import Any

import numpy as np

from sso._limits import COMPILED_CACHE_BYTES
from sso._solvers.least_squares import (
    SUCCESS_STATUSES,
    ResidualFunction,
    leave_saddles,
)
from sso._solvers.library_cache import mark_used, prune
from sso._solvers.lm_batch import BatchRun
from sso._solvers.lm_kernel import NEWTON_KERNEL_VARIABLES, iteration_functions
from sso._solvers.lm_kernel import SWITCH_VARIABLE as SWITCH_VARIABLE
from sso._solvers.lm_rules import NEWTON, NEWTON_INDEFINITE, RUNNING, SCALARS
from sso._solvers.saddle import (
    ABSOLUTE_CURVATURE,
    ON_BOUND,
    RELATIVE_CURVATURE,
    STATIONARY_START,
    ZERO_OBJECTIVE,
)

NATIVE_VARIABLES = 5
"""Shapes of at most this many free variables are compiled (3 joints of option 3, up to 6
joints of option 1, 5 of option 2). The symbolic Hessian and its Cholesky factor grow
the source with the square and the cube of the count, and the compiler's time faster:
measured on 2 busy cores, 2 to 4.5 s up to 5 variables, 5.5 s for 7 (4 joints of
option 3), 34 s for 11 (6 joints of option 3), a first call's cost no batch of a few
thousand designs repays."""

CACHE_VARIABLE = "SSO_CACHE_DIR"
"""Environment variable naming the folder of compiled libraries (see :func:`cache_folder`)."""

COMPILER_FLAGS = ("-O2", "-shared", "-fPIC", "-ffp-contract=off")
"""Flags of the build: ``-ffp-contract=off`` forbids fused multiply-adds, which would round
differently from CasADi's virtual machine (``-O2`` ran the 2,000-start benchmark 27% faster
than ``-O1`` with the same bits, for twice the build time)."""

DESIGNS_PER_CALL = 20_000
"""Designs one call of the library solves (about 0.1 s): Python sees Ctrl-C between
calls, so a batch of millions stops within a fraction of a second."""

MAX_SADDLE_ESCAPES = 3
"""Times a design that stopped on a saddle is moved downhill and solved again."""

COMPILE_TIMEOUT_S = 300.0
"""A compiler still running after this long is stopped and the numpy path kept."""

_FUNCTIONS = ("sso_lm_start", "sso_lm_gauss_newton", "sso_lm_newton", "sso_lm_shifted")
_STATUS = SCALARS.index("status")
_NFEV = SCALARS.index("nfev")
_DRIVER = """
#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef int (*sso_step_t)(const casadi_real**, casadi_real**, casadi_int*, casadi_real*, int);
typedef int (*sso_work_t)(casadi_int*, casadi_int*, casadi_int*, casadi_int*);

static void sso_step(sso_step_t step, casadi_real* state, const casadi_real* problem,
                     casadi_real* next, casadi_int state_size, const casadi_real** arg,
                     casadi_real** res, casadi_int* iw, casadi_real* w) {
  arg[0] = state;
  arg[1] = problem;
  res[0] = next;
  step(arg, res, iw, w, 0);
  memcpy(state, next, (size_t)state_size * sizeof(casadi_real));
}

/* Each design from its start (state with nfev = 0) to its end, or with
   gauss_newton_only to the end of its Gauss-Newton steps; returns 0, or 1 when memory
   ran out (no design touched). */
static int sso_lm_run(casadi_int count, const casadi_real* problems, casadi_int problem_size,
                      casadi_real* states, casadi_int state_size, casadi_int status_index,
                      int gauss_newton_only) {
  sso_work_t works[4] = {sso_lm_start_work, sso_lm_gauss_newton_work, sso_lm_newton_work,
                         sso_lm_shifted_work};
  casadi_int most[4] = {0, 0, 0, 0}, sizes[4], function, entry, design;
  for (function = 0; function < 4; ++function) {
    works[function](&sizes[0], &sizes[1], &sizes[2], &sizes[3]);
    for (entry = 0; entry < 4; ++entry)
      if (sizes[entry] > most[entry]) most[entry] = sizes[entry];
  }
  const casadi_real** arg = malloc((size_t)(most[0] + 1) * sizeof(casadi_real*));
  casadi_real** res = malloc((size_t)(most[1] + 1) * sizeof(casadi_real*));
  casadi_int* iw = malloc((size_t)(most[2] + 1) * sizeof(casadi_int));
  casadi_real* w = malloc((size_t)(most[3] + state_size + 1) * sizeof(casadi_real));
  if (!arg || !res || !iw || !w) {
    free(arg); free(res); free(iw); free(w);
    return 1;
  }
  casadi_real* next = w + most[3];
  for (design = 0; design < count; ++design) {
    casadi_real* state = states + design * state_size;
    const casadi_real* problem = problems + design * problem_size;
    sso_step(sso_lm_start, state, problem, next, state_size, arg, res, iw, w);
    for (;;) {
      casadi_real status = state[status_index];
      if (status == SSO_RUNNING) {
        sso_step(sso_lm_gauss_newton, state, problem, next, state_size, arg, res, iw, w);
      } else if (gauss_newton_only) {
        break;
      } else if (status == SSO_NEWTON) {
        sso_step(sso_lm_newton, state, problem, next, state_size, arg, res, iw, w);
      } else if (status == SSO_NEWTON_INDEFINITE) {
        state[status_index] = SSO_NEWTON;
        sso_step(sso_lm_shifted, state, problem, next, state_size, arg, res, iw, w);
        if (state[status_index] == SSO_NEWTON_INDEFINITE) break;
      } else {
        break;
      }
    }
  }
  free(arg); free(res); free(iw); free(w);
  return 0;
}

/* The measure of sso._solvers.multistart.measure_on_bounds of the exact model's closed
   form, bit for bit: CPython's complex arithmetic (a float operand taken as (value, 0),
   every product in full), sso._kinematics.hooke_matrix.residual_and_jacobian_complex's
   order of operations, then the point onto the bounds, RE, its gradient and the
   projected gradient's norm. cos and sin are called through pointers the compiler cannot
   see through, so they stay the library's own calls (never one fused sincos). */
typedef struct { double re, im; } sso_complex;
static double (*volatile sso_cos)(double) = cos;
static double (*volatile sso_sin)(double) = sin;

static sso_complex sso_c(double re, double im) {
  sso_complex z;
  z.re = re;
  z.im = im;
  return z;
}
static sso_complex sso_add(sso_complex a, sso_complex b) { return sso_c(a.re + b.re, a.im + b.im); }
static sso_complex sso_sub(sso_complex a, sso_complex b) { return sso_c(a.re - b.re, a.im - b.im); }
static sso_complex sso_mul(sso_complex a, sso_complex b) {
  return sso_c(a.re * b.re - a.im * b.im, a.re * b.im + a.im * b.re);
}
static sso_complex sso_scaled(sso_complex a, double value) { return sso_mul(a, sso_c(value, 0.0)); }

/* Whether the Hessian of RE over the variables that may move at the measured point has
   no negative curvature by the test of sso._solvers.saddle._negative_curvature before its
   eigendecomposition, bit for bit: no variable may move, an entry is not finite, or the
   Cholesky factor of the Hessian shifted by max(SSO_RELATIVE_CURVATURE x its largest
   diagonal magnitude, SSO_ABSOLUTE_CURVATURE) exists (sso._solvers.lm_rules.cholesky).
   The Hessian is sso._kinematics.hooke_matrix.residual_hessian_complex's, in its order of
   operations; a variable may move as sso._solvers.saddle._free_variables says, from the
   measure's gradient. Returns 0 when it has none, 1 when only the eigendecomposition can
   tell. */
/* (a, c) through one factor of the chain: a bend (p, q) or a turn (e^(i phi), e^(-i phi)). */
static void sso_factor(int bend, sso_complex first, sso_complex second, sso_complex* a,
                       sso_complex* c) {
  if (bend) {
    sso_complex next_a = sso_add(sso_mul(first, *a), sso_mul(second, *c));
    *c = sso_add(sso_mul(second, *a), sso_mul(first, *c));
    *a = next_a;
  } else {
    *a = sso_mul(first, *a);
    *c = sso_mul(second, *c);
  }
}

static int sso_curvature(casadi_int joints, int beta_free, int phase_free, casadi_int size,
                         const double* point, const double* fixed, const double* lower,
                         const double* upper, const double* slopes) {
  casadi_int free_index[size], free_count = 0, i, j, k, t, later;
  for (i = 0; i < size; ++i) {
    double entry = point[i], low = lower[i], high = upper[i], slope = slopes[i];
    if (!(high - low <= SSO_ON_BOUND || (entry - low <= SSO_ON_BOUND && slope > SSO_STATIONARY)
          || (high - entry <= SSO_ON_BOUND && slope < -SSO_STATIONARY)))
      free_index[free_count++] = i;
  }
  if (!free_count) return 0;
  const double* beta = beta_free ? point : fixed;
  const double* phase = beta_free && phase_free ? point + joints : phase_free ? point : fixed;
  casadi_int phase_offset = beta_free ? joints : 0, count = 2 * joints - 1;
  double cos_beta[joints], sin_beta[joints];
  for (k = 0; k < joints; ++k) {
    cos_beta[k] = sso_cos(beta[k]);
    sin_beta[k] = sso_sin(beta[k]);
  }
  /* The factors in the order they act: bends at even t, turns at odd t. */
  casadi_int variable[count];
  sso_complex first[count], second[count], before_a[count], before_c[count], after_e[count],
      after_f[count];
  double half_sine[count], half_cosine[count];
  for (k = 0; k < joints; ++k) {
    t = 2 * k;
    variable[t] = beta_free ? k : -1;
    first[t] = sso_c(0.5 + 0.5 * cos_beta[k], 0.0);
    second[t] = sso_c(0.5 - 0.5 * cos_beta[k], 0.0);
    half_sine[t] = 0.5 * sin_beta[k];
    half_cosine[t] = 0.5 * cos_beta[k];
    if (k < joints - 1) {
      sso_complex turn = sso_c(sso_cos(phase[k]), sso_sin(phase[k]));
      variable[t + 1] = phase_free ? phase_offset + k : -1;
      first[t + 1] = turn;
      second[t + 1] = sso_c(turn.re, -turn.im);
      half_sine[t + 1] = half_cosine[t + 1] = 0.0;
    }
  }
  sso_complex a = sso_c(1.0, 0.0), c = sso_c(0.0, 0.0);
  for (t = 0; t < count; ++t) {
    before_a[t] = a;
    before_c[t] = c;
    sso_factor(t % 2 == 0, first[t], second[t], &a, &c);
  }
  sso_complex final_c = c, e = sso_c(0.0, 0.0), f = sso_c(1.0, 0.0);
  for (t = count - 1; t >= 0; --t) {
    after_e[t] = e;
    after_f[t] = f;
    if (t % 2 == 0) {
      sso_complex next_e = sso_add(sso_mul(e, first[t]), sso_mul(f, second[t]));
      f = sso_add(sso_mul(e, second[t]), sso_mul(f, first[t]));
      e = next_e;
    } else {
      e = sso_mul(e, first[t]);
      f = sso_mul(f, second[t]);
    }
  }
  const sso_complex zero = sso_c(0.0, 0.0), i_unit = sso_c(0.0, 1.0),
      minus_i_unit = sso_c(-0.0, -1.0);
  sso_complex c_first[size], c_second[size][size];
  for (i = 0; i < size; ++i) {
    c_first[i] = zero;
    for (j = 0; j < size; ++j) c_second[i][j] = zero;
  }
  for (t = 0; t < count; ++t) {
    casadi_int own = variable[t];
    if (own < 0) continue;
    e = after_e[t];
    f = after_f[t];
    a = before_a[t];
    c = before_c[t];
    if (t % 2 == 0) {
      c_second[own][own] = sso_mul(sso_scaled(sso_sub(c, a), half_cosine[t]), sso_sub(e, f));
      sso_complex next_a = sso_scaled(sso_sub(c, a), half_sine[t]);
      c = sso_scaled(sso_sub(a, c), half_sine[t]);
      a = next_a;
    } else {
      sso_complex sum = sso_add(sso_mul(sso_mul(e, first[t]), a),
                                sso_mul(sso_mul(f, second[t]), c));
      c_second[own][own] = sso_c(-sum.re, -sum.im);
      a = sso_mul(sso_mul(i_unit, first[t]), a);
      c = sso_mul(sso_mul(minus_i_unit, second[t]), c);
    }
    c_first[own] = sso_add(sso_mul(e, a), sso_mul(f, c));
    for (later = t + 1; later < count; ++later) {
      casadi_int other = variable[later];
      if (other >= 0) {
        e = after_e[later];
        f = after_f[later];
        c_second[own][other] = c_second[other][own] = later % 2 == 0
            ? sso_mul(sso_scaled(sso_sub(c, a), half_sine[later]), sso_sub(e, f))
            : sso_mul(i_unit, sso_sub(sso_mul(sso_mul(e, first[later]), a),
                                      sso_mul(sso_mul(f, second[later]), c)));
      }
      sso_factor(later % 2 == 0, first[later], second[later], &a, &c);
    }
  }
  double product = 1.0;
  for (k = 0; k < joints; ++k) product *= cos_beta[k];
  double scale = sqrt(2.0 / product), log_first[size], log_second[size];
  for (i = 0; i < size; ++i) log_first[i] = log_second[i] = 0.0;
  if (beta_free)
    for (k = 0; k < joints; ++k) {
      log_first[k] = 0.5 * sin_beta[k] / cos_beta[k];
      log_second[k] = 0.5 / (cos_beta[k] * cos_beta[k]);
    }
  sso_complex rho = sso_scaled(final_c, scale), jacobian[size];
  for (i = 0; i < size; ++i)
    jacobian[i] = sso_scaled(sso_add(sso_scaled(final_c, log_first[i]), c_first[i]), scale);
  sso_complex weight = sso_scaled(sso_c(rho.re, -rho.im), 2.0 * scale);
  double hessian[size][size];
  for (i = 0; i < size; ++i)
    for (j = 0; j <= i; ++j) {
      double both = log_first[i] * log_first[j] + (i == j ? log_second[i] : 0.0);
      sso_complex curvature = sso_add(
          sso_add(sso_add(sso_scaled(final_c, both), sso_scaled(c_first[j], log_first[i])),
                  sso_scaled(c_first[i], log_first[j])),
          c_second[i][j]);
      hessian[i][j] = hessian[j][i] =
          2.0 * (jacobian[i].re * jacobian[j].re + jacobian[i].im * jacobian[j].im)
          + (weight.re * curvature.re - weight.im * curvature.im);
    }
  /* Over the free variables: finite, then the shifted Cholesky factor's pivots. */
  double largest_diagonal = 0.0, factor[free_count][free_count];
  for (i = 0; i < free_count; ++i)
    for (j = 0; j < free_count; ++j)
      if (!isfinite(hessian[free_index[i]][free_index[j]])) return 0;
  for (i = 0; i < free_count; ++i) {
    double magnitude = fabs(hessian[free_index[i]][free_index[i]]);
    if (i == 0 || magnitude > largest_diagonal) largest_diagonal = magnitude;
  }
  double shift = SSO_RELATIVE_CURVATURE * largest_diagonal;
  if (SSO_ABSOLUTE_CURVATURE > shift) shift = SSO_ABSOLUTE_CURVATURE;
  for (i = 0; i < free_count; ++i) {
    for (j = 0; j < i; ++j) {
      double total = hessian[free_index[i]][free_index[j]];
      for (k = 0; k < j; ++k) total = total - factor[i][k] * factor[j][k];
      factor[i][j] = total / factor[j][j];
    }
    double total = hessian[free_index[i]][free_index[i]] + shift;
    for (k = 0; k < i; ++k) total = total - factor[i][k] * factor[i][k];
    if (!(total > 0.0)) return 1;
    factor[i][i] = sqrt(total);
  }
  return 0;
}

static void sso_measure(casadi_int joints, int beta_free, int phase_free, casadi_int size,
                        const casadi_real* given, const casadi_real* fixed,
                        const casadi_real* lower, const casadi_real* upper,
                        int look_for_saddle, casadi_real* measure) {
  double point[size], cos_beta[joints];
  sso_complex turns[joints], before_a[joints], before_c[joints], jacobian[size];
  casadi_int k, i, last = joints - 1;
  for (i = 0; i < size; ++i) {
    double value = given[i], low = lower[i], high = upper[i];
    point[i] = value < low ? low : value > high ? high : value == value ? value
               : (low <= 0.0 && 0.0 <= high ? 0.0 : 0.0 < low ? low : high);
  }
  const double* beta = beta_free ? point : fixed;
  const double* phase = beta_free && phase_free ? point + joints : phase_free ? point : fixed;
  for (k = 0; k < joints; ++k) cos_beta[k] = sso_cos(beta[k]);
  for (k = 0; k < last; ++k) turns[k] = sso_c(sso_cos(phase[k]), sso_sin(phase[k]));
  sso_complex a = sso_c(1.0, 0.0), c = sso_c(0.0, 0.0);
  double determinant = 1.0;
  for (k = 0; k < joints; ++k) {
    double cosine = cos_beta[k];
    before_a[k] = a;
    before_c[k] = c;
    determinant *= cosine;
    double p = 0.5 + 0.5 * cosine, q = 0.5 - 0.5 * cosine;
    sso_complex next_a = sso_add(sso_scaled(a, p), sso_scaled(c, q));
    c = sso_add(sso_scaled(c, p), sso_scaled(a, q));
    a = next_a;
    if (k < last) {
      a = sso_mul(a, turns[k]);
      c = sso_mul(c, sso_c(turns[k].re, -turns[k].im));
    }
  }
  double scale = sqrt(2.0 / determinant);
  sso_complex rho = sso_scaled(c, scale);
  casadi_int phase_offset = beta_free ? joints : 0;
  sso_complex e = sso_c(1.0, 0.0), f = sso_c(0.0, 0.0);
  sso_complex minus_i_scale = sso_scaled(sso_c(-0.0, -1.0), scale);
  for (k = last; k >= 0; --k) {
    double cosine = cos_beta[k];
    if (beta_free) {
      double half_sine = 0.5 * sso_sin(beta[k]);
      jacobian[k] = sso_add(
          sso_mul(sso_scaled(sso_sub(e, f), -half_sine * scale),
                  sso_sub(before_c[k], before_a[k])),
          sso_scaled(rho, half_sine / cosine));
    }
    double p = 0.5 + 0.5 * cosine, q = 0.5 - 0.5 * cosine;
    sso_complex next_e = sso_add(sso_scaled(e, p), sso_scaled(f, q));
    f = sso_add(sso_scaled(e, q), sso_scaled(f, p));
    e = next_e;
    if (k) {
      if (phase_free)
        jacobian[phase_offset + k - 1] = sso_mul(
            minus_i_scale, sso_sub(sso_mul(e, before_c[k]), sso_mul(f, before_a[k])));
      e = sso_mul(e, sso_c(turns[k - 1].re, -turns[k - 1].im));
      f = sso_mul(f, turns[k - 1]);
    }
  }
  double r1 = 2.0 * rho.re, r2 = 2.0 * rho.im, norm = 0.0, slopes[size];
  for (i = 0; i < size; ++i) slopes[i] = r1 * jacobian[i].re + r2 * jacobian[i].im;
  for (i = 0; i < size; ++i) {
    double projected = point[i] - slopes[i];
    if (projected != projected) {
      norm = NAN;
      break;
    }
    double distance = fabs(point[i] - (projected < lower[i] ? lower[i]
                                       : projected > upper[i] ? upper[i] : projected));
    if (distance > norm) norm = distance;
  }
  for (i = 0; i < size; ++i) measure[i] = point[i];
  measure[size] = rho.re * rho.re + rho.im * rho.im;
  measure[size + 1] = norm;
  measure[size + 2] = look_for_saddle ? sso_curvature(joints, beta_free, phase_free, size, point,
                                                      fixed, lower, upper, slopes) : 1.0;
}

/* One design from its start to its end (sso_lm_solve), then into ended: where it ended
   (x, then fun, nit, nfev and status), the measure of that point (the point onto the
   bounds, RE and the projected gradient's norm there) and, where the design succeeded
   above round-off zero (sso._solvers.saddle.saddle_direction's look), 0 when the Hessian
   has no negative curvature by sso_curvature's test, else 1: 2 size + 7 entries. layout
   holds the sizes of the problem and the state, the index of the status in the state,
   and the chain's joints and option. Returns as sso_lm_solve. */
CASADI_SYMBOL_EXPORT int sso_lm_solve_measured(const casadi_int* layout,
                                               const casadi_real* problem, casadi_real* state,
                                               casadi_real* ended) {
  casadi_int problem_size = layout[0], state_size = layout[1], status_index = layout[2];
  casadi_int joints = layout[3], option = layout[4], i;
  casadi_int size = (state_size - 2 - SSO_SCALARS) / 3, scalars = 3 * size + 2;
  casadi_int fixed_size = problem_size - 2 * size - 2;
  if (sso_lm_run(1, problem, problem_size, state, state_size, status_index, 0)) return 1;
  for (i = 0; i < size; ++i) ended[i] = state[i];
  ended[size] = state[scalars + SSO_FUN];
  ended[size + 1] = state[scalars + SSO_NIT];
  ended[size + 2] = state[scalars + SSO_NFEV];
  ended[size + 3] = state[status_index];
  int look_for_saddle = state[status_index] > 0.0 && state[scalars + SSO_FUN] > SSO_ZERO_OBJECTIVE;
  sso_measure(joints, option != 1, option != 2, size, state, problem,
              problem + fixed_size, problem + fixed_size + size, look_for_saddle,
              ended + size + 4);
  return 0;
}

CASADI_SYMBOL_EXPORT int sso_lm_solve(casadi_int count, const casadi_real* problems,
                                      casadi_int problem_size, casadi_real* states,
                                      casadi_int state_size, casadi_int status_index) {
  return sso_lm_run(count, problems, problem_size, states, state_size, status_index, 0);
}

CASADI_SYMBOL_EXPORT int sso_lm_solve_gauss_newton(casadi_int count,
                                                   const casadi_real* problems,
                                                   casadi_int problem_size,
                                                   casadi_real* states,
                                                   casadi_int state_size,
                                                   casadi_int status_index) {
  return sso_lm_run(count, problems, problem_size, states, state_size, status_index, 1);
}
"""


@dataclass(frozen=True)
class NativeSolver:
    """A shape's compiled iterations: ``solve(count, problems, problem_size, states,
    state_size, status_index)`` (the library's ``sso_lm_solve``) for ``size`` variables."""

    solve: Any
    size: int
    solve_unchecked: Any = None
    """The same function without ctypes' argument conversions, for :class:`OneDesign`."""
    gauss_newton_unchecked: Any = None
    """The library's ``sso_lm_solve_gauss_newton``, the same arguments without ctypes'
    conversions: each design's start and Gauss-Newton steps only (where the kernel's blocks
    of :func:`sso._solvers.lm_kernel.run_kernel_flat` end it), for :class:`OneDesign`."""
    solve_measured: Any = None
    """The library's ``sso_lm_solve_measured``, without ctypes' conversions: one design
    solved, then measured where it ended as
    :func:`sso._solvers.multistart.measure_on_bounds` measures it, for :class:`OneDesign`."""

    @property
    def state_size(self) -> int:
        """Entries of one design's state (:func:`sso._solvers.lm_kernel.pack`)."""
        return 3 * self.size + 2 + len(SCALARS)



class OneDesign:
    """A shape's library called for one design at a time, in one thread (the single solve):
    its ctypes buffers and arguments made once, so a call costs the copy of the start and
    the problem in, the call, and the state out (for one design ctypes' conversions and
    new arrays cost more than the solve).

    Parameters
    ----------
    solver : NativeSolver
    joints, option : int
        The shape's chain length and option (1, 2 or 3), for :meth:`solve_measured`.
    """

    def __init__(self, solver: NativeSolver, joints: int, option: int) -> None:
        self.solver = solver
        size = solver.size
        self._size = size
        self._state: Any = (ctypes.c_double * solver.state_size)()
        self._ended: Any = (ctypes.c_double * (2 * size + 7))()
        self._nfev = 3 * size + 2 + _NFEV
        self._given: Any = None
        self._layout: Any = None
        self._problem: list[float] = []
        self._fixed = (ctypes.c_longlong(1), ctypes.c_longlong(solver.state_size),
                       ctypes.c_longlong(3 * size + 2 + _STATUS))
        self._shape = (joints, option)

    def solve(self, start: list[float], problem: list[float],
              gauss_newton_only: bool = False) -> list[float]:
        """One design from ``start`` to its end, as the flat state of
        :func:`sso._solvers.lm_kernel.pack` (what the compiled kernels end with); with
        ``gauss_newton_only`` to the end of its Gauss-Newton steps (what
        :func:`sso._solvers.lm_kernel.run_kernel_flat` ends with).

        ``problem`` is the flat problem of :func:`sso._solvers.lm_kernel.run_kernel_flat`:
        the fixed parameters, the lower and upper bounds, the tolerance and the iteration
        limit (of one length for a shape).

        Raises
        ------
        MemoryError
            If the library could not allocate its working memory.
        """
        given, given_size = self._load(start, problem)
        state = self._state
        count, state_size, status_index = self._fixed
        solve = (self.solver.gauss_newton_unchecked if gauss_newton_only
                 else self.solver.solve_unchecked)
        if solve(count, given, given_size, state, state_size, status_index):
            raise MemoryError("the compiled lm solver could not allocate its working memory")
        values: list[float] = state[:]
        return values

    def solve_measured(self, start: list[float], problem: list[float]
                       ) -> tuple[tuple[list[float], float, int, int, int], list[float]]:
        """One design from ``start`` to its end as :meth:`solve`, and the measure of where it
        ended, in the same call of the library: where it ended (``x``, ``fun``, ``nit``,
        ``nfev``, ``status`` as :func:`sso._solvers.lm_kernel.flat_outcome` reads them), and
        the point put onto the bounds, RE and the projected gradient's norm there, bit for
        bit what :func:`sso._solvers.multistart.measure_on_bounds` gives for the exact
        model's closed form, then, for a design that succeeded above round-off zero, 0.0
        where :func:`sso._solvers.saddle.saddle_direction` finds no negative curvature
        before its eigendecomposition (the same test on the same bits), else 1.0
        (``size + 3`` floats). The measure is of no use where the status is
        :data:`sso._solvers.lm_rules.NEWTON_INDEFINITE` (the solve goes on in Python from
        :meth:`state`).

        Raises
        ------
        MemoryError
            If the library could not allocate its working memory.
        """
        given, _ = self._load(start, problem)
        ended = self._ended
        if self.solver.solve_measured(self._layout, given, self._state, ended):
            raise MemoryError("the compiled lm solver could not allocate its working memory")
        values: list[float] = ended[:]
        size = self._size
        return ((values[:size], values[size], int(values[size + 1]), int(values[size + 2]),
                 int(values[size + 3])), values[size + 4:])

    def state(self) -> list[float]:
        """The flat state the last solve ended with (:func:`sso._solvers.lm_kernel.pack`)."""
        values: list[float] = self._state[:]
        return values

    def _load(self, start: list[float], problem: list[float]) -> tuple[Any, Any]:
        """The start into the state, the problem into its buffer (made on the first call:
        a shape's problems are of one length, and written only when it changed); that
        buffer and its length.

        Of the state only the start and a zero count of evaluations are written: a state
        whose count is zero is a start, whose other entries the library's first step
        replaces without reading them (:func:`sso._solvers.lm_kernel.iteration_functions`).
        """
        if self._given is None:
            self._given = ((ctypes.c_double * len(problem))(), ctypes.c_longlong(len(problem)))
            self._layout = (ctypes.c_longlong * 5)(len(problem), self.solver.state_size,
                                                   self._fixed[2].value, *self._shape)
        given, given_size = self._given
        state = self._state
        state[:self._size] = start
        state[self._nfev] = 0.0
        if problem != self._problem:
            given[:] = problem
            self._problem = list(problem)
        return given, given_size


_solvers: dict[Hashable, NativeSolver | None] = {}


def native_solver_of(shape: Hashable, size: int, nlp_of_shape: Callable[[], Any],
                     most_variables: int = NATIVE_VARIABLES) -> NativeSolver | None:
    """The compiled solver of ``shape`` (``size`` free variables), loaded from the cache or
    built from ``nlp_of_shape()`` on the shape's first call in this process and kept;
    None for more than ``most_variables`` variables (the batch's
    :data:`NATIVE_VARIABLES`; the single solve's
    :data:`sso._solvers.lm_kernel.NEWTON_KERNEL_VARIABLES`), where it cannot be had
    (tried once) or with ``SSO_NATIVE_LM=0``."""
    if size > most_variables or os.environ.get(SWITCH_VARIABLE, "1").strip() == "0":
        return None
    if shape not in _solvers:
        _solvers[shape] = _load_or_build(shape, size, nlp_of_shape)
    return _solvers[shape]


def cache_folder() -> Path:
    """Where compiled libraries are kept: ``$SSO_CACHE_DIR``, else ``$XDG_CACHE_HOME/sso``,
    else ``~/.cache/sso``."""
    given = os.environ.get(CACHE_VARIABLE)
    if given:
        return Path(given)
    base = os.environ.get("XDG_CACHE_HOME")
    return (Path(base) if base else Path.home() / ".cache") / "sso"


def build_native_solver(nlp: Any) -> NativeSolver | None:
    """The NLP's compiled solver, loaded from the cache or built there; None where the NLP
    has no residuals or more than :data:`NATIVE_VARIABLES` variables, or the compiler is
    missing or fails."""
    size = int(nlp.symbols["x"].numel()) if nlp.residuals is not None else 0
    return _load_or_build(nlp.name, size, lambda: nlp) if size <= NATIVE_VARIABLES else None


def _load_or_build(shape: Hashable, size: int, nlp_of_shape: Callable[[], Any]
                   ) -> NativeSolver | None:
    """The library of ``shape`` from the cache, else compiled into it from the source of
    ``nlp_of_shape()`` (or privately where the cache cannot be written); None where it
    cannot be had.

    Its name hashes the shape, the code that makes its source (every module of the
    package, :func:`_code_fingerprint`), the compiler command and the machine: a load
    from the cache needs neither the NLP nor the source.
    """
    if not 0 < size <= NEWTON_KERNEL_VARIABLES:
        return None
    command = [os.environ.get("CC") or "cc", *COMPILER_FLAGS]
    key = hashlib.sha256("\0".join([repr(shape), str(size), _code_fingerprint(), *command,
                                     platform.machine()]).encode())
    name = f"sso-lm-{key.hexdigest()[:32]}.so"
    source = cache(lambda: _source(nlp_of_shape()))  # made once, and only for a build
    try:
        library = cache_folder() / name
        if library.is_file():
            mark_used(library)
        else:
            _compile(source(), command, library)
            prune(library.parent, library, COMPILED_CACHE_BYTES)
        loaded = ctypes.CDLL(str(library))
    except (OSError, subprocess.SubprocessError):
        try:  # no cache folder to write: a private build for this process
            with tempfile.TemporaryDirectory(prefix="sso-lm-native-") as folder:
                library = Path(folder) / name
                _compile(source(), command, library)
                loaded = ctypes.CDLL(str(library))
        except (OSError, subprocess.SubprocessError):
            return None
    solve = loaded.sso_lm_solve
    solve.restype = ctypes.c_int
    solve.argtypes = [ctypes.c_longlong, ctypes.c_void_p, ctypes.c_longlong, ctypes.c_void_p,
                      ctypes.c_longlong, ctypes.c_longlong]
    # second function objects, without argtypes
    unchecked, gauss_newton = loaded["sso_lm_solve"], loaded["sso_lm_solve_gauss_newton"]
    measured = loaded["sso_lm_solve_measured"]
    unchecked.restype = gauss_newton.restype = measured.restype = ctypes.c_int
    return NativeSolver(solve, size, unchecked, gauss_newton, measured)


@cache
def _code_fingerprint() -> str:
    """A hash of every module of the package and of CasADi's version: any change to the
    code that writes a library's source names a new library."""
    package = Path(__file__).resolve().parent.parent
    digest = hashlib.sha256(metadata.version("casadi").encode())
    for path in sorted(package.rglob("*.py")):
        digest.update(path.relative_to(package).as_posix().encode())
        digest.update(path.read_bytes())
    return digest.hexdigest()


def _source(nlp: Any) -> str:
    """The C source of the NLP's iterations and the loop over designs."""
    import casadi

    symbols = (nlp.symbols["x"], nlp.symbols["p"], nlp.residuals)
    start, gauss_newton = iteration_functions(*symbols, mode="gauss_newton")
    newton = iteration_functions(*symbols, mode="newton")[1]
    shifted = iteration_functions(*symbols, mode="shifted")[1]
    generator = casadi.CodeGenerator("sso_lm_native.c", {"with_header": False})
    for name, function in zip(_FUNCTIONS, (start, gauss_newton, newton, shifted), strict=True):
        inputs = function.sx_in()
        generator.add(casadi.Function(name, inputs, function.call(inputs), {"cse": True}))
    statuses = (f"#define SSO_RUNNING {RUNNING}\n#define SSO_NEWTON {NEWTON}\n"
                f"#define SSO_NEWTON_INDEFINITE {NEWTON_INDEFINITE}\n"
                f"#define SSO_SCALARS {len(SCALARS)}\n#define SSO_FUN {SCALARS.index('fun')}\n"
                f"#define SSO_NIT {SCALARS.index('nit')}\n#define SSO_NFEV {_NFEV}\n"
                f"#define SSO_ZERO_OBJECTIVE {ZERO_OBJECTIVE!r}\n"
                f"#define SSO_ON_BOUND {ON_BOUND!r}\n"
                f"#define SSO_STATIONARY {STATIONARY_START!r}\n"
                f"#define SSO_RELATIVE_CURVATURE {RELATIVE_CURVATURE!r}\n"
                f"#define SSO_ABSOLUTE_CURVATURE {ABSOLUTE_CURVATURE!r}\n")
    return str(generator.dump()) + statuses + _DRIVER


def _compile(source: str, command: list[str], library: Path) -> None:
    """Compile ``source`` into ``library``, written atomically (a partial library is never
    seen under its name, and processes building it at once each replace it whole).

    Raises
    ------
    OSError, subprocess.SubprocessError
        If the folder cannot be written or the compiler is missing, fails or times out.
    """
    library.parent.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(prefix="sso-lm-native-") as folder:
        source_file = Path(folder) / "sso_lm_native.c"
        source_file.write_text(source)
        descriptor, partial = tempfile.mkstemp(dir=library.parent, prefix=".building-",
                                               suffix=".so")
        os.close(descriptor)
        try:
            subprocess.run([*command, "-o", partial, str(source_file), "-lm"], check=True,
                           capture_output=True, timeout=COMPILE_TIMEOUT_S)
            os.replace(partial, library)
        finally:
            if os.path.exists(partial):
                os.remove(partial)


def solve_native(solver: NativeSolver, start: np.ndarray, parameters: np.ndarray,
                 lower: np.ndarray, upper: np.ndarray, tolerance: float,
                 max_iterations: Any) -> BatchRun | None:
    """Every design from its start to its end by the compiled rules.

    Parameters are those of :func:`sso._solvers.lm_batch.solve_batch`, except that
    ``max_iterations`` may be one limit per design. A design whose shifted Newton step
    was still indefinite (round-off beyond its rescue shifts) ends with status
    :data:`sso._solvers.lm_rules.NEWTON_INDEFINITE`. Returns None when the library could
    not allocate its working memory.
    """
    count, size = start.shape
    problems = np.empty((count, parameters.shape[1] + 2 * size + 2))
    problems[:, :parameters.shape[1]] = parameters
    problems[:, parameters.shape[1]:-1] = [*lower, *upper, tolerance]
    problems[:, -1] = max_iterations
    states = np.zeros((count, solver.state_size))
    states[:, :size] = start
    scalars = 3 * size + 2
    for first in range(0, count, DESIGNS_PER_CALL):
        part = slice(first, first + DESIGNS_PER_CALL)
        if solver.solve(len(states[part]), problems[part].ctypes.data, problems.shape[1],
                        states[part].ctypes.data, solver.state_size,
                        scalars + SCALARS.index("status")):
            return None
    residual = states[:, size:size + 2]
    jacobian = states[:, size + 2:scalars]
    gradient = 2.0 * (jacobian[:, 0::2] * residual[:, :1] + jacobian[:, 1::2] * residual[:, 1:])
    value = {name: states[:, scalars + index] for index, name in enumerate(SCALARS)}
    return BatchRun(states[:, :size].copy(), value["fun"].copy(), gradient,
                    value["nit"].astype(int), value["nfev"].astype(int),
                    value["status"].astype(int))


def solve_native_leaving_saddles(solver: NativeSolver, start: np.ndarray,
                                 parameters: np.ndarray, lower: np.ndarray,
                                 upper: np.ndarray, tolerance: float, max_iterations: int,
                                 residual_and_jacobian: ResidualFunction,
                                 zero_level: float) -> BatchRun | None:
    """:func:`solve_native`, then the designs that stopped with success on a saddle above
    ``zero_level`` moved downhill (:func:`sso._solvers.least_squares.leave_saddles`) and
    solved again from there, at most :data:`MAX_SADDLE_ESCAPES` times, as the single
    solve's second-order care does; each leg's counts add up and count against the limit.

    ``residual_and_jacobian(x, rows)`` gives the residuals of the designs ``rows``.
    """
    run = solve_native(solver, start, parameters, lower, upper, tolerance, max_iterations)
    checked = np.ones(len(start), dtype=bool)
    for _ in range(MAX_SADDLE_ESCAPES):
        if run is None:
            break
        candidates = np.flatnonzero(checked & np.isin(run.status, SUCCESS_STATUSES)
                                    & (run.fun > zero_level) & (run.nit < max_iterations))
        if candidates.size == 0:
            break
        moved, points, evaluations = leave_saddles(rows_of(residual_and_jacobian, candidates),
                                                   run.x[candidates], lower, upper)
        run.nfev[candidates] += evaluations
        rows = candidates[moved]
        if rows.size == 0:
            break
        again = solve_native(solver, points, parameters[rows], lower, upper, tolerance,
                             max_iterations - run.nit[rows])
        if again is None:
            break
        run.x[rows], run.fun[rows], run.gradient[rows] = again.x, again.fun, again.gradient
        run.status[rows] = again.status
        run.nit[rows] += again.nit
        run.nfev[rows] += again.nfev
        checked = np.isin(np.arange(len(start)), rows)
    return run


def rows_of(residual_and_jacobian: ResidualFunction, rows: np.ndarray) -> ResidualFunction:
    """``residual_and_jacobian`` of the designs ``rows``, indexed from 0."""
    def of_rows(x: np.ndarray, among: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        return residual_and_jacobian(x, rows[among])
    return of_rows
