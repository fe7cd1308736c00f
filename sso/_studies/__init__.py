"""Many cases at once: parameter sweeps and tolerance Monte Carlo studies.

Work runs in a local process pool by default, or on Dask when a
``dask.distributed.Client`` is given. Nothing here imports dask unless a client or
a scheduler address is given.
"""
