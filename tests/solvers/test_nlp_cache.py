"""The cache of built NLPs keeps the most recently used shapes and no more."""

from __future__ import annotations

import numpy as np

from sso._limits import NLP_CACHE_SHAPES, QUADRATURE_BLOCK_SAMPLES
from sso._shafts.objective import residual_error
from sso._shafts.options import build_problem
from sso._shafts.problem import compiled_nlp
from sso._solvers.nlp import cached_nlp, cached_shapes


def test_least_recently_used_shape_is_dropped():
    builds = []

    def build(key):
        builds.append(key)
        return object()

    for index in range(NLP_CACHE_SHAPES):
        cached_nlp(("lru-test", index), lambda index=index: build(index))
    cached_nlp(("lru-test", 0), lambda: build("again"))  # 0 is now the most recent
    cached_nlp(("lru-test", "new"), lambda: build("new"))  # evicts 1, the oldest
    keys = list(cached_shapes())
    assert len(keys) == NLP_CACHE_SHAPES
    assert ("lru-test", 1) not in keys
    assert keys[-2:] == [("lru-test", 0), ("lru-test", "new")]
    assert builds == [*range(NLP_CACHE_SHAPES), "new"]


def test_mapped_blocks_give_the_written_out_sum():
    # above one block the graph maps a 64-angle block; the objective must not change
    beta_deg, phase_deg = [60.0, 45.0, 70.0], [30.0, 100.0]
    problem = build_problem(beta_deg, phase_deg, "exact", 3, (0.0, 89.0), (0.0, 180.0))
    samples = 4 * QUADRATURE_BLOCK_SAMPLES
    objective, gradient = compiled_nlp(problem, samples).objective_and_gradient(
        problem.start_rad, problem.parameters_rad)
    expected = residual_error(list(np.radians(beta_deg)), list(np.radians(phase_deg)), "exact",
                              samples)
    assert objective == np.float64(expected) or abs(objective - expected) <= 1e-14 * expected
    assert np.all(np.isfinite(gradient)) and np.any(gradient != 0.0)
