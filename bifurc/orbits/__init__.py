"""Periodic orbits and their continuation.

:mod:`.periodic` solves an orbit by Newton's method on multiple shooting, :mod:`.orbit` wraps it
into a dataset (:func:`bifurc.periodic_orbit`), :mod:`.branch` follows it in one parameter
(:func:`bifurc.continue_orbit`) through :mod:`.continuation` (the bordered system) and
:mod:`.arclength` (step control), :mod:`.special_points` detects and locates folds,
period doublings, grazings (:mod:`.grazing_orbit`) and lost impacts, and :mod:`.curves`
follows those points in two parameters.  Nothing is imported here.
"""
