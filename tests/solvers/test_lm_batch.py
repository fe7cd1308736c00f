"""The rules run on numpy columns (many designs at once) against the same rules in plain
Python floats, one design at a time (:func:`sso._solvers.lm.minimise`).

Reference: the Python loop from the same starts and bounds. Both are the rules of
:mod:`sso._solvers.lm_rules`; here they run through different arithmetic (numpy's
array operations, Python's floats), so a design must end with the same status, the
same counts and the same point up to round-off.
"""

import numpy as np

from sso._kinematics.hooke_matrix import residual_and_jacobian_complex, residual_jacobian
from sso._solvers import lm
from sso._solvers.lm_batch import solve_batch
from sso._solvers.lm_rules import NEWTON


def _columns(point, parameters):
    # Option 3 of three joints: beta_1..3, then phi_1, phi_2 (rad).
    (first, second), d_beta, d_phase = residual_jacobian(np, point[:3], point[3:])
    derivatives = [*d_beta, *d_phase]
    return first, second, [pair[0] for pair in derivatives], [pair[1] for pair in derivatives]


def _one(x):
    return residual_and_jacobian_complex(x[:3], x[3:])


def test_many_designs_end_as_each_does_alone():
    rng = np.random.default_rng(20261125)
    count = 300
    lower = np.radians([5.0, 5.0, 5.0, 0.0, 0.0])
    upper = np.radians([35.0, 35.0, 35.0, 180.0, 180.0])
    # Starts partly outside the bounds: they are moved onto them first.
    start = np.radians(np.column_stack([rng.uniform(0.0, 40.0, (count, 3)),
                                        rng.uniform(-10.0, 190.0, (count, 2))]))
    batch = solve_batch(_columns, start, np.zeros((count, 0)), lower, upper, 1e-12, 3000)
    same = 0
    for row in range(count):
        x, fun, nit, nfev, status = lm.minimise(_one, start[row].tolist(), lower.tolist(),
                                                upper.tolist(), 1e-12, 3000)
        if batch.status[row] == NEWTON:
            # The batch leaves Newton steps to its caller; the loop went on with them.
            assert nit > batch.nit[row]
            continue
        assert (batch.status[row] > 0) == (status > 0)
        assert batch.fun[row] <= fun * (1.0 + 1e-6) + 1e-20
        assert fun <= batch.fun[row] * (1.0 + 1e-6) + 1e-20
        same += (batch.status[row], batch.nit[row], batch.nfev[row]) == (status, nit, nfev)
        if fun > 1e-20:
            np.testing.assert_allclose(batch.x[row], x, rtol=0, atol=1e-8)
        assert np.all(batch.x[row] >= lower) and np.all(batch.x[row] <= upper)
    # Round-off in the last digits may move a threshold test by an iteration.
    assert same >= 0.97 * count - np.count_nonzero(batch.status == NEWTON)
    # The gradient handed back is 2 J^T r at the final point.
    rho, jacobian = _one(batch.x[0].tolist())
    np.testing.assert_allclose(batch.gradient[0],
                               [2.0 * (rho.real * d.real + rho.imag * d.imag) for d in jacobian],
                               rtol=1e-10, atol=1e-14)
