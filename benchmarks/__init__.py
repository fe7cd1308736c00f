"""Benchmarks of sso: run time against error, and a long numerical stress run.

Run them as modules from the repository root::

    python -m benchmarks.work_precision [--quick] [--out DIR]
    python -m benchmarks.best_known          # recompute best_known.json (slow)
    python -m benchmarks.stress [--out DIR]
"""
