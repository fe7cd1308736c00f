"""Optimisation back-ends (IPOPT via CasADi, SciPy SLSQP), their common result and cross-check."""
