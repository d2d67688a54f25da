"""bifurc: bifurcation analysis of the electro-vibro-impact system.

Sweeps, classification, grazing, storage, plotting and the command line, on
top of the dynamics in :mod:`maps`.

>>> import numpy as np, bifurc
>>> d = bifurc.sweep("thesis-1dof", "relay_hz", np.linspace(2, 10, 41), preset="matlab-listing")
>>> d.bifurc.plot(); d.bifurc.table(); d.bifurc.class_at(6.0)

Importing bifurc never selects a matplotlib backend; it registers the ``ds.bifurc`` accessor.
"""
from ._version import __version__
from ._xarray_hook import register_accessor_with_xarray
from .orbits.branch import continue_orbit
from .storage.load import load
from .orbits.orbit import periodic_orbit, sweep_point
from .orbits.periodic import OrbitNotFound, find_periodic_orbit
from .plots.branch import plot_branch, plot_curves
from .plots.diagram import plot_diagram
from .plots.history import plot_time_history
from .plots.map import plot_regime_map
from .plots.orbit import plot_orbit
from .sweeps.regime import regime_map
from .report import class_at, classification_report
from .sweeps.sweep import sweep

register_accessor_with_xarray()  # ds.bifurc, without importing xarray in worker processes

__all__ = ["__version__", "sweep", "load", "plot_diagram", "plot_time_history", "regime_map", "plot_regime_map",
           "classification_report", "class_at", "periodic_orbit", "continue_orbit", "plot_branch", "plot_curves", "plot_orbit",
           "sweep_point", "find_periodic_orbit", "OrbitNotFound"]
