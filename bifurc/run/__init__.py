"""Where an analysis runs: the executor (local processes or Dask) shared by every grid of parameter points.

Nothing is imported here: worker processes load only what they use.
"""
