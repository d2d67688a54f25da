"""The explorer: click a stored diagram's value and see its orbit (``bifurc explore``, ``ds.bifurc.explore()``).

Public, to drive it without a browser (its benchmark does): the pages :class:`Explorer` (a diagram),
:class:`MapExplorer`, :class:`CensusExplorer`; their computers :class:`Computer` (a diagram's click: history,
orbit, branch), :class:`MapComputer`, :class:`CensusComputer`; a zoom's :class:`Zoom` and its warm processes
:class:`Spares`. Each is imported on first use (the pages need the ``explore`` extra).
"""
from maps._lazy import lazy_exports

#: public name -> the module of ``bifurc.explore`` that defines it
_LAZY = {"Explorer": "app", "MapExplorer": "app", "CensusExplorer": "app", "Computer": "compute",
         "MapComputer": "compute", "CensusComputer": "compute", "Zoom": "compute", "Spares": "compute"}

__getattr__, __dir__ = lazy_exports(__name__, _LAZY, globals())
