"""bifurc: bifurcation analysis of the electro-vibro-impact system.

Sweeps, classification, grazing, storage, plotting and the command line, on
top of the dynamics in :mod:`maps`.

>>> import numpy as np, bifurc
>>> d = bifurc.sweep("thesis-1dof", "relay_hz", np.linspace(2, 10, 41), preset="matlab-listing")
>>> d.bifurc.plot(); d.bifurc.table(); d.bifurc.class_at(6.0)

Public modules beside the names in ``__all__``: :mod:`bifurc.attractors` (the census, callable),
:mod:`bifurc.labels` (judging records of one's own), :mod:`bifurc.studykit` (what a study or a benchmark is built
from) and :mod:`bifurc.explore` (the explorer's pages and computers).

Importing bifurc never selects a matplotlib backend; it registers the ``ds.bifurc`` accessor.
The public names are imported on first use (PEP 562), so the command line starts without
heyoka, xarray or matplotlib.
"""
from maps._lazy import lazy_exports

from ._version import __version__
from ._xarray_hook import register_accessor_with_xarray

#: public name -> the submodule that defines it, imported on first use
_LAZY = {
    "continue_orbit": "orbits.branch", "load": "storage.load", "periodic_orbit": "orbits.orbit",
    "sweep_point": "orbits.orbit", "OrbitNotFound": "orbits.periodic", "find_periodic_orbit": "orbits.periodic",
    "plot_branch": "plots.branch", "plot_curves": "plots.branch", "plot_diagram": "plots.diagram",
    "plot_time_history": "plots.history", "plot_regime_map": "plots.map", "plot_orbit": "plots.orbit",
    "regime_map": "sweeps.regime", "class_at": "report", "classification_report": "report", "sweep": "sweeps.sweep",
    "plot_basins": "attractors.plots", "plot_attractors": "attractors.plots",
    "Run": "run.where", "Diagram": "sweeps.method", "Census": "attractors.method", "Box": "attractors.method",
    "Slice": "attractors.method", "SwitchOn": "attractors.method", "Given": "attractors.method",
    "ByDistance": "attractors.method", "grid_points": "attractors.atlas", "Shooting": "orbits.method",
    "PALC": "orbits.method", "ClassCode": "labels.codes", "Status": "labels.codes", "Outcome": "labels.codes",
}

register_accessor_with_xarray()  # ds.bifurc, without importing xarray in worker processes

__all__ = ["__version__", "sweep", "load", "plot_diagram", "plot_time_history", "regime_map", "plot_regime_map",
           "classification_report", "class_at", "periodic_orbit", "continue_orbit", "plot_branch", "plot_curves", "plot_orbit",
           "sweep_point", "find_periodic_orbit", "OrbitNotFound", "attractors", "plot_basins",
           "Run", "Diagram", "Census", "Box", "Slice", "SwitchOn", "Given", "ByDistance", "grid_points",
           "Shooting", "PALC", "ClassCode", "Status", "Outcome", "plot_attractors", "labels", "studykit", "explore"]

#: the public modules: their names in ``_LAZY`` are public too (``bifurc.studykit.write_text``); nothing else in them
_MODULES = ("attractors", "labels", "studykit", "explore")


_lazy_getattr, __dir__ = lazy_exports(__name__, _LAZY, globals())


def __getattr__(name):
    if name in _MODULES:        # bifurc.attractors is callable: bifurc.attractors(scene, param, values, ...)
        import importlib
        return importlib.import_module(f".{name}", __name__)
    return _lazy_getattr(name)
