"""Brute-force sweeps: one parameter value at a time, many values at once.

:mod:`.sweep` runs a one-parameter diagram and :mod:`.regime` a two-parameter regime map on
the same machinery: :mod:`.job` integrates and classifies one value (:mod:`.classify`,
:mod:`.lyapunov`, :mod:`.grazing`), :mod:`.executor` spreads values over worker processes or
Dask, :mod:`.resume` saves finished chunks so an interrupted sweep resumes, and :mod:`.errors`
re-runs a sample at a tighter tolerance for the numerical error.  Nothing is imported here:
worker processes load only the modules they use.
"""
