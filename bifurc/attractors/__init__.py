"""The attractor census: every attractor, its basin and how it changes over parameter points.

``bifurc.attractors(problem, param, values, method=None, *, starts=None, match=None, run=None, **options)`` is this
package called as a function (:func:`bifurc.attractors.atlas.attractors`; ``help()`` and Jupyter show its real
signature); its modules: ``method`` (the Census method, the samplers of starts and the matcher), ``starts``
(ensembles of starts), ``census`` (recurrence on a grid), ``identify`` (distinct attractors), ``follow`` (global
continuation), ``atlas`` (the driver), ``dataset`` (the xarray output), ``plots`` (figures).
Nothing is imported here, so a worker loads only what it uses.
"""
import sys
import types


class _CallablePackage(types.ModuleType):
    """The package, callable as :func:`bifurc.attractors.atlas.attractors`."""

    def __call__(self, *args, **kwargs):
        from .atlas import attractors
        return attractors(*args, **kwargs)

    @property
    def __signature__(self):
        """The census' own signature (:func:`inspect.signature` reads it: ``help()``, Jupyter's Shift-Tab)."""
        import inspect

        from .atlas import attractors
        return inspect.signature(attractors)

    @property
    def __doc__(self):
        """The package's text and the census' own parameters (``help(bifurc.attractors)``, Jupyter's Shift-Tab:
        G7 of newcomer review 4); read only when asked, so importing the package stays light."""
        import inspect
        import textwrap

        from .atlas import attractors
        own = self.__dict__.get("__doc__") or ""      # the census' text as a literal block: valid reST for the docs
        return f"{own}\nCalled as a function::\n\n{textwrap.indent(inspect.getdoc(attractors), '    ')}\n"


sys.modules[__name__].__class__ = _CallablePackage
