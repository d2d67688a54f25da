"""The attractor census: every attractor, its basin and how it changes over a parameter.

``bifurc.attractors(...)`` is this package called as a function (:func:`bifurc.attractors.atlas.attractors`);
its modules: ``starts`` (ensembles of starts), ``census`` (recurrence on a grid), ``identify`` (distinct
attractors), ``follow`` (global continuation), ``dataset`` (the xarray output), ``plots`` (figures).
Nothing is imported here, so a worker loads only what it uses.
"""
import sys
import types


class _CallablePackage(types.ModuleType):
    """The package, callable as :func:`bifurc.attractors.atlas.attractors`."""

    def __call__(self, *args, **kwargs):
        from .atlas import attractors
        return attractors(*args, **kwargs)


sys.modules[__name__].__class__ = _CallablePackage
